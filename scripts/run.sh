#!/usr/bin/env bash
# The main job: install, build, then reproduce the paper's nine experiment sets (4050 runs per
# reading, five readings, plus 600 for the sensitivity section) and write the report to
# out/report.html. Extra arguments go to `plumetrace reproduce` (e.g. --runs 10, --out DIR,
# --preset calibrated, --presets none).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
./build/plumetrace reproduce "$@"
