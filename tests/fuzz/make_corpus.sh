#!/usr/bin/env bash
# Writes the seed corpora of the fuzz targets into tests/fuzz/corpus/TARGET/: copies of the
# scenario, sweep and calibration study files of the repository, a short run's traces and a tiny sweep's store made
# by the plumetrace command, and slightly broken variants of each. Run it again after a change
# of the file formats (it rewrites only the files it makes; regress-* inputs are kept).
#
#   tests/fuzz/make_corpus.sh [PATH/TO/plumetrace]    (default: build/plumetrace)
#
# Needs sqlite3 (the command-line shell) to shrink and vary the store.
set -euo pipefail
cd "$(dirname "$0")/../.."
P="$(realpath "${1:-build/plumetrace}")"
corpus=tests/fuzz/corpus
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$corpus"/{scenario,sweep,trace,store,study,calibration}

# the --set separator of the TOML targets (tests/fuzz/fuzz_support.hpp)
with_sets() {
  cat "$1"
  printf '\n#--set\n'
  shift
  printf '%s\n' "$@"
}

# scenario: the repository's scenarios and readings, the resolved form, --set lines, mistakes
s="$corpus/scenario"
cp scenarios/lochmatter2008.toml "$s/lochmatter2008.toml"
cp scenarios/paper-literal.toml "$s/paper-literal.toml"
for f in studies/lochmatter2008/presets/*.toml; do cp "$f" "$s/preset-$(basename "$f")"; done
"$P" config >"$s/resolved.toml"
with_sets scenarios/lochmatter2008.toml controller.algorithm=surge-spiral plume.preset=printed \
  wind.vx=0.5 supervisor.timeout=inf >"$s/sets.toml"
with_sets /dev/null plume.kernel=gaussian robot.start_heading_deg=-90 casting.beta_deg=45 \
  >"$s/sets-only.toml"
printf '[plume]\nsigma_p = -1.0\n' >"$s/bad-range.toml"
printf '[plume]\nsigma_pp = 0.02\n' >"$s/bad-key.toml"
printf '[robot]\nstart_x = "far"\n' >"$s/bad-type.toml"
printf '[sim]\ndt = 0.032\nwarmup = [1, 2]\n' >"$s/bad-array.toml"
printf '[arena\nx_min = 0\n' >"$s/bad-syntax.toml"
printf 'sim.dt = 1e-3\narena.x_max = 1.5\n' >"$s/dotted.toml"
with_sets /dev/null sim.dt nosuch.key=1 'controller.algorithm=' >"$s/bad-sets.toml"

# sweep: the experiment sets, the golden sweep, the store seeds' sweep, --set lines, mistakes
w="$corpus/sweep"
for f in studies/lochmatter2008/sets/*.toml studies/lochmatter2008/*.toml; do cp "$f" "$w/$(basename "$f")"; done
cp tests/golden/sweep.toml "$w/golden.toml"
cp tests/fuzz/store_sweep.toml "$w/store_sweep.toml"
with_sets tests/golden/sweep.toml supervisor.timeout=60 robot.start_y=0.5 >"$w/sets.toml"
with_sets tests/golden/sweep.toml wind_sensor.sigma_a=0.3 >"$w/bad-set-axis.toml"
printf 'name = "e"\n[[axis]]\nkey = "wind.vx"\nvalues = []\n' >"$w/bad-empty-axis.toml"
printf 'name = "d"\n[[axis]]\nkey = "wind.vx"\nvalues = [1.0]\n[[axis]]\nkey = "wind.vx"\nvalues = [2.0]\n' \
  >"$w/bad-twice.toml"
printf 'name = "u"\n[[axis]]\nkey = "wind.vz"\nvalues = [0.1, "x"]\n' >"$w/bad-value.toml"
printf 'title = "no name"\nruns = 0\n[[axis]]\nkey = "sim.dt"\nvalues = [0.01]\n' >"$w/bad-name.toml"
printf 'name = "s"\nscenario = "missing.toml"\n[[axis]]\nkey = "sim.dt"\nvalues = [0.01]\n' \
  >"$w/bad-scenario.toml"

# calibration: the two calibration studies, a synthetic one with [truth] and [fixed], one with an
# unknowns file of its own (after the line "#--unknowns", tests/fuzz/fuzz_calibration.cpp), and
# mistakes: each key out of range or of the wrong type, names twice, an unknown without evidence
c="$corpus/calibration"
cp studies/lochmatter2008/calibration.toml "$c/calibration.toml"
cp studies/lochmatter2008/calibration-evidenced.toml "$c/calibration-evidenced.toml"
small='unknowns = "unknowns.toml"\nsets_dir = "sets"\nsets = ["A", "D"]\nsearch = ["amount", "success_radius"]\n'
printf "$small"'runs = 4\nseed = 3\ntrials = 30\nstartup_trials = 5\nthreads = 2\ntarget = "synthetic"\n[truth]\namount = 1.0\nsuccess_radius = 0.3\n[fixed]\nsupervisor.timeout = 400.0\n[validation]\ntop = 2\nruns = 4\nseed = 9\n' \
  >"$c/synthetic.toml"
printf 'unknowns = "unknowns.toml"\nsets = ["G"]\nevidenced_only = true\n\n#--unknowns\n[[unknown]]\nname = "r"\nkey = "supervisor.success_radius"\nprinted = 0.185\nlow = 0.1\nhigh = 0.5\n[[unknown.evidence]]\nvalue = 0.185\nsource = "paper"\n[[unknown]]\nname = "n"\nkey = "casting.beta_deg"\nlow = 5\nhigh = 45\nint = true\nlog = true\n[[unknown.evidence]]\nvalue = 25\n' \
  >"$c/own-unknowns.toml"
printf "$small"'runs = 100000000\n' >"$c/bad-runs.toml"
printf "$small"'runs = 200000\n' >"$c/bad-runs-points.toml"
printf "$small"'threads = 5000\n' >"$c/bad-threads.toml"
printf "$small"'trials = 0\n[validation]\nruns = 10000001\n' >"$c/bad-trials.toml"
printf 'unknowns = "unknowns.toml"\nsearch = ["amount", "amount"]\nsets = ["A", "A"]\n' >"$c/bad-twice.toml"
printf 'unknowns = "unknowns.toml"\nsearch = ["amount"]\nevidenced_only = "yes"\nseed = 4\n[validation]\nseed = 4\n' \
  >"$c/bad-types.toml"
printf 'unknowns = "unknowns.toml"\ntarget = "synthetic"\n[truth]\nwind = 1\n[fixed.plume]\namount = [1]\n' \
  >"$c/bad-truth.toml"
printf 'unknowns = "unknowns.toml"\nsets_dir = "nowhere"\nname = ""\n' >"$c/bad-sets-dir.toml"
printf 'unknowns = "unknowns.toml"\n\n#--unknowns\n[[unknown]]\nname = "a"\nkey = "plume.amount"\nlow = 1.0\nhigh = nan\n[[unknown]]\nname = "a"\nkey = "plume.amount"\nchoices = []\n' \
  >"$c/bad-unknowns.toml"

# trace: a short run written as .json and .csv, a team's, one with controller snapshots, and
# broken variants (format2.json, a trace of the format before teams, is kept as it is)
t="$corpus/trace"
short=(--set sim.dt=0.1 --set sim.warmup=1 --set supervisor.timeout=1.2 --set plume.capacity=12
  --set plume.release_rate=10 --set robot.start_x=1.8)
"$P" run "${short[@]}" --trace "$tmp/run.json" --snapshot-interval 0.6 >/dev/null
"$P" run "${short[@]}" --trace "$tmp/run.csv" --snapshot-interval 0.6 >/dev/null
"$P" run "${short[@]}" --algorithm surge-spiral --set robot.start_x=1.3 --set supervisor.timeout=2 \
  --trace "$tmp/success.json" --snapshot-interval 0 >/dev/null
"$P" run "${short[@]}" --set team.count=3 --trace "$tmp/team.json" --snapshot-interval 0.6 \
  >/dev/null
cp "$tmp/run.json" "$t/run.json"
cp "$tmp/success.json" "$t/success.json"
cp "$tmp/team.json" "$t/team.json"
cp "$tmp/run.csv" "$t/run.csv"
cp "$tmp/run.filaments.csv" "$t/run.filaments.csv"
cp "$tmp/run.controller.csv" "$t/run.controller.csv"
/usr/bin/python3 - "$tmp/run.json" "$t" "$tmp/team.json" <<'EOF'
import json, sys
doc = json.load(open(sys.argv[1]))
out = sys.argv[2]
team = json.load(open(sys.argv[3]))
def write(name, d):
    with open(f"{out}/{name}", "w") as f:
        json.dump(d, f, separators=(",", ":"))
d = json.loads(json.dumps(doc)); d["steps"]["x"] = d["steps"]["x"][:-1]; write("bad-column.json", d)
d = json.loads(json.dumps(doc)); del d["result"]["outcome"]; write("bad-missing.json", d)
d = json.loads(json.dumps(doc)); d["result"]["outcome"] = "lost"; write("bad-outcome.json", d)
d = json.loads(json.dumps(doc)); d["config"]["plume"]["sigma_p"] = -1; write("bad-config.json", d)
d = json.loads(json.dumps(doc)); d["snapshots"] = [{"time": 0, "x": [1], "y": [], "z": [], "w": []}]
write("bad-snapshot.json", d)
d = json.loads(json.dumps(doc)); del d["plumetrace_trace"]; write("bad-not-trace.json", d)
d = json.loads(json.dumps(doc)); d["snapshots"][0]["x"] = "@@@@"; write("bad-base64.json", d)
d = json.loads(json.dumps(doc)); d["steps"]["state"][0] = 9; write("bad-state-index.json", d)
# a controller's snapshots (the CLI's controllers show none): every layer, one of each robot
snap = {"time": 0.0, "agent": 0, "points": {"x": [1.0, 1.2], "y": [0.1, -0.2]},
        "weights": [0.25, 0.75], "path": {"x": [1.8, 1.4], "y": [0.0, 0.1]},
        "grid": {"x0": 0.1, "y0": -0.2, "dx": 0.2, "dy": 0.2, "nx": 2, "ny": 2,
                 "values": [0.0, 0.5, None, 1.0]}, "estimate": [1.1, 0.0]}
d = json.loads(json.dumps(team)); d["declared"] = [1.1, 0.0]
d["controller_snapshots"] = [dict(snap, agent=k) for k in range(3)]
write("snapshots.json", d)
d = json.loads(json.dumps(team)); d["teammates"][1]["steps"]["x"] = d["teammates"][1]["steps"]["x"][:-1]
write("bad-teammate.json", d)
d = json.loads(json.dumps(team)); d["controller_snapshots"] = [dict(snap, grid=dict(snap["grid"], nx=3))]
write("bad-controller-snapshot.json", d)
EOF

# store: a tiny sweep's store with 512-byte pages, and variants (WAL, partial, other campaign,
# empty, not a database)
r="$corpus/store"
"$P" sweep tests/fuzz/store_sweep.toml --store "$tmp/fz.sqlite" --out "$tmp/out" --quiet >/dev/null
sqlite3 "$tmp/fz.sqlite" "PRAGMA journal_mode=DELETE; PRAGMA page_size=512; VACUUM;" >/dev/null
cp "$tmp/fz.sqlite" "$r/fz.sqlite"
cp "$tmp/fz.sqlite" "$tmp/slim.sqlite"
sqlite3 "$tmp/slim.sqlite" "UPDATE points SET config = 'x'; VACUUM;"
cp "$tmp/slim.sqlite" "$r/slim.sqlite"
cp "$tmp/slim.sqlite" "$tmp/wal.sqlite"
sqlite3 "$tmp/wal.sqlite" "PRAGMA journal_mode=WAL;" >/dev/null
cp "$tmp/wal.sqlite" "$r/slim-wal.sqlite"
cp "$tmp/slim.sqlite" "$tmp/partial.sqlite"
sqlite3 "$tmp/partial.sqlite" "DELETE FROM runs WHERE point = 1 AND trial = 1; VACUUM;"
cp "$tmp/partial.sqlite" "$r/slim-partial.sqlite"
cp "$tmp/slim.sqlite" "$tmp/other.sqlite"
sqlite3 "$tmp/other.sqlite" "UPDATE meta SET value = '{\"sweeps\":[]}' WHERE key = 'definition'; VACUUM;"
cp "$tmp/other.sqlite" "$r/slim-other-definition.sqlite"
: >"$r/empty.sqlite"
printf 'not a database\n' >"$r/bad-text.sqlite"
# study: study.toml files of the fuzzed study folder (tests/fuzz/fuzz_study.cpp: two.toml,
# sets/one.toml and report.py inside it, outside.py beside it), the shipped ones, and mistakes
st="$corpus/study"
cp studies/meander/study.toml "$st/meander.toml"
printf 'name = "meander"\ntitle = "Beyond the paper"\nsets = ["two.toml", "sets/one.toml"]\nreport = "plumetrace.studies.meander"\n' >"$st/ok-module.toml"
printf 'name = "fuzzed"\nsets = ["two.toml"]\nreport = "report.py"\n' >"$st/ok-file.toml"
printf 'name = "../../escaped"\nsets = ["two.toml"]\n' >"$st/bad-name.toml"
printf 'name = "x"\nsets = ["two.toml"]\nreport = "this"\n' >"$st/bad-report-module.toml"
printf 'name = "x"\nsets = ["two.toml"]\nreport = "../outside.py"\n' >"$st/bad-report-outside.toml"
printf 'name = "x"\nsets = ["two.toml", "two.toml"]\n' >"$st/bad-twice.toml"
printf 'name = "t\\u001b[31m"\nsets = ["two.toml"]\n' >"$st/bad-control.toml"
printf 'name = "x"\nsets = ["two.toml"]\nextra = 1\n' >"$st/bad-key.toml"
mkdir -p tests/fuzz/dict
/usr/bin/python3 tests/fuzz/make_dict.py "$s/resolved.toml" tests/fuzz/dict/toml.dict
echo "make_corpus: seeds in $corpus/{scenario,sweep,trace,store,study,calibration}; tests/fuzz/dict/toml.dict"
