#!/usr/bin/env bash
# Times the full `plumetrace reproduce` from an empty output folder and prints runs per second.
# Usage: scripts/bench_reproduce.sh [extra reproduce arguments, e.g. --threads 1]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh >/dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
start=$(date +%s.%N)
./build/plumetrace reproduce --out "$out" --quiet "$@" >/dev/null
end=$(date +%s.%N)
runs=$(/usr/bin/python3 -c "import json,sys; print(json.load(open('$out/summary.json'))['total_runs'])")
/usr/bin/python3 - "$start" "$end" "$runs" <<'PY'
import sys
start, end, runs = float(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3])
wall = end - start
print(f"reproduce: {runs} runs in {wall:.1f} s wall ({runs / wall:.1f} runs/s), report included")
PY
