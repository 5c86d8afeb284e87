#!/usr/bin/env bash
# Builds and runs one libFuzzer target (docs/reliability.md):
#   scripts/fuzz.sh TARGET SECONDS [libFuzzer options...]
#   scripts/fuzz.sh list
# TARGET is one of the inputs below. The build is build-fuzz/ (Debian's clang, the libraries
# TARGET needs built with -fsanitize=fuzzer-no-link,address,undefined, the target linked with
# -fsanitize=fuzzer), apart from the Release build and never part of scripts/test.sh. The corpus
# build-fuzz/corpus/TARGET grows run after run; it starts from the repository's own files and
# ../shared/testdata/external/ (linked by path from build-fuzz/seeds/TARGET, never copied into the
# repository) and, when the Release binary build/tools/mopad exists, from a small scene, truth
# and scan it generates. Findings (crash-*, leak-*, timeout-*, slow-unit-*) go to
# build-fuzz/findings/TARGET/; reproduce one with build-fuzz/fuzz/TARGET_fuzz FILE.
# MOPAD_FUZZ_RUN_DIR=DIR adds the JSON files of a run folder as seeds of run_folder;
# MOPAD_FUZZ_JOBS=N builds with N jobs (default 1).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
targets=(scene_spec mission_config truth_json gltf ifc ply ptx run_folder suite_manifest)
if [[ "${1:-}" == "list" ]]; then
  printf '%s\n' "${targets[@]}"
  exit 0
fi
if [[ $# -lt 2 ]] || ! [[ "$2" =~ ^[0-9]+$ ]] || [[ " ${targets[*]} " != *" $1 "* ]]; then
  echo "usage: scripts/fuzz.sh TARGET SECONDS [libFuzzer options...]; TARGET: ${targets[*]}" >&2
  exit 2
fi
target="$1" seconds="$2"
shift 2
command -v clang++ >/dev/null || {
  echo "fuzz.sh: error: clang++ not found; install it: apt-get install --no-install-recommends clang" >&2
  exit 2
}

bf="$root/build-fuzz"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [[ ! -f "$bf/CMakeCache.txt" ]]; then
  cmake -S "$root" -B "$bf" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_COMPILER=clang++ -DMOPAD_BUILD_TESTS=OFF -DMOPAD_BUILD_FUZZERS=ON \
    -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" >/dev/null
fi
# MOPAD_FUZZ_SKIP_BUILD=1 runs the target as built (while another build uses build-fuzz/).
[[ "${MOPAD_FUZZ_SKIP_BUILD:-0}" == 1 ]] || cmake --build "$bf" --target "${target}_fuzz" -j"${MOPAD_FUZZ_JOBS:-1}"

# Seeds: links to files by path, per target.
seeds="$bf/seeds/$target"
rm -rf "$seeds"
mkdir -p "$seeds" "$bf/corpus/$target" "$bf/findings/$target"
ext="$root/../shared/testdata/external"
[[ -d "$ext" ]] || ext="/work/shared/testdata/external"
gen="$bf/seeds/generated"
mopad="$root/build/tools/mopad"
if [[ -x "$mopad" && ! -f "$gen/done" ]]; then
  rm -rf "$gen"
  mkdir -p "$gen"
  "$mopad" scene generate "$root/scenes/two_rooms_door.yaml" -o "$gen/scene" >/dev/null
  "$mopad" scan "$gen/scene" --pose 2,2,0,0 --step-deg 4 -o "$gen/scan.ply" --ptx "$gen/scan.ptx" \
    --truth "$gen/scan.truth.ply" >/dev/null
  touch "$gen/done"
fi
add() {  # add FILE...: links each existing file into the seed folder
  local f
  for f in "$@"; do
    [[ -f "$f" ]] || continue
    ln -sf "$(realpath "$f")" "$seeds/$(echo "$f" | md5sum | cut -c1-12)_$(basename "$f")"
  done
}
shopt -s nullglob globstar
mapfile -t repo_yaml < <(git -C "$root" ls-files '*.yaml' | sed "s|^|$root/|")
case "$target" in
  scene_spec) add "$root"/scenes/*.yaml "$gen"/scene/spec.effective.yaml ;;
  mission_config | suite_manifest) add "${repo_yaml[@]}" ;;
  truth_json) add "$gen"/scene/scene.truth.json "$ext"/**/*.json ;;
  gltf) add "$ext"/**/*.gltf "$ext"/**/*.glb "$gen"/scene/scene.glb ;;
  ifc) add "$ext"/**/*.ifc ;;
  ply) add "$gen"/*.ply ;;
  ptx) add "$gen"/*.ptx ;;
  run_folder)
    add "$gen"/scene/scene.truth.json
    [[ -n "${MOPAD_FUZZ_RUN_DIR:-}" ]] && add "$MOPAD_FUZZ_RUN_DIR"/**/*.json
    ;;
esac
echo "fuzz.sh: $target for $seconds s; seeds $(ls "$seeds" | wc -l), corpus $(ls "$bf/corpus/$target" | wc -l)"
cd "$bf/findings/$target"
# Inputs are at most 1 MB (-max_len): longer seeds (the external IFC files) are cut, which is
# one more hostile input.
exec "$bf/fuzz/${target}_fuzz" "$bf/corpus/$target" "$seeds" -max_total_time="$seconds" \
  -timeout=20 -rss_limit_mb=4096 -max_len=1048576 -print_final_stats=1 \
  -artifact_prefix="$bf/findings/$target/" "$@"
