#!/usr/bin/env bash
# The main job: install, build, then one default run of each algorithm on the paper's setup.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
for algorithm in casting surge-spiral surge-cast; do
  ./build/plumetrace run scenarios/lochmatter2008.toml --algorithm "$algorithm" "$@"
  echo
done
