#!/usr/bin/env bash
# `pip install .` as a new user runs it (README, "From Python"), offline: the wheel that
# `pip install .` builds, made once from a copy of the source tree, installed into a fresh
# virtual environment made with --system-site-packages (Debian's numpy, pandas), then into a
# user site (PYTHONUSERBASE in a temporary folder). From another folder, with no PYTHONPATH,
# the installed package must import, sweep a shipped set of the paper with the same results as
# the command, and convert the rows to pandas.
# Usage: python_install_test.sh SOURCE_DIR PLUMETRACE_CLI
set -euo pipefail
src=$(cd "$1" && pwd)
cli=$2
python=/usr/bin/python3

work=$(mktemp -d "${TMPDIR:-/tmp}/plumetrace-pip.XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# a clean checkout: the files git knows (tracked, or new and not ignored); no build folders
mkdir "$work/src"
if git -C "$src" rev-parse --git-dir >/dev/null 2>&1; then
  (cd "$src" && git ls-files -z --cached --others --exclude-standard |
     xargs -0 sh -c 'for f; do [ -e "$f" ] && printf "%s\0" "$f"; done' sh |
     tar --null -T - -cf -) | tar -xf - -C "$work/src"
else
  (cd "$src" && tar --exclude='./build*' --exclude=./out --exclude=node_modules -cf - .) |
    tar -xf - -C "$work/src"
fi
[[ -f "$work/src/pyproject.toml" && ! -e "$work/src/build" ]] || fail "the source copy is not clean"

# why: nothing from the caller's setup may help the installed package be found; ccache keys
# relative to the copy, so that it reuses the objects of the build that runs this test
unset PYTHONPATH PLUMETRACE_CMAKE_BUILD_DIR PYTHONHOME
export PIP_NO_CACHE_DIR=1 PIP_DISABLE_PIP_VERSION_CHECK=1 CCACHE_BASEDIR="$work"

# the sweep the installed package must reproduce: set A of the paper, 2 runs per value
"$cli" sweep "$src/studies/lochmatter2008/sets/A.toml" --runs 2 --threads 2 --quiet \
  --out "$work/cli" >/dev/null

check='
import sys
from pathlib import Path
import pandas as pd
import plumetrace as pt
from plumetrace.studies import lochmatter2008 as paper

where, cli_csv = Path(sys.argv[1]).resolve(), sys.argv[2]
assert Path(pt.__file__).resolve().is_relative_to(where), (pt.__file__, where)
assert Path.cwd() != where
rows = pt.sweep(paper.sets["A"], runs=2, threads=2)   # a shipped sweep file, from any folder
assert paper.sets["A"].resolve().is_relative_to(where), paper.sets["A"]
df = rows.to_pandas()
assert isinstance(df, pd.DataFrame) and df.shape == (18, len(rows.keys())), df.shape
assert list(df.columns) == rows.keys()
want = pd.read_csv(cli_csv, float_precision="round_trip")
for col in ("point", "casting.beta_deg", "trial", "seed", "success", "time_s", "d_t", "d_u",
            "steps"):
    assert df[col].tolist() == want[col].tolist(), col
# the licence travels with the package: in its metadata and as a file of its dist-info
from importlib import metadata
dist = metadata.distribution("plumetrace")
assert dist.metadata["License"] == "BSD-3-Clause", dist.metadata["License"]
assert any(f.name == "LICENSE" and "BSD 3-Clause" in f.read_text() for f in dist.files), dist.files
print("installed", pt.__version__, "at", Path(pt.__file__).parent, "sweep of set A equal to the command")
'

# why: `pip install .` is `pip wheel .` then the install of that wheel; building the wheel once
# and installing it twice tests both installs at the cost of one build (the build is most of
# this test's time, and the suite's budget on 2 cores is tight)
(cd "$work/src" && $python -m pip wheel --no-build-isolation --no-index --no-deps -w "$work/wheels" .) \
  > "$work/pip-wheel.log" 2>&1 || { cat "$work/pip-wheel.log"; fail "pip wheel ."; }
wheel=("$work"/wheels/plumetrace-*.whl)
[[ ${#wheel[@]} -eq 1 && -f "${wheel[0]}" ]] || fail "pip wheel . made no single plumetrace wheel"

# 1. a virtual environment that sees Debian's numpy and pandas
$python -m venv --system-site-packages "$work/venv"
"$work/venv/bin/python" -m pip install --no-index "${wheel[0]}" \
  > "$work/pip-venv.log" 2>&1 || { cat "$work/pip-venv.log"; fail "pip install of the wheel in a venv"; }
mkdir "$work/elsewhere"
(cd "$work/elsewhere" &&
   "$work/venv/bin/python" -c "$check" "$work/venv" "$work/cli/runs.csv") ||
  fail "the package installed in the venv"

# 2. the user site (Debian 12's pip needs --break-system-packages there, PEP 668)
export PYTHONUSERBASE="$work/userbase"
$python -m pip install --user --break-system-packages --no-index "${wheel[0]}" \
  > "$work/pip-user.log" 2>&1 || { cat "$work/pip-user.log"; fail "pip install --user of the wheel"; }
(cd "$work/elsewhere" && $python -c "$check" "$work/userbase" "$work/cli/runs.csv") ||
  fail "the package installed in the user site"
echo "python_install: venv and user site OK"
