"""The leaderboard's statistics: each cell's figures, the overall score with its paired bootstrap
interval and rank intervals, and the separation of the best and worst algorithms.

Definitions and their reasons: docs/benchmark.md, "Leaderboard" and "Score". Every bootstrap
draws from a numpy Generator seeded from BOOTSTRAP_SEED and the name of what it resamples (a
task, a cell), so a page is the same byte for byte every time, and a cell's interval does not
move when another controller or task is added.
"""

from __future__ import annotations

import math
import zlib
from typing import Optional, Sequence

import numpy as np

from ..evidence import newcombe_difference, wilson_interval

__all__ = ["BOOTSTRAP_REPS", "BOOTSTRAP_SEED", "TIE", "bootstrap_difference", "bootstrap_mean",
           "cell_figures", "generator", "paired_scores", "percentile", "ranks", "separation"]

BOOTSTRAP_REPS = 2000
BOOTSTRAP_SEED = 20261127
#: Two scores closer than this are equal (a tie shares its rank). why: a mean of the same rates
#: summed in another order may differ in the last bit
TIE = 1e-9
# the largest number of resampled values drawn at once (memory: 8 bytes each)
_CHUNK = 4_000_000


def generator(*names: str) -> np.random.Generator:
    """The Generator of one resampling, seeded from BOOTSTRAP_SEED and `names` (crc32 of each:
    stable across runs and Python versions, unlike hash())."""
    words = [BOOTSTRAP_SEED] + [zlib.crc32(n.encode("utf-8")) for n in names]
    return np.random.default_rng(np.random.SeedSequence(words))


def percentile(values: np.ndarray, q: float) -> float:
    """The q-quantile (0 < q < 1) of `values` by nearest rank, NaN values left out (NaN when none
    is left): evidence.bootstrap_mean_interval's rule."""
    v = np.sort(np.asarray(values, dtype=float)[~np.isnan(values)])
    if v.size == 0:
        return math.nan
    return float(v[min(v.size - 1, max(0, math.ceil(q * v.size) - 1))])


def _interval(replicates: np.ndarray) -> tuple:
    return (percentile(replicates, 0.025), percentile(replicates, 0.975))


def _resampled_means(x: np.ndarray, rng: np.random.Generator, reps: int) -> np.ndarray:
    """`reps` means of `x` resampled with replacement."""
    out = np.empty(reps)
    step = max(1, _CHUNK // max(1, x.size))
    for start in range(0, reps, step):
        k = min(step, reps - start)
        out[start:start + k] = x[rng.integers(0, x.size, size=(k, x.size))].mean(axis=1)
    return out


def bootstrap_mean(values: Sequence[float], *names: str, reps: int = BOOTSTRAP_REPS) -> tuple:
    """Percentile bootstrap 95% interval of the mean of `values`; NaN ends for fewer than 2."""
    x = np.asarray(values, dtype=float)
    if x.size < 2:
        return (math.nan, math.nan)
    return _interval(_resampled_means(x, generator(*names), reps))


def bootstrap_difference(a: Sequence[float], b: Sequence[float], *names: str,
                         reps: int = BOOTSTRAP_REPS) -> tuple:
    """Percentile bootstrap 95% interval of mean(a) - mean(b), a and b resampled apart (two
    samples); NaN ends unless each has 2 values or more."""
    xa, xb = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if xa.size < 2 or xb.size < 2:
        return (math.nan, math.nan)
    rng = generator(*names)
    return _interval(_resampled_means(xa, rng, reps) - _resampled_means(xb, rng, reps))


def _mean(values: Sequence[float]) -> Optional[float]:
    return math.fsum(values) / len(values) if len(values) else None


def _finite(v: float) -> Optional[float]:
    return v if v is not None and math.isfinite(v) else None


def cell_figures(task: str, controller: str, runs: dict, expected: int) -> dict:
    """The figures of one cell from its runs {trial: Run}: success k/n with Wilson 95%, mean time
    to source and mean overhead of the successful runs with bootstrap 95%, declarations."""
    order = [runs[t] for t in sorted(runs)]
    n = len(order)
    k = sum(r.success for r in order)
    lo, hi = wilson_interval(k, n)
    times = [r.time for r in order if r.success]
    overheads = [r.overhead for r in order if r.success and math.isfinite(r.overhead)]
    errors = [r.declaration_error for r in order if r.declared]
    outcomes = {}
    for r in order:
        for outcome, count in r.outcomes.items():
            outcomes[outcome] = outcomes.get(outcome, 0) + count

    def summary(values, what):
        mean = _mean(values)
        ends = bootstrap_mean(values, task, controller, what)
        return {"n": len(values), "mean": mean, "lo": _finite(ends[0]), "hi": _finite(ends[1])}

    return {
        "task": task, "controller": controller, "runs": n, "expected": expected,
        "missing": max(0, expected - n), "successes": k,
        "success_rate": k / n if n else None,
        "success_lo": lo if n else None, "success_hi": hi if n else None,
        "time": summary(times, "time"), "overhead": summary(overheads, "overhead"),
        "declarations": len(errors), "declaration_error": _mean(errors),
        "outcomes": {o: outcomes[o] for o in sorted(outcomes)},
        # per trial 0..expected-1: 1 success, 0 failure, - no run (for compare's paired bootstrap)
        "trials": "".join("-" if t not in runs else "1" if runs[t].success else "0"
                          for t in range(expected)),
        "times": times,
    }


def trial_matrix(trials: Sequence[str]) -> np.ndarray:
    """Rows of 1.0, 0.0 and NaN (no run) from cells' "trials" strings of equal length."""
    table = {"1": 1.0, "0": 0.0, "-": math.nan}
    return np.array([[table[c] for c in s] for s in trials], dtype=float).reshape(
        len(trials), len(trials[0]) if trials else 0)


def paired_scores(tasks: Sequence[str], matrices: Sequence[np.ndarray],
                  reps: int = BOOTSTRAP_REPS, names: Sequence[str] = ()) -> np.ndarray:
    """Bootstrap replicates (controllers x reps) of the score, the mean over tasks of each
    controller's success rate. `matrices[i]` is task i's controllers x trials successes (NaN: no
    run). In each replicate the same trial indices are drawn for every controller of a task (the
    design is paired: trial t meets the same plume and start for all); a rate whose drawn trials
    have no run is NaN, and so is that replicate's score."""
    n_controllers = matrices[0].shape[0] if matrices else 0
    total = np.zeros((n_controllers, reps))
    for task, m in zip(tasks, matrices):
        rng = generator("score", task, *names)
        trials = m.shape[1]
        step = max(1, _CHUNK // max(1, trials * max(1, n_controllers)))
        for start in range(0, reps, step):
            k = min(step, reps - start)
            drawn = m[:, rng.integers(0, trials, size=(k, trials))]  # controllers x k x trials
            present = (~np.isnan(drawn)).sum(axis=2)
            with np.errstate(invalid="ignore", divide="ignore"):
                total[:, start:start + k] += np.nansum(drawn, axis=2) / present
    return total / max(1, len(tasks))


def ranks(scores: np.ndarray) -> np.ndarray:
    """Competition ranks along axis 0 (1 is the highest score; equal scores share the better
    rank, "1224"); NaN for a NaN score, which ranks no one."""
    s = np.asarray(scores, dtype=float)
    valid = ~np.isnan(s)
    higher = (s[None, :] > s[:, None] + TIE) & valid[None, :]  # [i, j]: j beats i
    r = 1.0 + higher.sum(axis=1)
    r[~valid] = math.nan
    return r


def separation(cells: dict, order: Sequence[str], null: set, task: str) -> dict:
    """Whether the best and the worst non-null controllers of `task` differ beyond noise.

    Success: the highest and lowest rates (ties: the first in `order`, the leaderboard's), apart
    when Newcombe's 95% interval of their difference excludes 0. Time: the fastest and slowest
    mean times among controllers with 2 successes or more, apart when the two-sample bootstrap
    95% interval of their difference excludes 0. `cells`: controller -> the cell's figures."""
    entrants = [c for c in order if c not in null and cells.get(c) and cells[c]["runs"] > 0]
    out = {"task": task, "compared": len(entrants), "best": None, "worst": None,
           "success_difference": None, "success_lo": None, "success_hi": None,
           "success_separated": None, "fastest": None, "slowest": None,
           "time_difference": None, "time_lo": None, "time_hi": None, "time_separated": None,
           "separated": None}
    if len(entrants) < 2:
        return out
    by_rate = sorted(entrants, key=lambda c: -cells[c]["success_rate"])
    best, worst = by_rate[0], by_rate[-1]
    b, w = cells[best], cells[worst]
    lo, hi = newcombe_difference(b["successes"], b["runs"], w["successes"], w["runs"])
    out.update(best=best, worst=worst, success_difference=b["success_rate"] - w["success_rate"],
               success_lo=lo, success_hi=hi, success_separated=bool(lo > 0 or hi < 0))
    timed = [c for c in entrants if cells[c]["time"]["n"] >= 2]
    if len(timed) >= 2:
        by_time = sorted(timed, key=lambda c: cells[c]["time"]["mean"])
        fast, slow = by_time[0], by_time[-1]
        lo, hi = bootstrap_difference(cells[slow]["times"], cells[fast]["times"], "separation",
                                      task)
        out.update(fastest=fast, slowest=slow,
                   time_difference=cells[slow]["time"]["mean"] - cells[fast]["time"]["mean"],
                   time_lo=lo, time_hi=hi, time_separated=bool(lo > 0 or hi < 0))
    out["separated"] = bool(out["success_separated"] or out["time_separated"])
    return out
