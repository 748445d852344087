"""Sweeps given as a dict of axes, and the statistics of a sweep's rows per point.

    import plumetrace as pt
    rows = pt.sweep({"surge_cast.d_lost": [0.1, 0.2, 0.4]}, runs=20,
                    base=pt.Scenario(controller__algorithm="surge-cast"))
    rows.summary().to_pandas()    # per point: Wilson 95% of success, bootstrap 95% of overhead

A dict sweep is the same sweep as a file with those axes (docs/experiments.md): the first key
varies slowest, every value is checked against its key, and every run is a pure function of
(the point's scenario, seed, trial). The statistics are computed by the C++ functions that
`plumetrace sweep` prints, over the same runs in the same order, so they agree exactly with its
summary.csv.
"""

import math
import os

# the columns of SweepRows.summary() after the point and its axis values
SUMMARY_COLUMNS = ("runs", "successes", "walls", "timeouts", "gave_up", "success_rate",
                   "success_lo", "success_hi", "overhead_n", "overhead_mean", "overhead_lo",
                   "overhead_hi", "overhead_median", "overhead_q1", "overhead_q3")

# runs per point and master seed of a dict sweep that names none (as a sweep file's defaults)
DEFAULT_RUNS = 10
DEFAULT_SEED = 1


def sweep_spec(sweep, runs=0, base=None, seed=None, name=None, title=None, fixed=None,
               labels=None):
    """What plumetrace._core takes for a sweep: a sweep file's path as a str, or, for a dict of
    axes ({dotted key: values}), a dict of the sweep's parts. `base`: the base scenario (a
    Scenario, a scenario file's path, or None for the defaults); `seed`, `name`, `title`: the
    master seed (default 1), the sweep's name (default "sweep") and title; `fixed`, `labels`:
    dicts by axis key of the value to mark in reports and of the axis label. Options that only a
    dict sweep takes are refused for a file, whose own keys say them."""
    if isinstance(sweep, (str, os.PathLike)):
        given = {k: v for k, v in (("base", base), ("seed", seed), ("name", name),
                                   ("title", title), ("fixed", fixed), ("labels", labels))
                 if v is not None}
        if given:
            raise TypeError(f"{', '.join(given)}: given with the sweep file {os.fspath(sweep)!r}, "
                            "which says them itself; pass a dict of axes to set them here")
        return os.fspath(sweep)
    if not isinstance(sweep, dict):
        raise TypeError("sweep must be a sweep file's path or a dict of axes {dotted key: "
                        f"values}}, got {type(sweep).__name__}")
    if not sweep:
        raise ValueError("sweep: the dict has no axis (a sweep varies at least one key)")
    from .api import Scenario, _config_value, _whole

    fixed, labels = dict(fixed or {}), dict(labels or {})
    axes = []
    for key, values in sweep.items():
        if not isinstance(key, str):
            raise TypeError(f"sweep: axis key {key!r} is not a str (a dotted config key)")
        if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
            raise TypeError(f"axis {key}: values must be a list of values, got "
                            f"{type(values).__name__} {values!r}")
        values = [_config_value(key, v) for v in values]
        if not values:
            raise ValueError(f"axis {key}: values must not be empty")
        marked = _config_value(key, fixed.pop(key)) if key in fixed else None
        # why: the value a report marks is one the sweep runs ("auto " or 0.25 for 0.2 marks
        # nothing)
        if marked is not None and not any(_same_value(marked, v) for v in values):
            raise ValueError(f"fixed: {key} = {marked!r} is not one of the axis' values "
                             f"{values}"[:300])
        axes.append({"key": key, "values": values, "label": labels.pop(key, None),
                     "fixed": marked})
    for what, rest in (("fixed", fixed), ("labels", labels)):
        if rest:
            raise ValueError(f"{what}: {', '.join(map(str, rest))} is not an axis of the sweep "
                             f"(axes: {', '.join(sweep)})")
    if base is None:
        path, settings = None, []
    elif isinstance(base, Scenario):
        path, settings = base._settings()
    elif isinstance(base, (str, os.PathLike)):
        path, settings = os.fspath(base), []
    else:
        raise TypeError(f"base must be a Scenario, a scenario file's path or None, got "
                        f"{type(base).__name__}")
    name = "sweep" if name is None else name
    if not isinstance(name, str) or not name:
        raise ValueError(f"name must be a non-empty str, got {name!r}")
    if title is None:
        title = " x ".join(a["key"] for a in axes)
    return {"name": name, "title": str(title),
            "seed": _whole("seed", DEFAULT_SEED if seed is None else seed, 0, 2**64 - 1),
            "runs": runs if runs > 0 else DEFAULT_RUNS, "scenario": path,
            "settings": list(settings), "axes": axes}


def _same_value(a, b):
    """Whether two config values are one: equal, both text or both numbers (1 is 1.0), and a
    bool only equal to a bool."""
    return (isinstance(a, bool) == isinstance(b, bool) and isinstance(a, str) == isinstance(b, str)
            and a == b)


def axis_keys(rows):
    """The axis keys of a sweep's rows, in axis order."""
    if rows.info.get("axes") is not None:
        return [a["key"] for a in rows.info["axes"]]
    keys = list(rows.columns)
    return keys[keys.index("point") + 1:keys.index("trial")]


def summary(rows):
    """Per point of `rows` (SweepRows), in point order: the point, its axis values, the count of
    each outcome, the success rate with its Wilson 95% interval, and over the successful runs
    the mean distance overhead with its percentile bootstrap 95% interval (overhead_lo,
    overhead_hi: 2000 resamples, fixed seed; within the sample's range, so never below 1; NaN
    below two successful runs) and its quartiles (NaN where there is none). Returns SweepRows
    with these columns."""
    import numpy as np

    from . import _core
    from .api import SweepRows

    cols = rows.to_numpy()
    keys = axis_keys(rows)
    out = {k: [] for k in ("point", *keys, *SUMMARY_COLUMNS)}
    if len(rows) == 0:
        return SweepRows(rows.name, {k: np.asarray(v) for k, v in out.items()}, rows.info)
    outcome = np.asarray(cols["outcome"]).astype(str)
    success = np.asarray(cols["success"], dtype=bool)
    overhead = np.asarray(cols["overhead"], dtype=float)
    for point in dict.fromkeys(cols["point"].tolist()):
        # why: rows are sorted by (point, trial, agent), so these are the runs in the order the C++
        # summary sums them: the same floating-point results, bit for bit
        sel = cols["point"] == point
        first = int(np.flatnonzero(sel)[0])
        n, k = int(sel.sum()), int(success[sel].sum())
        lo, hi = _core.wilson_interval(k, n)
        values = overhead[sel & success].tolist()
        mean = _core.mean_ci(values)[0]
        mlo, mhi = _core.bootstrap_mean_interval(values)
        q1, median, q3 = _core.quartiles(values)
        stats = {"runs": n, "successes": k,
                 "walls": int((outcome[sel] == "wall").sum()),
                 "timeouts": int((outcome[sel] == "timeout").sum()),
                 "gave_up": int((outcome[sel] == "gave_up").sum()),
                 "success_rate": k / n, "success_lo": lo, "success_hi": hi,
                 "overhead_n": sum(1 for v in values if not math.isnan(v)),
                 "overhead_mean": mean, "overhead_lo": mlo, "overhead_hi": mhi,
                 "overhead_median": median, "overhead_q1": q1, "overhead_q3": q3}
        out["point"].append(point)
        for key in keys:
            out[key].append(rows.columns[key][first])
        for key in SUMMARY_COLUMNS:
            out[key].append(stats[key])
    columns = {}
    for key, values in out.items():
        columns[key] = values if key in keys else np.asarray(values)
    return SweepRows(rows.name, columns, rows.info)
