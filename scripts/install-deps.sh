#!/usr/bin/env bash
# Installs the Debian 12 packages OpenMoPAD needs, skipping those already present (idempotent).
#   scripts/install-deps.sh          build + run dependencies
#   scripts/install-deps.sh --test   also what the test suite uses (GoogleTest; Node.js and the
#                                    npm test oracles of tests/oracles/package.json — the Khronos
#                                    glTF validator, web-ifc, copc — installed into build/_npm;
#                                    Debian's chromium for the report's 3D-view test; Slurm
#                                    and munge for the `slurm` tests; python3-pytest
#                                    for the Python module's tests)
#   scripts/install-deps.sh --fuzz   also Debian's clang for the libFuzzer targets of fuzz/
#                                    (scripts/fuzz.sh; not needed to build or test)
# Runs as root (or through sudo when available). Nothing is downloaded outside Debian and npm.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config ca-certificates
  libeigen3-dev libembree-dev libbullet-dev libopencv-dev libompl-dev liboctomap-dev
  libtinygltf-dev libassimp-dev libyaml-cpp-dev libtbb-dev libcli11-dev libspdlog-dev
  nlohmann-json3-dev libnanoflann-dev libgtest-dev
  # Images (io/image_codec.h): PNG and JPEG without OpenCV's imgcodecs, which would load GDAL,
  # GDCM, HDF5 and PROJ into every process.
  libpng-dev libjpeg62-turbo-dev
  libjs-three  # three.js r111, inlined into report.html's 3D view (report/report_viewer.h)
  # IfcPlusPlus (IFC4 reader, carve tessellation: scenes/ifc4_loader.h); its headers include
  # Boost headers the package does not declare.
  libifcplusplus-dev libboost-dev
  # The Python module `import mopad` (python/, docs/python.md), built with the project.
  pybind11-dev python3-dev python3-numpy
)
with_tests=0 with_fuzz=0
for arg in "$@"; do
  case "$arg" in
    --test) with_tests=1 ;;
    --fuzz) with_fuzz=1 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if (( with_tests )) && ! command -v node >/dev/null 2>&1; then
  missing+=(nodejs npm)
fi
# pytest: the Python module's and loader's tests (python/).
if (( with_tests )); then
  for p in python3-pytest; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
fi
# Universal Ctags: function extents for scripts/check-code-size.sh (a test of the suite).
if (( with_tests )) && ! dpkg-query -W -f='${Status}' universal-ctags 2>/dev/null | grep -q "install ok installed"; then
  missing+=(universal-ctags)
fi
# A single-node Slurm (slurmctld, slurmd, the clients) and munge, its authentication: the `slurm`
# tests start one with scripts/slurm-local.sh (no systemd; they skip without it).
if (( with_tests )); then
  for p in slurm-wlm slurmctld slurmd slurm-client munge; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
fi

# Fuzzing (optional): clang 14 ships libFuzzer and the sanitizer runtimes (scripts/fuzz.sh).
if (( with_fuzz )) && ! dpkg-query -W -f='${Status}' clang 2>/dev/null | grep -q "install ok installed"; then
  missing+=(clang)
fi

if (( ${#missing[@]} )); then
  echo "install-deps: installing ${missing[*]}"
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then
    command -v sudo >/dev/null || { echo "install-deps: error: need root or sudo to install ${missing[*]}" >&2; exit 1; }
    SUDO=sudo
  fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  echo "install-deps: all Debian packages present"
fi

# Headless Chromium for the report's 3D-view test (best effort: its test skips when absent).
if (( with_tests )) && ! command -v chromium >/dev/null 2>&1; then
  SUDO=""
  [[ $(id -u) -ne 0 ]] && command -v sudo >/dev/null && SUDO=sudo
  if $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      chromium >/dev/null 2>&1; then
    echo "install-deps: chromium installed"
  else
    echo "install-deps: warning: could not install chromium; the report's 3D-view test will skip"
  fi
fi

# The npm test oracles (independent readers of the exports); their tests skip when absent.
if (( with_tests )) && command -v npm >/dev/null 2>&1; then
  root="$(cd "$(dirname "$0")/.." && pwd)"
  mkdir -p "$root/build/_npm"
  cp "$root/tests/oracles/package.json" "$root/build/_npm/package.json"
  if npm install --silent --no-audit --no-fund --prefix "$root/build/_npm" >/dev/null 2>&1; then
    echo "install-deps: npm test oracles in build/_npm"
  else
    echo "install-deps: warning: could not install the npm test oracles; their tests will skip"
  fi
fi
