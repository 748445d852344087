"""The evidence library for Python: the tests a study decides its statements with.

The same tests as the C++ library every study uses (`include/plumetrace/experiment/evidence.hpp`;
the rules: docs/claims.md, "The tests applied to each part" and "Margins"), with intervals as
``(lo, hi)`` tuples and verdicts as ``"yes"``, ``"no"`` and ``"unclear"``::

    from plumetrace import evidence as ev
    d = ev.newcombe_difference(45, 50, 30, 50)   # 95% interval of 45/50 - 30/50
    ev.directional(d, 0.10)                      # Test(verdict='yes', margin=...)
    ev.within(d, 0.10).verdict                   # 'no'

A test returns a `Test`: its verdict and its signed margin, how far the interval lies on the
claimed side of the threshold in widths of the interval (positive exactly when the verdict is
yes, NaN when the interval cannot be computed, that is when an end is NaN).

The tests and the two rate intervals (Wilson, Newcombe) are pure Python, the C++ library's
arithmetic operation for operation, so that a report can decide without the C++ module (the main
job builds none: scripts/build.sh) and gets the same bits as the C++ (python/tests/test_evidence.py
compares them with ``plumetrace._core.evidence``). `relative_difference` (Welch's t interval)
needs the C++ module. `bootstrap_mean_interval` (a percentile bootstrap of a mean, with its own
seeded stream) is Python's only.
"""

from __future__ import annotations

import math
from typing import Iterable, NamedTuple, Sequence, Tuple

__all__ = ["YES", "NO", "UNCLEAR", "SINGLE_THRESHOLD", "LEGACY_030", "RULES", "Z95", "Test",
           "in_widths", "width", "directional", "within", "below", "at_least", "weakest",
           "all_of", "combine", "negate", "scaled", "wilson_interval", "newcombe_difference",
           "relative_difference", "bootstrap_mean_interval"]

YES, NO, UNCLEAR = "yes", "no", "unclear"
#: The directional rule with one threshold m: yes when the interval lies above m, no when below
#: it; its verdict never moves between yes and no as runs grow (issue 23).
SINGLE_THRESHOLD = "single-threshold"
#: The directional rule of plumetrace 0.3.0: yes when the interval lies above 0, no when below m.
LEGACY_030 = "legacy-0.3.0"
RULES = (SINGLE_THRESHOLD, LEGACY_030)
#: The standard normal quantile at 0.975 (experiment/stats.hpp, kZ95).
Z95 = 1.959963984540054
_MIN_WIDTH = 1e-6

Interval = Tuple[float, float]


class Test(NamedTuple):
    """The outcome of one test: "yes", "no" or "unclear", and the signed margin in widths."""

    verdict: str
    margin: float


def _fmin(a: float, b: float) -> float:
    """C's fmin: the smaller, or the one that is a number when the other is NaN."""
    if math.isnan(a):
        return b
    if math.isnan(b):
        return a
    return b if b < a else a


def in_widths(distance: float, width: float) -> float:
    """A distance from a threshold (positive on the claimed side) in units of a width, the width
    floored at 1e-6; NaN when either is NaN."""
    if math.isnan(distance) or math.isnan(width):
        return math.nan
    return distance / (width if width > _MIN_WIDTH else _MIN_WIDTH)


def width(interval: Interval) -> float:
    """hi - lo."""
    return interval[1] - interval[0]


def directional(effect: Interval, m: float, rule: str = SINGLE_THRESHOLD) -> Test:
    """"The effect is positive" (signed so that the claimed direction is positive), m the smallest
    effect worth the name. single-threshold: yes when lo > m, no when hi < m, margin
    (lo - m) / width; legacy-0.3.0: yes when lo > 0, no when hi < m, margin lo / width."""
    if rule not in RULES:
        raise ValueError(f"rule '{rule}': use {' or '.join(RULES)}")
    lo, hi = effect
    yes_above = m if rule == SINGLE_THRESHOLD else 0.0
    margin = in_widths(lo - yes_above, width(effect))
    if lo > yes_above:
        return Test(YES, margin)
    if hi < m:
        return Test(NO, margin)
    return Test(UNCLEAR, margin)


def within(effect: Interval, margin: float) -> Test:
    """"The effect is negligible": yes when the interval lies inside (-margin, margin), no when
    it lies wholly outside."""
    lo, hi = effect
    m = in_widths(_fmin(lo + margin, margin - hi), width(effect))
    if math.isnan(lo) or math.isnan(hi):
        m = math.nan
    if lo > -margin and hi < margin:
        return Test(YES, m)
    if lo >= margin or hi <= -margin:
        return Test(NO, m)
    return Test(UNCLEAR, m)


def below(value: Interval, limit: float) -> Test:
    """"The quantity is below the limit": yes when hi < limit, no when lo >= limit."""
    lo, hi = value
    m = in_widths(limit - hi, width(value))
    if hi < limit:
        return Test(YES, m)
    if lo >= limit:
        return Test(NO, m)
    return Test(UNCLEAR, m)


def at_least(value: Interval, limit: float) -> Test:
    """"The quantity is at least the limit": yes when lo >= limit, no when hi < limit."""
    lo, hi = value
    m = in_widths(lo - limit, width(value))
    if lo >= limit:
        return Test(YES, m)
    if hi < limit:
        return Test(NO, m)
    return Test(UNCLEAR, m)


def weakest(margins: Iterable[float]) -> float:
    """The smallest margin (a conjunction is as close to failing as its weakest part); NaN when
    any is NaN or there is none."""
    out, n = math.inf, 0
    for m in margins:
        if math.isnan(m):
            return math.nan
        out = _fmin(out, m)
        n += 1
    return out if n else math.nan


def all_of(tests: Iterable[Tuple[str, float]]) -> Test:
    """The conjunction of tests: no when one says no, yes when all say yes (also when there is
    none), the weakest margin (NaN when any is NaN)."""
    verdict, margin, all_yes = UNCLEAR, math.inf, True
    for v, m in tests:
        _check_verdict(v)
        margin = math.nan if math.isnan(m) or math.isnan(margin) else _fmin(margin, m)
        if v == NO:
            verdict = NO
        if v != YES:
            all_yes = False
    if verdict != NO and all_yes:
        verdict = YES
    return Test(verdict, margin)


def combine(verdicts: Iterable[str]) -> str:
    """The verdict of a conjunction of parts: no as soon as one says no, yes when every one says
    yes, unclear otherwise and when there is none."""
    seen, all_yes = False, True
    for v in verdicts:
        _check_verdict(v)
        seen = True
        if v == NO:
            return NO
        if v != YES:
            all_yes = False
    return YES if seen and all_yes else UNCLEAR


def _check_verdict(v: str) -> None:
    if v not in (YES, NO, UNCLEAR):
        raise ValueError(f"verdict '{v}': use yes, no or unclear")


def negate(interval: Interval) -> Interval:
    """(-hi, -lo): the same effect signed the other way."""
    return (-interval[1], -interval[0])


def scaled(interval: Interval, f: float) -> Interval:
    """Both ends times f; NaN ends unless f is finite and positive."""
    if not (f > 0.0) or not math.isfinite(f):
        return (math.nan, math.nan)
    return (interval[0] * f, interval[1] * f)


def _count(name: str, v) -> int:
    if isinstance(v, bool) or not isinstance(v, int):
        raise TypeError(f"{name} must be a whole number, not {type(v).__name__}")
    return v


def wilson_interval(successes: int, n: int) -> Interval:
    """Wilson score 95% interval of successes / n; n <= 0 gives (0, 1) (experiment/stats.hpp)."""
    successes, n = _count("successes", successes), _count("n", n)
    if n <= 0:
        return (0.0, 1.0)
    nn = float(n)
    p = float(successes) / nn
    z = Z95
    z2 = z * z
    denom = 1.0 + z2 / nn
    centre = (p + z2 / (2.0 * nn)) / denom
    half = z * math.sqrt(p * (1.0 - p) / nn + z2 / (4.0 * nn * nn)) / denom
    # why: at 0 or n the interval touches the boundary exactly; rounding must not move it off
    lo = 0.0 if successes <= 0 else max(0.0, centre - half)
    hi = 1.0 if successes >= n else min(1.0, centre + half)
    return (lo, hi)


_hypot = None


def _c_hypot():
    """The C library's hypot, the function std::hypot calls; math.hypot where none loads.

    why: glibc's hypot is not correctly rounded (about 0.8 ulp) and Python's math.hypot is, so the
    two differ in the last bit for about 1 in 100 of Newcombe's intervals; the C library's gives
    the C++ library's bits."""
    global _hypot
    if _hypot is None:
        try:
            import ctypes
            import ctypes.util

            try:
                f = ctypes.CDLL(None).hypot
            except AttributeError:
                f = ctypes.CDLL(ctypes.util.find_library("m")).hypot
            f.restype = ctypes.c_double
            f.argtypes = (ctypes.c_double, ctypes.c_double)
            _hypot = f
        except (ImportError, OSError, AttributeError, TypeError):
            _hypot = math.hypot
    return _hypot


def newcombe_difference(successes1: int, n1: int, successes2: int, n2: int) -> Interval:
    """Newcombe's hybrid score 95% interval (his method 10) of p1 - p2 of two independent
    proportions; NaN ends when a group is empty."""
    successes1, n1 = _count("successes1", successes1), _count("n1", n1)
    successes2, n2 = _count("successes2", successes2), _count("n2", n2)
    if n1 <= 0 or n2 <= 0:
        return (math.nan, math.nan)
    p1 = float(successes1) / float(n1)
    p2 = float(successes2) / float(n2)
    w1 = wilson_interval(successes1, n1)
    w2 = wilson_interval(successes2, n2)
    delta = p1 - p2
    hypot = _c_hypot()
    lo = delta - hypot(p1 - w1[0], w2[1] - p2)
    hi = delta + hypot(w1[1] - p1, p2 - w2[0])
    return (max(-1.0, lo), min(1.0, hi))


def relative_difference(a: Sequence[float], b: Sequence[float],
                        ref: Sequence[float]) -> Interval:
    """Welch's 95% interval of (mean_a - mean_b) / mean_ref, each mean given as (n, mean, sd) of
    its sample; NaN ends unless both samples have two values or more. Needs the C++ module."""
    from . import _core  # why: Student's t quantile is the C++ library's; see the module's doc

    def mean(name, v):
        if len(v) != 3:
            raise ValueError(f"{name} must be (n, mean, sd), not {v!r}")
        return (_count(f"{name}'s n", v[0]), float(v[1]), float(v[2]))

    return tuple(_core.evidence.relative_difference(mean("a", a), mean("b", b),
                                                    mean("ref", ref)))


def bootstrap_mean_interval(values: Sequence[float], reps: int = 2000,
                            seed: int = 20081124) -> Interval:
    """Percentile bootstrap 95% interval of the mean of `values` (Efron & Tibshirani 1993,
    ch. 13): `reps` resamples with replacement drawn from Python's Mersenne Twister seeded with
    `seed`, so that a report gives the same interval every time; the 2.5th and 97.5th
    percentiles of the resampled means (nearest rank). NaN ends for fewer than 2 values. For
    times and overheads, whose distributions are skewed and bounded below, where Welch's
    symmetric interval can reach below 0."""
    import random

    xs = [float(v) for v in values]
    reps = _count("reps", reps)
    if reps < 1:
        raise ValueError(f"reps must be >= 1, not {reps}")
    if len(xs) < 2:
        return (math.nan, math.nan)
    rng = random.Random(seed)
    n = len(xs)
    means = sorted(math.fsum(xs[rng.randrange(n)] for _ in range(n)) / n for _ in range(reps))
    lo = means[max(0, math.ceil(0.025 * reps) - 1)]
    hi = means[min(reps - 1, math.ceil(0.975 * reps) - 1)]
    return (lo, hi)
