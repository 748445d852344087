#!/usr/bin/env bash
# Times one sweep computed in every way plumetrace can split it: one process (1 and 2 threads),
# mpirun with 1, 2 and 3 (oversubscribed) ranks, and two shards run side by side plus the merge.
# Usage: scripts/bench_ranks.sh [SWEEP.toml] [RUNS]   (default: set G with 400 runs per value)
set -euo pipefail
cd "$(dirname "$0")/.."
sweep=${1:-studies/lochmatter2008/sets/G.toml}
runs=${2:-400}
P=build/plumetrace
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# why: Open MPI refuses root unless told (containers); shared memory only; no binding to cores
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader \
  OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_pml=ob1
mpi=(mpirun --oversubscribe --bind-to none)

# prints "LABEL: W s wall, R runs/s" for a command
timed() {
  local label=$1
  shift
  local start end
  start=$(date +%s.%N)
  "$@" >/dev/null
  end=$(date +%s.%N)
  /usr/bin/python3 -c "import sys; w = $end - $start; print(f'{sys.argv[1]:<34} {w:6.2f} s wall  {sys.argv[2] and int(sys.argv[2]) / w:7.1f} runs/s')" \
    "$label" "$total"
}

total=$($P sweep "$sweep" --runs 1 --quiet --store "$work/count.sqlite" --out "$work/count" |
  /usr/bin/python3 -c "import sys, re; print(int(re.search(r'^(\d+) runs', sys.stdin.read(), re.M).group(1)) * $runs)")
echo "sweep $sweep, $runs runs per value: $total runs on $(nproc) cores"
common=(sweep "$sweep" --runs "$runs" --quiet)
timed "1 process, 1 thread" $P "${common[@]}" --threads 1 --store "$work/a.sqlite" --out "$work/a"
timed "1 process, 2 threads" $P "${common[@]}" --threads 2 --store "$work/b.sqlite" --out "$work/b"
timed "mpirun -n 1" "${mpi[@]}" -n 1 $P "${common[@]}" --store "$work/c.sqlite" --out "$work/c"
timed "mpirun -n 2 (1 thread per rank)" "${mpi[@]}" -n 2 $P "${common[@]}" --store "$work/d.sqlite" \
  --out "$work/d"
timed "mpirun -n 3 --oversubscribe" "${mpi[@]}" -n 3 $P "${common[@]}" --store "$work/e.sqlite" \
  --out "$work/e"
shards() {
  $P "${common[@]}" --threads 1 --shard 1/2 --store "$work/p1.sqlite" &
  $P "${common[@]}" --threads 1 --shard 2/2 --store "$work/p2.sqlite"
  wait
  $P merge "$work/p1.sqlite" "$work/p2.sqlite" --store "$work/f.sqlite"
}
timed "2 shards side by side + merge" shards
for x in c d e; do cmp -s "$work/a/runs.csv" "$work/$x/runs.csv" || echo "runs.csv of $x differs!"; done
$P export "$sweep" --runs "$runs" --store "$work/f.sqlite" --out "$work/f"
cmp -s "$work/a/runs.csv" "$work/f/runs.csv" || echo "runs.csv of the merged shards differs!"
echo "every runs.csv compared equal to the single process's"
