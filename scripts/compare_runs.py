#!/usr/bin/env python3
"""Compares two runs.csv files column by column (docs/agents.md, "A robot alone is unchanged").

    scripts/compare_runs.py OLD/runs.csv NEW/runs.csv [--ignore COLUMN ...]

Every column of OLD must be in NEW with the same text in every row, rows matched in order by
(sweep, point, trial); columns NEW adds (agent, t_first_odor, ...) are listed, not compared.
`--ignore config_hash` leaves out a column whose values are expected to change (the run's
identity is a hash of values since version 0.5.0). Exit 0 when identical, 1 otherwise, 2 on bad
input.
"""

import argparse
import csv
import sys


def read(path):
    try:
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f)
            return list(reader.fieldnames or ()), list(reader)
    except OSError as e:
        print(f"compare_runs: cannot read {path}: {e}", file=sys.stderr)
        sys.exit(2)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("old")
    p.add_argument("new")
    p.add_argument("--ignore", action="append", default=[])
    a = p.parse_args()
    old_cols, old = read(a.old)
    new_cols, new = read(a.new)
    missing = [c for c in old_cols if c not in new_cols]
    if missing:
        print(f"columns of {a.old} missing from {a.new}: {', '.join(missing)}")
        return 1
    if "agent" in new_cols:
        new = [r for r in new if r["agent"] in ("", "0")]
    if len(old) != len(new):
        print(f"{len(old)} rows against {len(new)} rows of robot 0")
        return 1
    compared = [c for c in old_cols if c not in a.ignore]
    differ = 0
    for i, (r, s) in enumerate(zip(old, new)):
        for c in compared:
            if r[c] != s[c]:
                differ += 1
                if differ <= 10:
                    print(f"row {i + 2}, column {c}: {r[c]!r} against {s[c]!r}")
    added = [c for c in new_cols if c not in old_cols]
    print(f"{len(old)} rows, {len(compared)} columns compared"
          f"{' (ignored: ' + ', '.join(a.ignore) + ')' if a.ignore else ''}; "
          f"{differ} cells differ; columns added: {', '.join(added) or 'none'}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
