#!/usr/bin/env bash
# Install what is missing, build, and run the default test suite (tests labelled `long` are
# left out; run them with `ctest --test-dir build -L long`).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --test
bash scripts/build.sh
# install-deps.sh --test put the npm oracles (glTF validator, web-ifc, copc) in build/_npm.
ctest --test-dir build --output-on-failure -LE long -j"$(nproc)" --timeout 600
