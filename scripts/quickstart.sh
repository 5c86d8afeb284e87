#!/usr/bin/env bash
# The main job: install what is missing, build, and run `mopad run` on the embedded default
# scene (office_5rooms). Results and report go to ./out/quickstart (override with $1).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
out="${1:-out/quickstart}"
./build/tools/mopad run -o "$out"
echo "quickstart: results in $out (open $out/report.html)"
