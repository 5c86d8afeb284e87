#!/usr/bin/env bash
# Install what is missing, build, and run the default test suite (tests labelled `long` are
# left out; run them with `ctest --test-dir build -L long`).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --test
bash scripts/build.sh
# The Khronos glTF validator (npm, pinned) for the export tests; they skip if it is absent.
if command -v npm >/dev/null && [[ ! -f build/_npm/node_modules/gltf-validator/package.json ]]; then
  npm install --silent --no-audit --no-fund --prefix build/_npm gltf-validator@2.0.0-dev.3.10 \
    >/dev/null 2>&1 || echo "test: warning: could not install gltf-validator from npm; its tests will skip"
fi
ctest --test-dir build --output-on-failure -LE long -j"$(nproc)" --timeout 600
