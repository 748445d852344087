"""plumetrace.evidence: the tests on hand-computed intervals, and the same bits as the C++ library
(plumetrace._core.evidence) on a grid of cases."""

import itertools
import math
import os
import random
import struct

import pytest

from plumetrace import evidence as ev


def test_directional_reads_the_interval_by_its_rule():
    # ends are binary fractions, so every margin is exact
    assert ev.directional((0.625, 0.875), 0.5) == ("yes", 0.5)
    assert ev.directional((0.25, 0.75), 0.5) == ("unclear", -0.5)
    assert ev.directional((0.125, 0.375), 0.5) == ("no", -1.5)
    # the 0.3.0 rule says yes to the same interval: above 0, though below m
    assert ev.directional((0.125, 0.375), 0.5, rule=ev.LEGACY_030) == ("yes", 0.5)
    assert ev.directional((-0.25, 0.25), 0.5, rule=ev.LEGACY_030) == ("no", -0.5)
    t = ev.directional((math.nan, math.nan), 0.05)
    assert t.verdict == "unclear" and math.isnan(t.margin)
    with pytest.raises(ValueError, match="rule 'strict'"):
        ev.directional((0.1, 0.2), 0.05, rule="strict")


def test_within_below_and_at_least():
    assert ev.within((-0.0625, 0.03125), 0.125) == ("yes", 0.0625 / 0.09375)
    assert ev.within((0.125, 0.25), 0.125) == ("no", -1.0)
    assert ev.within((0.0, 0.25), 0.125) == ("unclear", -0.5)
    assert ev.below((0.25, 0.5), 0.75) == ("yes", 1.0)
    assert ev.below((0.75, 1.0), 0.75).verdict == "no"
    assert ev.at_least((0.75, 1.0), 0.75) == ("yes", 0.0)
    assert ev.at_least((0.25, 0.5), 0.75) == ("no", -2.0)
    assert ev.at_least((0.875, 0.875), 0.75) == ("yes", 0.125 / 1e-6)


def test_conjunctions_are_as_strong_as_their_weakest_part():
    assert ev.all_of([("yes", 0.5), ("yes", 2.0)]) == ("yes", 0.5)
    assert ev.all_of([("yes", 0.5), ("unclear", -0.25)]) == ("unclear", -0.25)
    assert ev.all_of([ev.Test("unclear", -0.25), ev.Test("no", -1.0)]) == ("no", -1.0)
    assert math.isnan(ev.all_of([("yes", 0.5), ("yes", math.nan)]).margin)
    assert ev.weakest([0.5, -0.25, 2.0]) == -0.25
    assert math.isnan(ev.weakest([])) and math.isnan(ev.weakest([0.5, math.nan]))
    assert ev.combine(["yes", "yes"]) == "yes"
    assert ev.combine(["yes", "unclear"]) == "unclear"
    assert ev.combine(["unclear", "no", "yes"]) == "no"
    assert ev.combine([]) == "unclear"
    with pytest.raises(ValueError, match="verdict 'maybe'"):
        ev.combine(["maybe"])


def test_rate_intervals():
    lo, hi = ev.wilson_interval(1, 4)
    assert (round(lo, 3), round(hi, 3)) == (0.046, 0.699)
    assert ev.wilson_interval(0, 10)[0] == 0.0 and ev.wilson_interval(10, 10)[1] == 1.0
    assert ev.wilson_interval(0, 0) == (0.0, 1.0)
    lo, hi = ev.newcombe_difference(50, 50, 50, 50)
    assert -0.072 < lo < -0.071 and 0.071 < hi < 0.072  # docs/claims.md: +-0.071
    assert all(math.isnan(x) for x in ev.newcombe_difference(1, 0, 1, 2))
    with pytest.raises(TypeError, match="successes1 must be a whole number"):
        ev.newcombe_difference(0.5, 2, 1, 2)
    assert ev.negate((0.1, 0.3)) == (-0.3, -0.1)
    assert all(math.isnan(x) for x in ev.scaled((1.0, 2.0), 0.0))


# --- the same bits as the C++ library ---------------------------------------------------------

def _core_evidence():
    if os.environ.get("PLUMETRACE_CORE_OPTIONAL") == "1":
        pytest.importorskip("plumetrace._core")
    from plumetrace import _core

    return _core


def bits(x):
    return struct.pack("<d", x) if not math.isnan(x) else b"nan"


def same(a, b):
    """The same bits, tuple for tuple (every NaN counted as one)."""
    a, b = tuple(a), tuple(b)
    return len(a) == len(b) and all(
        (x == y) if isinstance(x, str) else bits(x) == bits(y) for x, y in zip(a, b))


COUNTS = [(k, n) for n in (1, 2, 3, 7, 10, 20, 50, 200) for k in sorted({0, 1, n // 3, n // 2,
                                                                          n - 1, n})]


def test_python_and_cpp_rate_intervals_agree_bit_for_bit():
    core = _core_evidence()
    for k, n in COUNTS + [(0, 0)]:
        assert same(ev.wilson_interval(k, n), core.wilson_interval(k, n)), (k, n)
    pairs = list(itertools.product(COUNTS, COUNTS))
    # and 3000 drawn from every count up to 60 runs: math.hypot would differ in about 30
    every = [(k, n) for n in range(1, 61) for k in range(n + 1)]
    draw = random.Random(20081124)
    pairs += [(draw.choice(every), draw.choice(every)) for _ in range(3000)]
    for (k1, n1), (k2, n2) in pairs:
        py = ev.newcombe_difference(k1, n1, k2, n2)
        assert same(py, core.evidence.newcombe_difference(k1, n1, k2, n2)), (k1, n1, k2, n2)


def test_python_and_cpp_tests_agree_bit_for_bit():
    core = _core_evidence().evidence
    intervals = [ev.newcombe_difference(k1, n1, k2, n2)
                 for (k1, n1), (k2, n2) in itertools.product(COUNTS[::3], COUNTS[::2])]
    intervals += [(0.5, 0.5), (math.nan, math.nan), (-0.25, 0.25), (0.1, math.inf)]
    checked = 0
    for e in intervals:
        for m in (0.0, 0.01, 0.05, 0.1, -0.1):
            for rule in ev.RULES:
                assert same(ev.directional(e, m, rule), core.directional(e, m, rule)), (e, m, rule)
            assert same(ev.within(e, abs(m)), core.within(e, abs(m))), (e, m)
            assert same(ev.below(e, m), core.below(e, m)), (e, m)
            assert same(ev.at_least(e, m), core.at_least(e, m)), (e, m)
            checked += 1
    assert checked > 1000
    tests = [ev.directional(e, 0.05) for e in intervals[:40]]
    for i in range(0, len(tests), 3):
        group = tests[i:i + 4]
        assert same(ev.all_of(group), core.all_of(group)), group
        margins = [t.margin for t in group]
        assert same([ev.weakest(margins)], [core.weakest(margins)]), margins
    assert same(ev.all_of([]), core.all_of([]))
    with pytest.raises(ValueError, match="rule 'strict'"):
        core.directional((0.1, 0.2), 0.05, "strict")


def test_relative_difference_is_welchs_interval_scaled_by_the_reference_mean():
    _core_evidence()
    lo, hi = ev.relative_difference((50, 2.2, 0.1), (50, 2.0, 0.1), (50, 2.0, 0.1))
    # t(0.975, 98) = 1.98446745, se = sqrt(2 * 0.01 / 50) = 0.02
    half = 1.98446745 * 0.02
    assert lo == pytest.approx((0.2 - half) / 2.0, abs=1e-9)
    assert hi == pytest.approx((0.2 + half) / 2.0, abs=1e-9)
    assert all(math.isnan(x) for x in ev.relative_difference((1, 2.2, 0.0), (50, 2.0, 0.1),
                                                             (50, 2.0, 0.1)))
    with pytest.raises(ValueError, match=r"a must be \(n, mean, sd\)"):
        ev.relative_difference((50, 2.2), (50, 2.0, 0.1), (50, 2.0, 0.1))


def test_bootstrap_mean_interval_covers_the_mean_like_the_normal_interval_and_replays():
    import random
    rng = random.Random(3)
    xs = [rng.gauss(10.0, 2.0) for _ in range(400)]
    lo, hi = ev.bootstrap_mean_interval(xs)
    m = sum(xs) / len(xs)
    sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1))
    half = ev.Z95 * sd / math.sqrt(len(xs))
    # for a normal sample of 400 the percentile interval is the normal one within a few percent
    assert lo < m < hi
    assert abs((hi - lo) / (2 * half) - 1.0) < 0.12, (lo, hi, half)
    assert abs((lo + hi) / 2 - m) < 0.1 * half
    # the same values and seed give the same interval; a constant sample gives a point
    assert ev.bootstrap_mean_interval(xs) == (lo, hi)
    assert ev.bootstrap_mean_interval([4.0] * 5) == (4.0, 4.0)
    assert all(math.isnan(v) for v in ev.bootstrap_mean_interval([1.0]))
    with pytest.raises(ValueError, match="reps"):
        ev.bootstrap_mean_interval(xs, reps=0)
