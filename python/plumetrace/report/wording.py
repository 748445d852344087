"""The reports' words for counts, shares and changes, so that a sentence says what its numbers
say: "all 9 claims hold" (not "9 of 9"), "1 of 9 claims holds", "most failed runs", "half",
"falls 38 points" (a change by its direction and an unsigned size, never "drop +38")."""

from __future__ import annotations


def counted(k: int, n: int, noun: str, nouns: str) -> str:
    """`k` of `n` things as the subject of a sentence: "no claims", "none of the 9 claims",
    "the one claim", "both claims", "all 9 claims", "1 of 9 claims", "3 of 9 claims". Its verb
    agrees by verb(k, ...)."""
    if n == 0:
        return f"no {nouns}"
    if k == 0:
        return f"no {noun} (0 of 1)" if n == 1 else f"none of the {n} {nouns}"
    if k == n:
        return f"the one {noun}" if n == 1 else f"both {nouns}" if n == 2 else f"all {n} {nouns}"
    return f"{k} of {n} {nouns}"


def verb(k: int, singular: str, plural: str) -> str:
    """The verb of a subject of `k` things (counted): singular for exactly one."""
    return singular if k == 1 else plural


def share_lead(k: int, n: int) -> str:
    """How much of `n` the largest group of `k` is, to lead a sentence about that group: "All",
    "Most" (more than half), "Half of the", or "The largest group of" (less than half)."""
    if not 0 < k <= n:
        raise ValueError(f"share_lead: the largest group of {n} holds {k}")
    if k == n:
        return "All"
    if 2 * k > n:
        return "Most"
    return "Half of the" if 2 * k == n else "The largest group of"


def points(delta: float) -> str:
    """An unsigned difference of two rates in percentage points: "38 points", "1 point"."""
    size = round(abs(100 * delta))
    return f"{size} point" if size == 1 else f"{size} points"


def change(before: float, after: float) -> str:
    """How a rate goes from `before` to `after` (0 to 1): "rises 38 points", "falls 5 points",
    or "stays the same" (a change under half a point)."""
    if round(abs(100 * (after - before))) == 0:
        return "stays the same"
    return f"{'rises' if after > before else 'falls'} {points(after - before)}"


def difference(a: float, b: float) -> str:
    """Rate `a` against rate `b` (0 to 1): "12 points higher", "3 points lower", or "the same"
    (a difference under half a point)."""
    if round(abs(100 * (a - b))) == 0:
        return "the same"
    return f"{points(a - b)} {'higher' if a > b else 'lower'}"
