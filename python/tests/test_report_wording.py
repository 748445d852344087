"""The reports' sentences say what their numbers say: counts as "all", "most", "half", "none",
changes as "rises"/"falls" with an unsigned size (report/wording.py and the sentences that use
it), at the boundaries: 0, 1, all, equal, rising, falling."""

import re
import pytest

from plumetrace.report import wording
from plumetrace.report.sweep import build_sweep_report
from plumetrace.studies.lochmatter2008.report_sections import failure_sentence
from plumetrace.studies.meander import report as meander


@pytest.mark.parametrize("k, n, says, verb", [
    (0, 0, "no claims", "hold"), (0, 1, "no claim (0 of 1)", "hold"),
    (0, 9, "none of the 9 claims", "hold"), (1, 1, "the one claim", "holds"),
    (1, 9, "1 of 9 claims", "holds"), (2, 2, "both claims", "hold"),
    (3, 9, "3 of 9 claims", "hold"), (9, 9, "all 9 claims", "hold"),
])
def test_counts_say_none_one_both_and_all(k, n, says, verb):
    assert wording.counted(k, n, "claim", "claims") == says
    assert wording.verb(k, "holds", "hold") == verb


@pytest.mark.parametrize("k, n, lead", [(1, 1, "All"), (5, 5, "All"), (3, 5, "Most"),
                                        (2, 4, "Half of the"), (1, 3, "The largest group of"),
                                        (4, 9, "The largest group of")])
def test_a_largest_group_is_all_most_half_or_the_largest(k, n, lead):
    assert wording.share_lead(k, n) == lead


def test_a_largest_group_of_none_or_more_than_all_is_refused():
    for k, n in ((0, 3), (4, 3)):
        with pytest.raises(ValueError):
            wording.share_lead(k, n)


@pytest.mark.parametrize("before, after, says", [
    (0.90, 0.52, "falls 38 points"), (0.10, 0.48, "rises 38 points"),
    (0.50, 0.50, "stays the same"), (0.500, 0.504, "stays the same"),
    (0.50, 0.51, "rises 1 point"), (1.0, 0.0, "falls 100 points"),
])
def test_a_change_is_a_rise_or_a_fall_with_an_unsigned_size(before, after, says):
    assert wording.change(before, after) == says
    assert "+" not in says and "-" not in says


@pytest.mark.parametrize("a, b, says", [(0.6, 0.4, "20 points higher"),
                                        (0.4, 0.6, "20 points lower"), (0.3, 0.3, "the same"),
                                        (0.31, 0.30, "1 point higher")])
def test_a_difference_is_higher_lower_or_the_same(a, b, says):
    assert wording.difference(a, b) == says


# -- the paper's report: the main failure mode ---------------------------------------------------

def _summary(places, runs=None, failed=None):
    """A summary whose failed runs end at `places` (each "upwind_wall", "upwind", "near" or
    "far"; the source at x = 1), of `runs` runs at the fixed values."""
    where = {"upwind_wall": (0.07, "wall"), "upwind": (0.5, "timeout"),
             "near": (1.5, "timeout"), "far": (4.0, "timeout")}
    ends = [{"x": where[p][0], "y": 0.2, "outcome": where[p][1]} for p in places]
    failed = len(places) if failed is None else failed
    walls = sum(e["outcome"] == "wall" for e in ends)
    return {"failures": {"algorithms": [{
        "algorithm": "casting", "runs": 20 if runs is None else runs, "failed": failed,
        "walls": walls, "timeouts": failed - walls, "gave_up": 0, "examined": len(places),
        "source_x": 1.0, "source_y": 0.0, "ends": ends, "closest_median_m": 0.35}]}}


@pytest.mark.parametrize("places, failed, starts", [
    (["upwind_wall"] * 3, None, "All 3 failed runs ended at a wall upwind of the source"),
    (["far"], None, "The one failed run ended more than 1 m downwind"),
    (["near"] * 2, None, "Both failed runs ended downwind of the source but within 1 m"),
    (["far", "far", "far", "near"], None, "Most failed runs (3 of 4) ended more than 1 m"),
    (["upwind", "upwind", "far", "near"], None,
     "Half of the failed runs (2 of 4) ended upwind of the source (not at a wall)"),
    (["far", "far", "near", "upwind", "upwind_wall"], None,
     "The largest group of failed runs (2 of 5) ended more than 1 m"),
    (["far", "far", "near"], 7, "Most failed runs (2 of 3 re-run) ended more than 1 m"),
    (["far", "far"], 7, "Both re-run failed runs ended more than 1 m"),
    (["far"], 7, "The one re-run failed run ended more than 1 m"),
])
def test_the_main_failure_mode_says_all_most_half_or_the_largest_group(places, failed, starts):
    sentence = failure_sentence(_summary(places, failed=failed))
    assert sentence.startswith(starts), sentence
    assert "(100%)" not in sentence.split(". ")[0]


@pytest.mark.parametrize("runs, places, says", [
    (20, [], "None of the 20 runs at the paper's fixed values failed."),
    (1, [], "No run (0 of 1) at the paper's fixed values failed."),
    (20, ["far"], "1 of 20 runs at the paper's fixed values fails (5%)"),
    (3, ["far"] * 3, "All 3 runs at the paper's fixed values fail (100%)"),
    (1, ["far"], "The one run at the paper's fixed values fails (100%)"),
])
def test_the_failure_count_says_none_one_and_all(runs, places, says):
    assert says in failure_sentence(_summary(places, runs=runs))


def test_one_failed_run_is_not_given_a_median():
    sentence = failure_sentence(_summary(["far"]))
    assert "On its way, the failed run came within 0.35 m of the source's centre" in sentence
    assert "median" not in sentence


# -- the meander study: a change in success is a rise or a fall ----------------------------------

def _curve(label, rates):
    c = meander.Curve(label)
    for x, r in zip((0.0, 1.0, 2.0), rates):
        c.add(x, {"success_rate": r, "success_lo": max(0.0, r - 0.1),
                  "success_hi": min(1.0, r + 0.1), "runs": 50, "successes": round(50 * r)})
    return c


def test_meander_changes_are_rises_and_falls_never_a_signed_drop():
    verdict, text = meander.degradation([_curve("casting", [0.9, 0.7, 0.52]),
                                         _curve("surge-cast", [0.1, 0.3, 0.48]),
                                         _curve("surge-spiral", [0.5, 0.5, 0.5])])
    assert "casting: 90% [80%, 100%] at gain 0, 52% [42%, 62%] at gain 2 (success falls 38 " \
           "points)" in text
    assert "(success rises 38 points)" in text and "(success stays the same)" in text
    assert "drop" not in text and "+" not in text
    # the line that loses least here gains: it is not said to degrade
    assert verdict.startswith("surge-cast does not degrade")
    verdict, _ = meander.degradation([_curve("a", [0.9, 0.8, 0.2]), _curve("b", [0.9, 0.9, 0.8])])
    assert verdict.startswith("b degrades least")


def test_meander_d_lost_differences_are_higher_lower_or_the_same():
    _, text = meander.d_lost_effect([_curve("0.5", [0.5, 0.5, 0.6]),
                                     _curve("2.0", [0.5, 0.45, 0.3])])
    assert ("(30 points lower; Newcombe 95%: 11 to 47 points lower -> no), the same in the "
            "weakest.") in text
    _, text = meander.d_lost_effect([_curve("0.5", [0.5, 0.5, 0.3]),
                                     _curve("2.0", [0.6, 0.45, 0.35])])
    assert ("(5 points higher; Newcombe 95%: 12 points lower to 24 points higher -> unclear), "
            "10 points higher in the weakest.") in text
    assert not re.search(r"[+-]\d", text), "no signed differences"


# -- any sweep's report: the points with runs missing -------------------------------------------

def _results(stored):
    """results.json of one sweep of len(stored) points, 4 runs asked per point."""
    points = [{"index": i, "values": [0.1 * (i + 1)],
               "stats": {"runs": n, "successes": n, "success_rate": 1.0 if n else None}}
              for i, n in enumerate(stored)]
    return {"plumetrace_results": 1, "sweeps": [{
        "name": "s", "runs_per_point": 4, "points": points,
        "axes": [{"key": "k", "values": [p["values"][0] for p in points]}]}]}


@pytest.mark.parametrize("stored, says", [
    ([4, 4, 2], "Incomplete: 1 of 3 points has fewer runs than its sweep asks for; its numbers"),
    ([4, 1, 2], "Incomplete: 2 of 3 points have fewer runs than their sweep asks for; their"),
    ([1, 1], "Incomplete: both points have fewer runs"),
    ([1, 2, 3], "Incomplete: all 3 points have fewer runs"),
])
def test_a_sweep_report_counts_its_incomplete_points_in_words(tmp_path, stored, says):
    build_sweep_report(tmp_path, _results(stored))
    assert says in (tmp_path / "report.md").read_text().replace("**", "")
