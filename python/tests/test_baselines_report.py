"""The baselines study's report drawn from synthetic runs (studies/baselines/report.py)."""

import csv
import json

import pytest

from plumetrace import evidence
from plumetrace.studies.baselines import report

COLUMNS = ["sweep", "point", "controller.algorithm", "team.range", "start.region", "trial",
           "agent", "outcome", "success", "time_s", "d_t", "d_u", "overhead",
           "declaration_error"]


def rows_of(sweep, algorithm, start, successes, runs=50, robots=1, reach="", declared=None):
    """`runs` runs of which the first `successes` have robot 0 arrive at 100 + trial s."""
    out = []
    for trial in range(runs):
        for agent in range(robots):
            ok = trial < successes and agent == 0
            out.append({"sweep": sweep, "point": 0, "controller.algorithm": algorithm,
                        "team.range": reach, "start.region": start, "trial": trial,
                        "agent": agent, "outcome": "success" if ok else "timeout",
                        "success": int(ok), "time_s": 100.0 + trial if ok else 1200.0,
                        "d_t": 20.0, "d_u": 14.5 if ok else 2.0,
                        "overhead": 20.0 / 14.5 if ok else 10.0,
                        "declaration_error": "" if declared is None else declared})
    return out


def write(tmp_path, rows):
    with open(tmp_path / "runs.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        w.writerows(rows)
    (tmp_path / "results.json").write_text(json.dumps({"plumetrace_results": 1, "sweeps": []}))
    return tmp_path


def test_the_title_names_the_leaders_everywhere_the_weak_and_the_random_walks(tmp_path):
    rows = []
    # the paper's setting: surge-cast 50/50 and infotaxis 47/50 are tied, casting 30/50 is not
    rows += rows_of("L", "surge-cast", "point", 50)
    rows += rows_of("L", "infotaxis", "point", 47, declared=0.2)
    rows += rows_of("L", "casting", "point", 30)
    rows += rows_of("L", "crw", "point", 3)
    rows += rows_of("LB", "crw", "point", 6)
    # strong meander from outside: surge-cast 45/50 leads, infotaxis falls to 10/50
    rows += rows_of("S", "surge-cast", "rectangle", 45)
    rows += rows_of("S", "infotaxis", "rectangle", 10)
    rows += rows_of("ST", "hayes", "rectangle", 40, robots=3, reach="inf")
    rows += rows_of("ST", "hayes", "rectangle", 20, robots=3, reach="0.0")
    rows += rows_of("S", "levy", "rectangle", 1)
    report.build_report(write(tmp_path, rows))
    md = (tmp_path / "report.md").read_text()
    title = md.splitlines()[0]
    # surge-cast is tied with the best in both conditions; infotaxis' 10/50 has a Wilson upper
    # end below half; the biased walk's mean time (100-105 s) against surge-cast's (100-149 s)
    assert title == ("# Baselines of the field: surge-cast is tied with the best in all 2 "
                     "conditions; infotaxis falls below half in at least one; random walks "
                     "biased upwind reach up to 12% but take 0.8 times the leaders' time; "
                     "unbiased walks at most 6%"), title
    assert evidence.wilson_interval(10, 50)[1] < 0.5 < evidence.wilson_interval(30, 50)[1]
    # the checks behind the title: 50/50 vs 47/50 tied, vs 30/50 not
    tied = evidence.newcombe_difference(50, 50, 47, 50)
    assert tied[0] < 0 < tied[1]
    assert evidence.newcombe_difference(50, 50, 30, 50)[0] > 0
    # rows: the variant names, Wilson intervals, times of successful runs, declarations
    lo, hi = evidence.wilson_interval(47, 50)
    assert f"| infotaxis | 47/50 [{100 * lo:.0f}%, {100 * hi:.0f}%] | 123 s [" in md
    assert "| crw + upwind bias | 6/50 " in md
    assert "| hayes, team of 3, no messages | 20/50 " in md
    # a team of 3 counts one run per trial, and every robot's ending
    assert "| 110 timeout, 40 success |" in md
    assert "| 50; error 0.20 m [0.20, 0.20] |" in md
    assert (tmp_path / "figures" / "baselines_success.png").stat().st_size > 10_000
    assert (tmp_path / "report.html").is_file()


def test_runs_of_another_study_are_refused_naming_the_missing_columns(tmp_path):
    with open(tmp_path / "runs.csv", "w") as f:
        f.write("sweep,trial,agent,outcome\nL,0,0,success\n")
    (tmp_path / "results.json").write_text("{}")
    with pytest.raises(report.BaselinesReportError, match="controller.algorithm"):
        report.build_report(tmp_path)
    assert report.main([str(tmp_path)]) == 2
