#!/bin/bash
# examples/zigzag: a controller registered outside the library is a controller of the plumetrace
# command like the built-ins: its keys in config, run, sweep and error messages; and a binary
# that does not register it knows nothing of it.
# Usage: example_zigzag_test.sh EXAMPLE_ZIGZAG PLUMETRACE
set -u
zigzag=$1
plumetrace=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0
fail() {
  echo "FAIL: $*"
  failed=1
}

# config: the built-in keys as plumetrace has them, then the [zigzag] table with its help
"$zigzag" config >"$tmp/zigzag.toml" || fail "config exited $?"
"$plumetrace" config >"$tmp/plumetrace.toml" || fail "plumetrace config exited $?"
grep -qx 'leg = 1.0  # path length of each leg of the zigzag (m)' "$tmp/zigzag.toml" ||
  fail "config does not list zigzag.leg with its help"
grep -qx '\[zigzag\]' "$tmp/zigzag.toml" || fail "config has no [zigzag] table"
head -c "$(wc -c <"$tmp/plumetrace.toml")" "$tmp/zigzag.toml" | cmp -s - "$tmp/plumetrace.toml" ||
  fail "the built-in keys differ from plumetrace config"
grep -q zigzag "$tmp/plumetrace.toml" && fail "plumetrace config knows zigzag"
"$zigzag" run --help | grep -q "hayes or zigzag" || fail "--algorithm help does not list zigzag"

# run: chosen by controller.algorithm, its key set by --set, the resolved config has it
"$zigzag" run --set controller.algorithm=zigzag --set zigzag.leg=0.8 --set supervisor.timeout=60 \
  --json >"$tmp/run.json" || fail "run exited $?"
grep -q '"zigzag"' "$tmp/run.json" || fail "run output does not name zigzag"
"$zigzag" config --algorithm zigzag --set zigzag.leg=0.8 | grep -qx 'leg = 0.8  # .*' ||
  fail "zigzag.leg=0.8 is not in the resolved config"

# a bad value names the key and its range, exit code 2; an unknown key lists the table's keys
"$zigzag" run --algorithm zigzag --set zigzag.leg=-1 2>"$tmp/err" >/dev/null
rc=$?
[ "$rc" -eq 2 ] || fail "a bad zigzag.leg exited $rc, not 2"
grep -q "zigzag.leg: must be a number > 0 and <= 10 (got -1.0)" "$tmp/err" ||
  fail "a bad zigzag.leg: $(cat "$tmp/err")"
"$zigzag" config --set zigzag.legs=1 2>"$tmp/err" >/dev/null
rc=$?
[ "$rc" -eq 2 ] || fail "an unknown zigzag key exited $rc, not 2"
grep -q "unknown config key 'zigzag.legs' (keys there: zigzag.leg, zigzag.angle_deg)" "$tmp/err" ||
  fail "an unknown zigzag key: $(cat "$tmp/err")"
"$plumetrace" config --set zigzag.leg=1 2>/dev/null && fail "plumetrace accepts zigzag.leg"

# sweep: an axis over its key
cat >"$tmp/sweep.toml" <<'TOML'
name = "zigzag"
runs = 2
seed = 7

[set]
controller.algorithm = "zigzag"
robot.start_x = 4.0
supervisor.timeout = 60.0

[[axis]]
key = "zigzag.leg"
values = [0.5, 1.5]
TOML
"$zigzag" sweep "$tmp/sweep.toml" --out "$tmp/out" --threads 2 --quiet >"$tmp/sweep.log" 2>&1 ||
  fail "sweep exited $?: $(cat "$tmp/sweep.log")"
grep -q "zigzag.leg" "$tmp/out/summary.csv" 2>/dev/null ||
  grep -rq "zigzag.leg" "$tmp/out" || fail "the sweep's output does not name zigzag.leg"
# each value is a point of its own: its column in runs.csv, a config hash of its own, and the
# store's resolved config of the point holds the value
/usr/bin/python3 - "$tmp/out" <<'PY' || fail "the points of zigzag.leg are not stored apart"
import csv, sqlite3, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(out + "/runs.csv")))
legs = sorted({r["zigzag.leg"] for r in rows})
hashes = {r["zigzag.leg"]: {x["config_hash"] for x in rows if x["zigzag.leg"] == r["zigzag.leg"]}
          for r in rows}
assert legs == ["0.5", "1.5"], legs
assert all(len(h) == 1 for h in hashes.values()) and len(set.union(*hashes.values())) == 2, hashes
points = sqlite3.connect(out + "/results.sqlite").execute(
    "SELECT axis_values, config FROM points ORDER BY point").fetchall()
assert [p[0] for p in points] == ["zigzag.leg = 0.5", "zigzag.leg = 1.5"], points
assert "[zigzag]\nleg = 0.5  #" in points[0][1] and "[zigzag]\nleg = 1.5  #" in points[1][1]
PY

# registering zigzag changes no other controller's runs: a casting sweep run by this program and
# by the plain command gives the same runs.csv (config hashes included), and the plain command
# reuses the other's store without computing a run
cat >"$tmp/casting.toml" <<'TOML'
name = "casting"
runs = 2
[set]
"controller.algorithm" = "casting"
[[axis]]
key = "casting.beta_deg"
values = [10.0, 20.0]
TOML
"$zigzag" sweep "$tmp/casting.toml" --out "$tmp/c1" --threads 2 --quiet >/dev/null 2>&1 ||
  fail "the casting sweep failed in the zigzag program"
"$plumetrace" sweep "$tmp/casting.toml" --out "$tmp/c2" --threads 2 --quiet >/dev/null 2>&1 ||
  fail "the casting sweep failed in the plain command"
cmp -s "$tmp/c1/runs.csv" "$tmp/c2/runs.csv" ||
  fail "registering zigzag changed the runs.csv of a casting sweep"
"$plumetrace" sweep "$tmp/casting.toml" --out "$tmp/c1" --threads 2 >"$tmp/reuse.log" 2>&1 ||
  fail "the plain command refused the zigzag program's store: $(cat "$tmp/reuse.log")"
grep -q "0 computed now" "$tmp/reuse.log" ||
  fail "the plain command recomputed the zigzag program's casting runs: $(cat "$tmp/reuse.log")"

[ "$failed" -eq 0 ] && echo "example_zigzag: ok"
exit "$failed"
