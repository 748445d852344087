"""The meander study's report drawn from synthetic results.json files (studies/meander/report.py)."""

import json
import math

import pytest

from plumetrace.studies.meander import report


def wilson(k, n, z=1.959963984540054):
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return c - h, c + h


def point(values, successes, runs=50, overhead=1.3):
    lo, hi = wilson(successes, runs)
    return {"values": values, "stats": {
        "runs": runs, "successes": successes, "success_rate": successes / runs,
        "success_lo": lo, "success_hi": hi,
        "overhead": {"mean": overhead, "lo": overhead - 0.5, "hi": overhead + 0.05,
                     "boot_lo": overhead - 0.04, "boot_hi": overhead + 0.03}}}


def sweep(name, title, key, label, table):
    """table: {other value: [successes at gains 0, 1, 2]}"""
    gains = [0.0, 1.0, 2.0]
    points = [point([v, g], s) for v, row in table.items() for g, s in zip(gains, row)]
    return {"name": name, "title": title, "points": points,
            "axes": [{"key": key, "label": label, "values": list(table)},
                     {"key": "meander.gain", "label": "gain", "values": gains}]}


def write(tmp_path, sweeps):
    (tmp_path / "results.json").write_text(json.dumps({"plumetrace_results": 1, "sweeps": sweeps}))
    return tmp_path


def first_line(tmp_path, algorithms, d_lost_key, d_lost):
    """The report's title for an algorithms sweep and one d_lost sweep (successes of 50 at gains
    0, 1 and 2), the report written into tmp_path."""
    out = write(tmp_path, [
        sweep("M", "algorithms", "controller.algorithm", "algorithm", algorithms),
        sweep("L", f"{d_lost_key.split('.')[0].replace('_', '-')}: d_lost", d_lost_key, "d_lost",
              d_lost),
    ])
    report.build_report(out)
    return (out / "report.md").read_text().splitlines()[0]


def test_the_title_names_the_algorithm_that_degrades_least_and_the_d_lost_effect(tmp_path):
    out = write(tmp_path, [
        sweep("M", "algorithms", "controller.algorithm", "algorithm",
              {"casting": [45, 30, 10], "surge-spiral": [48, 40, 25], "surge-cast": [49, 48, 46]}),
        sweep("L", "surge-cast: d_lost", "surge_cast.d_lost", "d_lost",
              {"0.5": [49, 48, 45], "2.0": [49, 40, 15]}),
    ])
    written = report.build_report(out)
    html = (out / "report.html").read_text()
    md = (out / "report.md").read_text()
    assert [p.name for p in written] == ["report.html", "report.md"]
    assert "Beyond the paper: surge-cast degrades least" in md.splitlines()[0]
    assert "a larger d_lost hurts surge-cast in strong meander" in md.splitlines()[0]
    assert (out / "figures" / "meander_M.png").stat().st_size > 1000
    assert "figures/meander_L.png" in md
    assert html.count("<img") == 2


def test_overlapping_intervals_are_not_called_a_difference(tmp_path):
    first = first_line(tmp_path, {"casting": [40, 38, 35], "surge-cast": [40, 37, 33]},
                       "casting.d_lost", {"0.5": [40, 38, 36], "2.0": [40, 37, 34]})
    assert "do not separate it from surge-cast" in first
    assert "no algorithm is clearly hurt by a larger d_lost" in first


def test_a_difference_is_decided_by_newcombes_interval_with_the_old_rule_beside(tmp_path):
    # 40/50 against 29/50 at the strongest meander: the Wilson intervals overlap ([0.67, 0.89],
    # [0.44, 0.71]), Newcombe's interval of the difference does not reach 0 ([+0.04, +0.38])
    first = first_line(tmp_path, {"casting": [45, 42, 40], "surge-cast": [50, 40, 29]},
                       "surge_cast.d_lost", {"0.5": [50, 45, 40], "2.0": [50, 40, 29]})
    md = (tmp_path / "report.md").read_text()
    assert "casting degrades least" in first and "do not separate" not in first
    assert "a larger d_lost hurts surge-cast in strong meander" in first
    assert ("at the strongest meander casting against surge-cast: 22 points higher (Newcombe "
            "95%: 4 to 38 points higher) -> yes (0.3.0's rule: Wilson intervals overlapping)") in md
    assert "(22 points lower; Newcombe 95%: 4 to 38 points lower -> no)" in md
    assert "By 0.3.0's rule (the Wilson intervals overlapping) it makes no clear difference." in md


def test_the_line_that_degrades_least_may_still_succeed_less(tmp_path):
    out = write(tmp_path, [sweep("M", "algorithms", "controller.algorithm", "algorithm",
                                 {"casting": [20, 20, 18], "surge-spiral": [50, 50, 45]})])
    report.build_report(out)
    first = (out / "report.md").read_text().splitlines()[0]
    assert ("casting degrades least, but still succeeds less than surge-spiral at the strongest "
            "meander") in first


def test_a_sweep_without_a_strength_axis_is_refused(tmp_path):
    bad = sweep("M", "algorithms", "controller.algorithm", "algorithm", {"casting": [1, 2, 3]})
    bad["axes"][1]["key"] = "sim.dt"
    out = write(tmp_path, [bad])
    with pytest.raises(report.MeanderReportError, match="meander.gain"):
        report.build_report(out)
    assert report.main([str(tmp_path / "nowhere")]) == 2


def test_the_overhead_is_shown_with_its_bootstrap_interval_never_its_t_interval(tmp_path):
    out = write(tmp_path, [sweep("M", "algorithms", "controller.algorithm", "algorithm",
                                 {"casting": [45, 30, 10], "surge-cast": [49, 48, 46]})])
    report.build_report(out)
    md = (out / "report.md").read_text()
    assert "overhead \\[bootstrap 95%\\]" in md or "overhead [bootstrap 95%]" in md
    assert "1.300 [1.260, 1.330]" in md and "0.800" not in md
