"""Build the plumetrace report from a `plumetrace reproduce` output folder.

    PYTHONPATH=python python3 -m plumetrace.report OUT_DIR

reads OUT_DIR/summary.json (and OUT_DIR/sensitivity.json when it exists) and writes
OUT_DIR/report.html (self-contained: every figure is embedded as a data URI), OUT_DIR/report.md
and the figures it links, OUT_DIR/figures/*.png. The file formats are described in docs/report.md.

Only the standard library, numpy and matplotlib (Agg) are used.
"""

from __future__ import annotations

import argparse
import base64
import html
import json
import math
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Optional, Sequence, Union

import numpy as np
from matplotlib import colormaps
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.colors import LinearSegmentedColormap, to_rgb
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Patch

__all__ = ["ReportError", "build_report", "main"]

SUMMARY_NAME = "summary.json"
SENSITIVITY_NAME = "sensitivity.json"
SUMMARY_FORMAT = 1
SENSITIVITY_FORMAT = 1

# The paper's three algorithms, in the order of its figures.
ALGORITHMS = ("casting", "surge-spiral", "surge-cast")

DPI = 100
BAR_COLOR = "#8fb3d9"
FIXED_COLOR = "#2c5d8f"
MISSING_COLOR = "#999999"

# Verdict -> (css class, background colour, symbol for the claims matrix).
VERDICT_STYLE = {
    "holds": ("holds", "#c8e6c9", "\u2713"),
    "does not hold": ("fails", "#ffcdd2", "\u2717"),
    "unclear": ("unclear", "#ffe0a3", "?"),
}
OTHER_VERDICT = ("other", "#e0e0e0", "\u2013")

# Controller states (the names the C++ controllers report), coloured by role: moving upwind in
# the plume is blue, searching is orange/red.
STATE_COLORS = {
    "upwind": "#1f77b4",
    "surge": "#1f77b4",
    "crosswind": "#ff7f0e",
    "spiral": "#ff7f0e",
    "cast1": "#ff7f0e",
    "cast2": "#d62728",
}
EXTRA_STATE_COLORS = ("#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22")

# Light grey map for the detection fraction, so the coloured trajectories stay readable.
ODOR_CMAP = LinearSegmentedColormap.from_list("plumetrace_odor", ["#ffffff", "#8c8c8c"])

DASH = "\u2013"


class ReportError(Exception):
    """A missing or malformed input file; the message starts with the file's path."""


# --------------------------------------------------------------------------------------------
# Reading and checking the input files


def _load_json(path: Path) -> Any:
    """Parses one JSON file, raising ReportError with the path on any problem."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ReportError(f"{path}: file not found") from None
    except (OSError, UnicodeDecodeError) as err:
        raise ReportError(f"{path}: cannot read: {err}") from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as err:
        raise ReportError(
            f"{path}: not valid JSON: {err.msg} at line {err.lineno}, column {err.colno}"
        ) from None


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


class _Checker:
    """Checks the shape of a parsed file; every failure names the file and the JSON path."""

    def __init__(self, path: Path):
        self.path = path

    def fail(self, where: str, msg: str) -> None:
        raise ReportError(f"{self.path}: {where}: {msg}")

    def obj(self, v: Any, where: str) -> dict:
        if not isinstance(v, dict):
            self.fail(where, f"expected an object, got {_json_type(v)}")
        return v

    def lst(self, v: Any, where: str) -> list:
        if not isinstance(v, list):
            self.fail(where, f"expected an array, got {_json_type(v)}")
        return v

    def num(self, v: Any, where: str, nullable: bool = True) -> None:
        if v is None and nullable:
            return
        if not _is_number(v):
            expected = "a number or null" if nullable else "a number"
            self.fail(where, f"expected {expected}, got {_json_type(v)}")

    def text(self, v: Any, where: str, nullable: bool = False) -> None:
        if v is None and nullable:
            return
        if not isinstance(v, str):
            self.fail(where, f"expected a string, got {_json_type(v)}")

    def numbers(self, v: Any, where: str) -> list:
        for i, x in enumerate(self.lst(v, where)):
            self.num(x, f"{where}[{i}]")
        return v


def _json_type(v: Any) -> str:
    if v is None:
        return "null"
    if isinstance(v, bool):
        return "a boolean"
    if _is_number(v):
        return f"the number {v!r}"
    if isinstance(v, str):
        return f"the string {v!r}" if len(v) < 40 else "a string"
    if isinstance(v, list):
        return "an array"
    if isinstance(v, dict):
        return "an object"
    return type(v).__name__


_POINT_NUMBERS = ("runs", "successes", "walls", "timeouts", "gave_up", "success_rate",
                  "success_lo", "success_hi", "mean_time", "mean_losses")
_OVERHEAD_NUMBERS = ("n", "mean", "lo", "hi", "boot_lo", "boot_hi", "median", "q1", "q3")


def _check_point(c: _Checker, p: Any, where: str, need_value: bool) -> None:
    c.obj(p, where)
    if need_value:
        if "value" not in p:
            c.fail(where, 'missing "value"')
        c.num(p["value"], f"{where}.value")
    for key in ("runs", "successes"):
        if key not in p:
            c.fail(where, f'missing "{key}"')
        c.num(p[key], f"{where}.{key}", nullable=False)
    for key in _POINT_NUMBERS:
        c.num(p.get(key), f"{where}.{key}")
    oh = p.get("overhead")
    if oh is not None:
        c.obj(oh, f"{where}.overhead")
        for key in _OVERHEAD_NUMBERS:
            c.num(oh.get(key), f"{where}.overhead.{key}")
    c.text(p.get("config_hash"), f"{where}.config_hash", nullable=True)


def _check_summary(data: Any, path: Path) -> dict:
    c = _Checker(path)
    if not isinstance(data, dict):
        raise ReportError(f"{path}: expected a JSON object at the top, got {_json_type(data)}")
    if "plumetrace_summary" not in data:
        raise ReportError(f'{path}: not a plumetrace summary (no "plumetrace_summary" key)')
    if data["plumetrace_summary"] != SUMMARY_FORMAT:
        raise ReportError(
            f"{path}: summary format {data['plumetrace_summary']!r} is not supported "
            f"(this report reads format {SUMMARY_FORMAT})"
        )
    for key in ("version", "generated_by", "preset", "config_toml"):
        c.text(data.get(key), key, nullable=True)
    for key in ("seed", "runs_per_point", "total_runs", "elapsed_s", "threads"):
        c.num(data.get(key), key)

    if "sets" not in data:
        raise ReportError(f'{path}: missing "sets"')
    for i, s in enumerate(c.lst(data["sets"], "sets")):
        where = f"sets[{i}]"
        c.obj(s, where)
        c.text(s.get("name"), f"{where}.name")
        for key in ("title", "algorithm", "key", "label"):
            c.text(s.get(key), f"{where}.{key}", nullable=True)
        c.num(s.get("fixed_index"), f"{where}.fixed_index")
        if "values" in s:
            c.numbers(s["values"], f"{where}.values")
        for j, p in enumerate(c.lst(s.get("points"), f"{where}.points")):
            _check_point(c, p, f"{where}.points[{j}]", need_value=True)

    for i, cl in enumerate(c.lst(data.get("claims") or [], "claims")):
        where = f"claims[{i}]"
        c.obj(cl, where)
        c.text(cl.get("text"), f"{where}.text")
        c.text(cl.get("verdict"), f"{where}.verdict")
        c.text(cl.get("evidence"), f"{where}.evidence", nullable=True)

    sens = data.get("sensitivity")
    if sens is not None:
        c.obj(sens, "sensitivity")
        for i, v in enumerate(c.lst(sens.get("variants") or [], "sensitivity.variants")):
            c.text(v, f"sensitivity.variants[{i}]")
        for i, row in enumerate(c.lst(sens.get("rows") or [], "sensitivity.rows")):
            where = f"sensitivity.rows[{i}]"
            _check_point(c, row, where, need_value=False)
            c.text(row.get("algorithm"), f"{where}.algorithm")
            c.text(row.get("variant"), f"{where}.variant")

    for i, t in enumerate(c.lst(data.get("trajectories") or [], "trajectories")):
        where = f"trajectories[{i}]"
        c.obj(t, where)
        c.text(t.get("algorithm"), f"{where}.algorithm")
        xs = c.numbers(t.get("x"), f"{where}.x")
        ys = c.numbers(t.get("y"), f"{where}.y")
        if len(xs) != len(ys):
            c.fail(where, f"x has {len(xs)} entries but y has {len(ys)}")
        for key in ("state", "odor"):
            if t.get(key) is not None and len(c.lst(t[key], f"{where}.{key}")) != len(xs):
                c.fail(f"{where}.{key}", f"has {len(t[key])} entries, x has {len(xs)}")
    for i, m in enumerate(c.lst(data.get("trajectories_missing") or [], "trajectories_missing")):
        c.text(m, f"trajectories_missing[{i}]")

    if data.get("detection_map") is not None:
        _check_map(c, data["detection_map"], "detection_map")

    for key, fields in (("arena", ("x_min", "x_max", "y_min", "y_max")),
                        ("source", ("x", "y", "radius", "success_radius"))):
        if data.get(key) is not None:
            c.obj(data[key], key)
            for f in fields:
                c.num(data[key].get(f), f"{key}.{f}")

    for i, r in enumerate(c.lst(data.get("readings") or [], "readings")):
        where = f"readings[{i}]"
        c.obj(r, where)
        c.text(r.get("name"), f"{where}.name")
        c.text(r.get("file"), f"{where}.file", nullable=True)
        for key in ("held", "not_held", "unclear", "success_radius"):
            c.num(r.get(key), f"{where}.{key}")
        if r.get("settings") is not None:
            c.obj(r["settings"], f"{where}.settings")
        for j, cl in enumerate(c.lst(r.get("claims") or [], f"{where}.claims")):
            c.obj(cl, f"{where}.claims[{j}]")
            c.text(cl.get("verdict"), f"{where}.claims[{j}].verdict")
        for j, p in enumerate(c.lst(r.get("fixed") or [], f"{where}.fixed")):
            _check_point(c, p, f"{where}.fixed[{j}]", need_value=False)
            c.text(p.get("algorithm"), f"{where}.fixed[{j}].algorithm")
        if r.get("detection_map") is not None:
            _check_map(c, r["detection_map"], f"{where}.detection_map")

    fails = data.get("failures")
    if fails is not None:
        c.obj(fails, "failures")
        for i, a in enumerate(c.lst(fails.get("algorithms") or [], "failures.algorithms")):
            where = f"failures.algorithms[{i}]"
            c.obj(a, where)
            c.text(a.get("algorithm"), f"{where}.algorithm")
            for key in FAILURE_NUMBERS:
                c.num(a.get(key), f"{where}.{key}")

    for i, sw in enumerate(c.lst(data.get("sweeps") or [], "sweeps")):
        c.obj(sw, f"sweeps[{i}]")
    return data


FAILURE_NUMBERS = ("runs", "failed", "walls", "timeouts", "gave_up", "examined", "end_upwind",
                   "end_upwind_wall", "end_within_1m", "passed_source", "came_within_0_5m",
                   "closest_median_m", "end_distance_median_m")


def _check_map(c: "_Checker", dmap: Any, where: str) -> None:
    c.obj(dmap, where)
    xs = c.numbers(dmap.get("x"), f"{where}.x")
    ys = c.numbers(dmap.get("y"), f"{where}.y")
    rows = c.lst(dmap.get("fraction"), f"{where}.fraction")
    if len(rows) != len(ys):
        c.fail(f"{where}.fraction", f"has {len(rows)} rows, y has {len(ys)} entries")
    for j, row in enumerate(rows):
        if len(c.numbers(row, f"{where}.fraction[{j}]")) != len(xs):
            c.fail(f"{where}.fraction[{j}]", f"has {len(row)} entries, x has {len(xs)}")


def _check_sensitivity(data: Any, path: Path) -> dict:
    c = _Checker(path)
    if not isinstance(data, dict):
        raise ReportError(f"{path}: expected a JSON object at the top, got {_json_type(data)}")
    if "plumetrace_sensitivity" not in data:
        raise ReportError(
            f'{path}: not a plumetrace sensitivity file (no "plumetrace_sensitivity" key)')
    if data["plumetrace_sensitivity"] != SENSITIVITY_FORMAT:
        raise ReportError(
            f"{path}: sensitivity format {data['plumetrace_sensitivity']!r} is not supported "
            f"(this report reads format {SENSITIVITY_FORMAT})"
        )
    c.num(data.get("runs_per_point"), "runs_per_point")
    c.num(data.get("elapsed_s"), "elapsed_s")
    claims = c.lst(data.get("claims") or [], "claims")
    for i, cl in enumerate(claims):
        c.obj(cl, f"claims[{i}]")
        c.text(cl.get("text"), f"claims[{i}].text")
    if "rows" not in data:
        raise ReportError(f'{path}: missing "rows"')
    for i, row in enumerate(c.lst(data["rows"], "rows")):
        where = f"rows[{i}]"
        c.obj(row, where)
        c.text(row.get("noise_mode"), f"{where}.noise_mode", nullable=True)
        c.text(row.get("kernel"), f"{where}.kernel", nullable=True)
        c.num(row.get("success_radius"), f"{where}.success_radius")
        verdicts = c.lst(row.get("verdicts"), f"{where}.verdicts")
        for j, v in enumerate(verdicts):
            c.text(v, f"{where}.verdicts[{j}]")
        if claims and len(verdicts) != len(claims):
            c.fail(f"{where}.verdicts", f"has {len(verdicts)} entries for {len(claims)} claims")
        c.num(row.get("held"), f"{where}.held")
    return data


# --------------------------------------------------------------------------------------------
# Normalised views of the data


def _num(v: Any) -> Optional[float]:
    """A finite float, or None for null, missing or non-finite values."""
    if not _is_number(v):
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def _int(v: Any) -> Optional[int]:
    x = _num(v)
    return None if x is None else int(round(x))


def wilson_interval(successes: int, runs: int, z: float = 1.959963984540054):
    """The Wilson score interval for a binomial proportion (95% by default)."""
    if runs <= 0:
        return None, None
    p = successes / runs
    denom = 1.0 + z * z / runs
    centre = (p + z * z / (2 * runs)) / denom
    half = z * math.sqrt(p * (1 - p) / runs + z * z / (4 * runs * runs)) / denom
    return max(0.0, centre - half), min(1.0, centre + half)


@dataclass
class Point:
    """One sweep point (or one sensitivity row) with every field made safe to use."""

    value: Optional[float]
    runs: int
    successes: int
    walls: Optional[int]
    timeouts: Optional[int]
    gave_up: Optional[int]
    rate: Optional[float]
    rate_lo: Optional[float]
    rate_hi: Optional[float]
    oh_n: int
    oh_mean: Optional[float]
    oh_lo: Optional[float]  # the interval the report shows: bootstrap when given, else t
    oh_hi: Optional[float]
    oh_median: Optional[float]
    oh_q1: Optional[float]
    oh_q3: Optional[float]
    mean_time: Optional[float]
    mean_losses: Optional[float]
    config_hash: Optional[str]

    @staticmethod
    def from_json(p: dict) -> "Point":
        runs = _int(p.get("runs")) or 0
        successes = _int(p.get("successes")) or 0
        rate = _num(p.get("success_rate"))
        if rate is None and runs > 0:
            rate = successes / runs
        lo, hi = _num(p.get("success_lo")), _num(p.get("success_hi"))
        if (lo is None or hi is None) and runs > 0:
            lo, hi = wilson_interval(successes, runs)
        oh = p.get("overhead") or {}
        oh_n = _int(oh.get("n"))
        return Point(
            value=_num(p.get("value")),
            runs=runs,
            successes=successes,
            walls=_int(p.get("walls")),
            timeouts=_int(p.get("timeouts")),
            gave_up=_int(p.get("gave_up")),
            rate=rate,
            rate_lo=lo,
            rate_hi=hi,
            oh_n=successes if oh_n is None else oh_n,
            oh_mean=_num(oh.get("mean")),
            oh_lo=_num(oh.get("boot_lo")) if "boot_lo" in oh else _num(oh.get("lo")),
            oh_hi=_num(oh.get("boot_hi")) if "boot_hi" in oh else _num(oh.get("hi")),
            oh_median=_num(oh.get("median")),
            oh_q1=_num(oh.get("q1")),
            oh_q3=_num(oh.get("q3")),
            mean_time=_num(p.get("mean_time")),
            mean_losses=_num(p.get("mean_losses")),
            config_hash=p.get("config_hash"),
        )


@dataclass
class SweepSet:
    name: str
    title: str
    algorithm: str
    key: str
    label: str
    fixed_index: Optional[int]
    points: list

    @staticmethod
    def from_json(s: dict) -> "SweepSet":
        points = [Point.from_json(p) for p in s.get("points") or []]
        fixed = _int(s.get("fixed_index"))
        if fixed is not None and not 0 <= fixed < len(points):
            fixed = None
        return SweepSet(
            name=str(s["name"]),
            title=s.get("title") or "",
            algorithm=s.get("algorithm") or "",
            key=s.get("key") or "",
            label=s.get("label") or s.get("key") or "value",
            fixed_index=fixed,
            points=points,
        )

    @property
    def fixed_value(self) -> Optional[float]:
        return None if self.fixed_index is None else self.points[self.fixed_index].value



# The paper's own sentence behind each of the eleven claims (Lochmatter & Martinoli 2008,
# sections 4 and 5; docs/claims.md states each claim and gives its reading and test).
PAPER_QUOTES = {
    1: "The surge-spiral algorithm is extremely robust and virtually all 1350 runs succeeded.",
    2: "Small angles yield a low distance overhead, but also a low success rate. In our setup, "
       "only configurations with \u03b2 > 20\u00b0 resulted in acceptable success rates.",
    3: "On one end of the scale, the success rate drops significantly, whereas on the other "
       "end, the performance gets worse.",
    4: "The accuracy of the wind sensor only has a marginal impact on the performance, and no "
       "visible influence on the robustness as long as the accuracy is good enough. If the noise "
       "is too high, however, the algorithm does not work at all.",
    5: "As expected, a small spiral gap is advantageous, at least as long as the robot "
       "reacquires the plume within one turn.",
    6: "Figure 8 (E) also suggests that higher d_lost yield slightly better performance.",
    7: "Wind sensor accuracy only affects the distance overhead of surge-spiral, and not its "
       "success rate.",
    8: "The distance overhead grows almost linearly with the cast distance, but at a fairly low "
       "rate. Furthermore, for very low cast distances, the algorithm fails to work reliably.",
    9: "The wind sensor noise seems to mainly affect the success rate.",
    10: "The casting algorithm remains the worst among the three algorithm in terms of distance "
        "overhead and success ratio. The results obtained with the surge-cast algorithm are "
        "comparable to those of the surge-spiral algorithm.",
    11: "The plume lost distance, d_lost, does not have a significant influence on the "
        "performance of the algorithms. Well-chosen upwind angles, spiral gap or cast distances "
        "are much more important.",
}

# The repository's root, whose docs the report links: this file is python/plumetrace/report.py
# there, or a copy in BUILD/python/plumetrace/ of a build folder inside it.
REPO_ROOT = next((p for p in Path(__file__).resolve().parents[1:4]
                  if (p / "docs").is_dir() and (p / "experiments").is_dir()),
                 Path(__file__).resolve().parents[2])

OUTCOME_COLORS = {"success": "#4c9a4c", "wall": "#d9534f", "timeout": "#f0ad4e",
                  "gave_up": "#8c6bb1"}


# --------------------------------------------------------------------------------------------
# Number formatting


def fmt_value(v: Optional[float]) -> str:
    if v is None:
        return DASH
    if v == int(v) and abs(v) < 1e15:
        return str(int(v))
    return f"{v:.6g}"


def fmt_raw_int(v: Any) -> str:
    """An integer field (a seed, a trial) exactly as the file gives it, even above 2**53."""
    if isinstance(v, int) and not isinstance(v, bool):
        return str(v)
    return fmt_value(_num(v))


def fmt_pct(v: Optional[float]) -> str:
    return DASH if v is None else f"{100 * v:.0f}%"


def fmt_rate(p: Point) -> str:
    if p.rate is None:
        return DASH
    if p.rate_lo is None or p.rate_hi is None:
        return fmt_pct(p.rate)
    return f"{fmt_pct(p.rate)} [{100 * p.rate_lo:.0f}, {100 * p.rate_hi:.0f}]"


def fmt_oh(v: Optional[float]) -> str:
    return DASH if v is None else f"{v:.2f}"


def fmt_overhead(p: Point) -> str:
    if p.oh_mean is None:
        return "no successful run" if p.oh_n == 0 else DASH
    if p.oh_lo is None or p.oh_hi is None:
        return fmt_oh(p.oh_mean)
    return f"{fmt_oh(p.oh_mean)} [{fmt_oh(p.oh_lo)}, {fmt_oh(p.oh_hi)}]"


def fmt_median(p: Point) -> str:
    if p.oh_median is None:
        return DASH
    if p.oh_q1 is None or p.oh_q3 is None:
        return fmt_oh(p.oh_median)
    return f"{fmt_oh(p.oh_median)} [{fmt_oh(p.oh_q1)}, {fmt_oh(p.oh_q3)}]"


def fmt_count(v: Optional[int]) -> str:
    return DASH if v is None else str(v)


def fmt_outcomes(p: Point) -> str:
    return " / ".join(fmt_count(v) for v in (p.successes, p.walls, p.timeouts, p.gave_up))


def fmt_duration(seconds: Optional[float]) -> str:
    if seconds is None:
        return DASH
    if seconds < 60:
        return f"{seconds:.1f} s"
    minutes, sec = divmod(int(round(seconds)), 60)
    hours, minutes = divmod(minutes, 60)
    parts = f"{hours} h {minutes} min" if hours else f"{minutes} min {sec} s"
    return f"{seconds:.1f} s ({parts})"


def verdict_style(verdict: Optional[str]):
    return VERDICT_STYLE.get((verdict or "").strip().lower(), OTHER_VERDICT)


# --------------------------------------------------------------------------------------------
# Figures


def _new_figure(width: float, height: float) -> Figure:
    fig = Figure(figsize=(width, height), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _save(fig: Figure, path: Path) -> Path:
    fig.savefig(path, format="png", dpi=DPI)
    return path


def _bar_colors(n: int, fixed: Optional[int]) -> list:
    return [FIXED_COLOR if i == fixed else BAR_COLOR for i in range(n)]


def _asym_err(centre: Sequence[Optional[float]], lo, hi, scale: float = 1.0):
    """Error-bar extents (2 x n); zero where the interval is undefined."""
    below, above = [], []
    for c, l, h in zip(centre, lo, hi):
        if c is None or l is None or h is None:
            below.append(0.0)
            above.append(0.0)
        else:
            below.append(max(0.0, (c - l) * scale))
            above.append(max(0.0, (h - c) * scale))
    return np.array([below, above])


def _overhead_axis(ax, x, points: Sequence[Point], colors: Sequence[str], label_n: bool = True):
    """Overhead bars from 1 (the straight-line optimum) with bootstrap intervals and medians.

    Returns the indices of points that have no mean overhead (no successful run).
    """
    means = [p.oh_mean for p in points]
    have = [i for i, m in enumerate(means) if m is not None]
    missing = [i for i, m in enumerate(means) if m is None]
    if have:
        hx = np.asarray(x, dtype=float)[have]
        heights = [means[i] - 1.0 for i in have]
        ax.bar(hx, heights, bottom=1.0, width=0.7, color=[colors[i] for i in have],
               edgecolor="#333333", linewidth=0.4, zorder=2)
        err = _asym_err([means[i] for i in have], [points[i].oh_lo for i in have],
                        [points[i].oh_hi for i in have])
        ax.errorbar(hx, [means[i] for i in have], yerr=err, fmt="none", ecolor="black",
                    elinewidth=1, capsize=3, zorder=3)
        med = [(xi, points[i].oh_median) for xi, i in zip(hx, have)
               if points[i].oh_median is not None]
        if med:
            ax.plot([m[0] for m in med], [m[1] for m in med], linestyle="none", marker="D",
                    markersize=4, color="#f2b134", markeredgecolor="black", markeredgewidth=0.5,
                    zorder=4, label="median")
        tops = [points[i].oh_hi if points[i].oh_hi is not None else means[i] for i in have]
        lows = [points[i].oh_lo if points[i].oh_lo is not None else means[i] for i in have]
        top = max(tops + [1.0])
        bottom = min(lows + [1.0])
        span = max(top - bottom, 0.05)
        ax.set_ylim(min(1.0, bottom) - 0.05 * span, top + 0.18 * span)
        if label_n:
            for xi, i, t in zip(hx, have, tops):
                ax.annotate(f"n={points[i].oh_n}", (xi, t), xytext=(0, 2),
                            textcoords="offset points", ha="center", va="bottom", fontsize=7)
    else:
        ax.set_ylim(0.95, 1.5)
        ax.text(0.5, 0.5, "no successful runs", transform=ax.transAxes, ha="center",
                va="center", color=MISSING_COLOR)
    lo_y = ax.get_ylim()[0]
    for i in missing:
        ax.text(x[i], lo_y, " none", rotation=90, ha="center", va="bottom", fontsize=7,
                color=MISSING_COLOR)
    ax.axhline(1.0, color="#555555", linewidth=0.6, zorder=1)
    ax.set_ylabel("distance overhead $d_t/d_u$")
    return missing


def set_figure(s: SweepSet, path: Path) -> Path:
    """The paper's two panels for one set: success rate, and overhead of the successful runs."""
    fig = _new_figure(10, 3.9)
    grid_spec = fig.add_gridspec(2, 2, height_ratios=[14, 1])
    ax_rate, ax_oh = fig.add_subplot(grid_spec[0, 0]), fig.add_subplot(grid_spec[0, 1])
    ax_legend = fig.add_subplot(grid_spec[1, :])
    ax_legend.axis("off")
    n = len(s.points)
    x = np.arange(n)
    colors = _bar_colors(n, s.fixed_index)
    ticks = [fmt_value(p.value) for p in s.points]

    rates = [p.rate for p in s.points]
    ax_rate.bar(x, [100 * r if r is not None else 0.0 for r in rates], width=0.7, color=colors,
                edgecolor="#333333", linewidth=0.4, zorder=2)
    err = _asym_err(rates, [p.rate_lo for p in s.points], [p.rate_hi for p in s.points], 100)
    ax_rate.errorbar(x, [100 * r if r is not None else 0.0 for r in rates], yerr=err, fmt="none",
                     ecolor="black", elinewidth=1, capsize=3, zorder=3)
    for xi, p in zip(x, s.points):
        top = 100 * (p.rate_hi if p.rate_hi is not None else (p.rate or 0.0))
        ax_rate.annotate(f"{p.successes}/{p.runs}", (xi, top), xytext=(0, 2),
                         textcoords="offset points", ha="center", va="bottom", fontsize=7)
    if n == 0:
        ax_rate.text(0.5, 0.5, "no points in this set", transform=ax_rate.transAxes,
                     ha="center", va="center", color=MISSING_COLOR)
    ax_rate.set_ylim(0, 112)
    ax_rate.set_yticks(range(0, 101, 20))
    ax_rate.set_ylabel("success rate (%)")
    ax_rate.set_title(f"{s.name}: success rate (Wilson 95%)", fontsize=10)

    _overhead_axis(ax_oh, x, s.points, colors)
    ax_oh.set_title(f"{s.name}: overhead of successful runs (bootstrap 95%)", fontsize=10)

    for ax in (ax_rate, ax_oh):
        ax.set_xticks(x)
        ax.set_xticklabels(ticks, fontsize=8)
        ax.set_xlabel(s.label)
        ax.set_xlim(-0.6, n - 0.4)
        ax.grid(axis="y", color="#e5e5e5", zorder=0)
        ax.set_axisbelow(True)
        if s.fixed_index is not None:
            ax.get_xticklabels()[s.fixed_index].set_fontweight("bold")
    handles = [Patch(color=BAR_COLOR, label="varied value")]
    if s.fixed_index is not None:
        handles.append(Patch(color=FIXED_COLOR, label="fixed value"))
    handles.append(Line2D([], [], color="black", marker="_", markersize=8, linewidth=1,
                          label="95% interval"))
    if any(p.oh_median is not None for p in s.points):
        handles.append(Line2D([], [], linestyle="none", marker="D", markersize=4,
                              color="#f2b134", markeredgecolor="black", label="median overhead"))
    ax_legend.legend(handles=handles, loc="center", ncol=len(handles), fontsize=8, frameon=False)
    return _save(fig, path)


def _state_palette(states: Iterable[str]) -> dict:
    palette, extra = {}, 0
    for st in states:
        if st in palette:
            continue
        if st in STATE_COLORS:
            palette[st] = STATE_COLORS[st]
        else:
            palette[st] = EXTRA_STATE_COLORS[extra % len(EXTRA_STATE_COLORS)]
            extra += 1
    return palette


def _elapsed_text(summary: dict) -> str:
    """The run time of the command that wrote the summary, and how many of its runs it
    computed: a report redrawn from a full store took no time to run anything."""
    text = fmt_duration(_num(summary.get("elapsed_s")))
    computed, total = _num(summary.get("computed_runs")), _num(summary.get("total_runs"))
    if computed is not None and total is not None and computed < total:
        text += (f" ({fmt_value(computed)} runs computed by this command, "
                 f"{fmt_value(total - computed)} read from the results store)")
    return text


def _wind_text(summary: dict) -> str:
    """The main reading's wind as the figures state it; older summaries do not carry it."""
    wind = summary.get("wind") or {}
    vx, vy = wind.get("vx"), wind.get("vy")
    if not _is_number(vx):
        return "(wind along +x)"
    if _is_number(vy) and vy != 0.0:
        return f"(wind {vx:g}, {vy:g} m/s)"
    return f"(wind {vx:g} m/s along +x)"


def _trajectory_panels(summary: dict) -> list:
    """(algorithm, "success" or "failure", trajectory or None): per algorithm in the paper's
    order (then any other), a successful run and a failed one."""
    first = {}
    for t in summary.get("trajectories") or []:
        kind = "success" if (t.get("outcome") or "success") == "success" else "failure"
        first.setdefault((t["algorithm"], kind), t)
    algorithms = list(ALGORITHMS) + [a for a, _ in first if a not in ALGORITHMS]
    panels = []
    for a in dict.fromkeys(algorithms):
        panels.append((a, "success", first.get((a, "success"))))
        if (a, "failure") in first or summary.get("failures") is not None:
            panels.append((a, "failure", first.get((a, "failure"))))
    return panels


def _arena(summary: dict):
    a = summary.get("arena") or {}
    get = lambda k, d: _num(a.get(k)) if _num(a.get(k)) is not None else d  # noqa: E731
    return get("x_min", 0.0), get("x_max", 16.0), get("y_min", -2.0), get("y_max", 2.0)


def trajectory_figure(summary: dict, path: Path) -> Path:
    """Fig. 6: per algorithm a successful and a failed run over the detection map."""
    panels = _trajectory_panels(summary)
    x_min, x_max, y_min, y_max = _arena(summary)
    aspect = (y_max - y_min) / max(x_max - x_min, 1e-9)
    fig = _new_figure(10, len(panels) * (8.3 * aspect + 0.6) + 0.3)
    axes = fig.subplots(len(panels), 1, squeeze=False)[:, 0]

    dmap = summary.get("detection_map")
    src = summary.get("source") or {}
    sx, sy = _num(src.get("x")), _num(src.get("y"))
    radius, success_radius = _num(src.get("radius")), _num(src.get("success_radius"))
    mesh = None
    for ax, (alg, kind, traj) in zip(axes, panels):
        if dmap is not None and dmap["x"] and dmap["y"]:
            frac = np.array([[np.nan if v is None else v for v in row] for row in dmap["fraction"]],
                            dtype=float)
            vmax = np.nanmax(frac) if np.isfinite(frac).any() else 1.0
            mesh = ax.pcolormesh(np.asarray(dmap["x"], float), np.asarray(dmap["y"], float), frac,
                                 shading="nearest", cmap=ODOR_CMAP, vmin=0.0,
                                 vmax=max(float(vmax), 1e-9), rasterized=True, zorder=0)
        if sx is not None and sy is not None:
            if radius is not None:
                ax.add_patch(Circle((sx, sy), radius, facecolor="#b2182b", edgecolor="black",
                                    linewidth=0.5, zorder=3))
            if success_radius is not None:
                ax.add_patch(Circle((sx, sy), success_radius, fill=False, edgecolor="#b2182b",
                                    linestyle="--", linewidth=1.0, zorder=3))
        if traj is not None and len(traj["x"]) > 0:
            _draw_trajectory(ax, traj)
            bits = [f"set {traj['set']}" if traj.get("set") else None,
                    f"trial {traj['trial']}" if traj.get("trial") is not None else None,
                    f"overhead {traj['overhead']:.2f}"
                    if kind == "success" and _num(traj.get("overhead")) is not None else None,
                    f"closest {traj['closest_m']:.2f} m to the source"
                    if kind == "failure" and _num(traj.get("closest_m")) is not None else None]
            label = ("succeeded" if kind == "success"
                     else f"failed ({str(traj.get('outcome') or '?').replace('_', ' ')})")
            ax.set_title(f"{alg}, {label}: " + ", ".join(b for b in bits if b), fontsize=10,
                         color="black" if kind == "success" else "#a33")
        else:
            what = "successful" if kind == "success" else "failed"
            ax.set_title(f"{alg}: no {what} run at the fixed values", fontsize=10,
                         color="#a33" if kind == "success" else "black")
            ax.text(0.5, 0.5, f"no {what} run", transform=ax.transAxes, ha="center",
                    va="center", color="#a33", fontsize=12, zorder=6,
                    bbox=dict(facecolor="white", edgecolor="#a33", boxstyle="round"))
        ax.set_xlim(x_min, x_max)
        ax.set_ylim(y_min, y_max)
        ax.set_aspect("equal")
        ax.set_ylabel("y (m)")
        ax.tick_params(labelsize=8)
    axes[-1].set_xlabel("x (m), downwind \u2192 " + _wind_text(summary))
    if mesh is not None:
        cbar = fig.colorbar(mesh, ax=list(axes), shrink=0.6, pad=0.01)
        cbar.set_label("fraction of instants with odor", fontsize=8)
        cbar.ax.tick_params(labelsize=7)
    return _save(fig, path)


def _draw_trajectory(ax, traj: dict) -> None:
    xy = np.column_stack([np.asarray(traj["x"], float), np.asarray(traj["y"], float)])
    states = traj.get("state")
    if states is None or len(xy) < 2:
        ax.plot(xy[:, 0], xy[:, 1], color=STATE_COLORS["surge"], linewidth=1.2, zorder=4)
        handles = []
    else:
        labels = [str(s) for s in states]
        palette = _state_palette(labels)
        segments = np.stack([xy[:-1], xy[1:]], axis=1)
        lc = LineCollection(segments, colors=[palette[s] for s in labels[:-1]], linewidths=1.3,
                            zorder=4)
        ax.add_collection(lc)
        handles = [Line2D([], [], color=c, linewidth=2, label=s) for s, c in palette.items()]
    ax.plot(xy[0, 0], xy[0, 1], marker="<", markersize=7, color="#2ca02c",
            markeredgecolor="black", linestyle="none", zorder=5)
    ax.plot(xy[-1, 0], xy[-1, 1], marker="o", markersize=5, color="white",
            markeredgecolor="black", linestyle="none", zorder=5)
    handles += [Line2D([], [], marker="<", color="#2ca02c", markeredgecolor="black",
                       linestyle="none", label="start"),
                Line2D([], [], marker="o", color="white", markeredgecolor="black",
                       linestyle="none", label="end")]
    ax.legend(handles=handles, fontsize=7, loc="lower right", framealpha=0.85, ncol=2)


def _sensitivity_grid(sens: dict):
    """(variants, algorithms, {(algorithm, variant): Point}) in a stable order."""
    rows = sens.get("rows") or []
    variants = list(sens.get("variants") or [])
    for r in rows:
        if r["variant"] not in variants:
            variants.append(r["variant"])
    algorithms = [a for a in ALGORITHMS if any(r["algorithm"] == a for r in rows)]
    algorithms += [a for a in dict.fromkeys(r["algorithm"] for r in rows) if a not in algorithms]
    grid = {(r["algorithm"], r["variant"]): Point.from_json(r) for r in rows}
    return variants, algorithms, grid


def sensitivity_figure(sens: dict, path: Path) -> Path:
    """Grouped bars: success rate and overhead per algorithm, one bar per variant."""
    variants, algorithms, grid = _sensitivity_grid(sens)
    fig = _new_figure(10, 4.4)
    grid_spec = fig.add_gridspec(2, 2, height_ratios=[10, 1])
    ax_rate, ax_oh = fig.add_subplot(grid_spec[0, 0]), fig.add_subplot(grid_spec[0, 1])
    ax_legend = fig.add_subplot(grid_spec[1, :])
    ax_legend.axis("off")
    nv = max(len(variants), 1)
    width = 0.8 / nv
    cmap = colormaps["tab10"]
    for k, variant in enumerate(variants):
        offset = (k - (nv - 1) / 2) * width
        color = cmap(k % 10)
        for ai, alg in enumerate(algorithms):
            p = grid.get((alg, variant))
            if p is None:
                continue
            xi = ai + offset
            if p.rate is not None:
                ax_rate.bar(xi, 100 * p.rate, width=width, color=color, edgecolor="#333333",
                            linewidth=0.3, zorder=2, label=variant if ai == 0 else None)
                err = _asym_err([p.rate], [p.rate_lo], [p.rate_hi], 100)
                ax_rate.errorbar([xi], [100 * p.rate], yerr=err, fmt="none", ecolor="black",
                                 elinewidth=0.8, capsize=2, zorder=3)
            if p.oh_mean is not None:
                ax_oh.bar(xi, p.oh_mean - 1.0, bottom=1.0, width=width, color=color,
                          edgecolor="#333333", linewidth=0.3, zorder=2)
                err = _asym_err([p.oh_mean], [p.oh_lo], [p.oh_hi])
                ax_oh.errorbar([xi], [p.oh_mean], yerr=err, fmt="none", ecolor="black",
                               elinewidth=0.8, capsize=2, zorder=3)
            else:
                ax_oh.text(xi, 1.0, " none", rotation=90, ha="center", va="bottom", fontsize=6,
                           color=MISSING_COLOR)
    ax_rate.set_ylim(0, 105)
    ax_rate.set_ylabel("success rate (%)")
    ax_rate.set_title("success rate (Wilson 95%)", fontsize=10)
    ax_oh.axhline(1.0, color="#555555", linewidth=0.6, zorder=1)
    ax_oh.set_ylabel("distance overhead $d_t/d_u$")
    ax_oh.set_title("overhead of successful runs (bootstrap 95%)", fontsize=10)
    for ax in (ax_rate, ax_oh):
        ax.set_xticks(range(len(algorithms)))
        ax.set_xticklabels(algorithms)
        ax.set_xlim(-0.5, len(algorithms) - 0.5)
        ax.grid(axis="y", color="#e5e5e5", zorder=0)
        ax.set_axisbelow(True)
    if variants:
        ax_legend.legend(*ax_rate.get_legend_handles_labels(), loc="center",
                         ncol=min(len(variants), 5), fontsize=8, frameon=False)
    return _save(fig, path)


def _combination_label(row: dict) -> str:
    radius = _num(row.get("success_radius"))
    return " \u00b7 ".join([str(row.get("noise_mode") or DASH), str(row.get("kernel") or DASH),
                            DASH if radius is None else f"r={fmt_value(radius)}"])


def claims_matrix_figure(sens: dict, path: Path) -> Path:
    """The sensitivity claims matrix as a picture: one row per combination, one column per claim."""
    rows = sens["rows"]
    n_claims = max([len(sens.get("claims") or [])] + [len(r["verdicts"]) for r in rows] + [1])
    rgb = np.ones((max(len(rows), 1), n_claims, 3))
    fig = _new_figure(8.5, 1.6 + 0.26 * max(len(rows), 1))
    grid_spec = fig.add_gridspec(2, 1, height_ratios=[0.26 * max(len(rows), 1) + 0.6, 0.35])
    ax = fig.add_subplot(grid_spec[0])
    ax_legend = fig.add_subplot(grid_spec[1])
    ax_legend.axis("off")
    for i, row in enumerate(rows):
        for j in range(n_claims):
            verdict = row["verdicts"][j] if j < len(row["verdicts"]) else None
            _, color, symbol = verdict_style(verdict)
            rgb[i, j] = to_rgb(color)
            ax.text(j, i, symbol, ha="center", va="center", fontsize=8)
    ax.imshow(rgb, aspect="auto", interpolation="nearest")
    ax.set_xticks(range(n_claims))
    ax.set_xticklabels([str(j + 1) for j in range(n_claims)], fontsize=8)
    ax.xaxis.tick_top()
    ax.xaxis.set_label_position("top")
    ax.set_xlabel("claim (docs/claims.md)", fontsize=8)
    ax.set_yticks(range(len(rows)))
    labels = []
    for row in rows:
        held = _int(row.get("held"))
        if held is None:
            held = sum(verdict_style(v)[0] == "holds" for v in row["verdicts"])
        labels.append(f"{_combination_label(row)}   ({held} held)")
    ax.set_yticklabels(labels, fontsize=7)
    ax.set_xticks(np.arange(-0.5, n_claims, 1), minor=True)
    ax.set_yticks(np.arange(-0.5, len(rows), 1), minor=True)
    ax.grid(which="minor", color="white", linewidth=1.2)
    ax.tick_params(which="minor", length=0)
    handles = [Patch(color=VERDICT_STYLE[v][1], label=f"{VERDICT_STYLE[v][2]} {v}")
               for v in VERDICT_STYLE]
    ax_legend.legend(handles=handles, loc="center", ncol=3, fontsize=8, frameon=False)
    return _save(fig, path)


# --------------------------------------------------------------------------------------------
# A tiny document model rendered to both HTML and Markdown, so both have the same sections


@dataclass
class Cell:
    text: str
    cls: Optional[str] = None
    title: Optional[str] = None
    num: bool = False


CellLike = Union[str, Cell]


@dataclass
class Para:
    spans: list  # str, ("code" | "b", text) or ("a", text, "#anchor")


@dataclass
class Table:
    header: Optional[list]  # None: no header row (Markdown still needs one; it stays empty)
    rows: list  # list of list of CellLike
    row_classes: list = field(default_factory=list)
    caption: Optional[str] = None


@dataclass
class Fig:
    path: Path  # absolute
    rel: str  # relative to the output folder, with forward slashes
    caption: str
    alt: str


@dataclass
class Pre:
    text: str
    lang: str = ""


@dataclass
class Bullets:
    items: list  # each a list of spans


@dataclass
class Section:
    anchor: str
    title: str
    blocks: list
    level: int = 2


def _cell(c: CellLike) -> Cell:
    return c if isinstance(c, Cell) else Cell(str(c))


# ---- HTML

CSS = """
body { font-family: -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, sans-serif;
       color: #222; max-width: 1100px; margin: 1.5em auto; padding: 0 1.2em; line-height: 1.45; }
h1 { font-size: 1.7em; margin-bottom: 0.2em; }
h2 { border-bottom: 2px solid #ddd; padding-bottom: 0.15em; margin-top: 2em; }
h3 { margin-top: 1.6em; }
table { border-collapse: collapse; margin: 0.6em 0 1.2em; font-size: 0.88em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.55em; text-align: left; vertical-align: top; }
th { background: #eef1f5; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td.mono, code { font-family: "SFMono-Regular", Consolas, "Liberation Mono", monospace;
                font-size: 0.92em; }
tr.fixed td { background: #eef4fb; font-weight: 600; }
td.holds { background: #c8e6c9; } td.fails { background: #ffcdd2; }
td.unclear { background: #ffe0a3; } td.other { background: #e0e0e0; }
td.verdict { font-weight: 600; white-space: nowrap; }
td.cell { text-align: center; min-width: 1.6em; }
figure { margin: 0.8em 0 1.2em; }
figure img { max-width: 100%; height: auto; border: 1px solid #e3e3e3; }
figcaption { font-size: 0.88em; color: #444; margin-top: 0.3em; }
pre { background: #f6f8fa; border: 1px solid #ddd; padding: 0.8em; overflow: auto;
      font-size: 0.82em; line-height: 1.35; }
nav.toc { background: #f7f7f7; border: 1px solid #e2e2e2; padding: 0.4em 1em;
          display: inline-block; }
nav.toc ol { margin: 0.3em 0; padding-left: 1.4em; }
td.key { background: #eef1f5; font-weight: 600; white-space: nowrap; }
""".strip()


def _h(text: Any) -> str:
    return html.escape(str(text), quote=True)


def _html_spans(spans: Sequence) -> str:
    out = []
    for s in spans:
        if isinstance(s, tuple) and s[0] == "a":
            out.append(f'<a href="{_h(s[2])}">{_h(s[1])}</a>')
        elif isinstance(s, tuple):
            kind, text = s
            out.append(f"<code>{_h(text)}</code>" if kind == "code" else f"<b>{_h(text)}</b>")
        else:
            out.append(_h(s))
    return "".join(out)


def _html_cell_text(text: str) -> str:
    return "<br>".join(_h(line) for line in text.split("\n"))


def _html_block(b: Any) -> str:
    if isinstance(b, Para):
        return f"<p>{_html_spans(b.spans)}</p>"
    if isinstance(b, Bullets):
        items = "".join(f"<li>{_html_spans(item)}</li>" for item in b.items)
        return f"<ul>{items}</ul>"
    if isinstance(b, Pre):
        return f"<pre>{_h(b.text)}</pre>"
    if isinstance(b, Fig):
        data = base64.b64encode(b.path.read_bytes()).decode("ascii")
        return (f'<figure><img src="data:image/png;base64,{data}" alt="{_h(b.alt)}">'
                f"<figcaption>{_h(b.caption)}</figcaption></figure>")
    if isinstance(b, Table):
        parts = ["<table>"]
        if b.caption:
            parts.append(f"<caption>{_h(b.caption)}</caption>")
        if b.header:
            parts.append("<thead><tr>" + "".join(f"<th>{_h(c)}</th>" for c in b.header)
                         + "</tr></thead>")
        parts.append("<tbody>")
        for i, row in enumerate(b.rows):
            rcls = b.row_classes[i] if i < len(b.row_classes) else None
            parts.append(f'<tr class="{_h(rcls)}">' if rcls else "<tr>")
            for c in map(_cell, row):
                classes = " ".join(x for x in (c.cls, "num" if c.num else None) if x)
                attrs = (f' class="{_h(classes)}"' if classes else "") + (
                    f' title="{_h(c.title)}"' if c.title else "")
                parts.append(f"<td{attrs}>{_html_cell_text(c.text)}</td>")
            parts.append("</tr>")
        parts.append("</tbody></table>")
        return "".join(parts)
    raise TypeError(type(b))


def render_html(title: str, intro: list, sections: list) -> str:
    toc = "".join(f'<li><a href="#{_h(s.anchor)}">{_h(s.title)}</a></li>'
                  for s in sections if s.level == 2)
    body = [f"<h1>{_h(title)}</h1>"]
    body += [_html_block(b) for b in intro]
    body.append(f'<nav class="toc"><b>Contents</b><ol>{toc}</ol></nav>')
    for s in sections:
        body.append(f'<h{s.level} id="{_h(s.anchor)}">{_h(s.title)}</h{s.level}>')
        body += [_html_block(b) for b in s.blocks]
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
            f"<title>{_h(title)}</title>\n<style>\n{CSS}\n</style>\n</head>\n<body>\n"
            + "\n".join(body) + "\n</body>\n</html>\n")


# ---- Markdown

# why: "[" and "_" are left alone (no link definitions here; GFM ignores intraword "_"), and ">"
# matters only at the start of a line, so raw report.md stays readable.
_MD_SPECIAL = str.maketrans({c: "\\" + c for c in "\\`*<|"})


def _md(text: Any) -> str:
    out = str(text).translate(_MD_SPECIAL)
    return "\\" + out if out[:1] in (">", "#", "+", "-") else out


def _md_spans(spans: Sequence) -> str:
    out = []
    for s in spans:
        if isinstance(s, tuple) and s[0] == "a":
            out.append(f"[{_md(s[1])}]({s[2]})")
        elif isinstance(s, tuple):
            kind, text = s
            if kind == "code":
                fence = "``" if "`" in text else "`"
                out.append(f"{fence}{text}{fence}")
            else:
                out.append(f"**{_md(text)}**")
        else:
            out.append(_md(s))
    return "".join(out)


def _md_block(b: Any) -> str:
    if isinstance(b, Para):
        return _md_spans(b.spans)
    if isinstance(b, Bullets):
        return "\n".join(f"- {_md_spans(item)}" for item in b.items)
    if isinstance(b, Pre):
        longest = max((len(run) for run in b.text.split("\n") if set(run) == {"`"}), default=0)
        fence = "`" * max(3, longest + 1)
        return f"{fence}{b.lang}\n{b.text.rstrip()}\n{fence}"
    if isinstance(b, Fig):
        alt = _md(b.alt).replace("[", "\\[").replace("]", "\\]")
        return f"![{alt}]({b.rel})\n\n*{_md(b.caption)}*"
    if isinstance(b, Table):
        lines = []
        if b.caption:
            lines += [_md(b.caption), ""]
        width = len(b.header) if b.header else max((len(r) for r in b.rows), default=1)
        header = b.header or [""] * width
        lines.append("| " + " | ".join(_md(h) for h in header) + " |")
        lines.append("|" + "|".join("---:" if _cell(c).num else "---"
                                    for c in (b.rows[0] if b.rows else header)) + "|")
        for i, row in enumerate(b.rows):
            strong = i < len(b.row_classes) and b.row_classes[i] == "fixed"
            cells = []
            for c in map(_cell, row):
                text = "<br>".join(_md(line) for line in c.text.split("\n"))
                cells.append(f"**{text}**" if strong and text and text != DASH else text)
            lines.append("| " + " | ".join(cells) + " |")
        return "\n".join(lines)
    raise TypeError(type(b))


def render_markdown(title: str, intro: list, sections: list) -> str:
    out = [f"# {_md(title)}", ""]
    for b in intro:
        out += [_md_block(b), ""]
    out.append("Contents:")
    out += [f"{i}. [{_md(s.title)}](#{s.anchor})"
            for i, s in enumerate((s for s in sections if s.level == 2), 1)]
    out.append("")
    for s in sections:
        out += [f'<a id="{s.anchor}"></a>', "", f"{'#' * s.level} {_md(s.title)}", ""]
        for b in s.blocks:
            out += [_md_block(b), ""]
    return "\n".join(out).rstrip() + "\n"


# --------------------------------------------------------------------------------------------
# The report's sections


def _fig(out_dir: Path, path: Path, caption: str, alt: str) -> Fig:
    return Fig(path=path, rel=path.relative_to(out_dir).as_posix(), caption=caption, alt=alt)


def _safe_name(name: str) -> str:
    cleaned = "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in name)
    return cleaned or "set"


def _point_row(p: Point, first: str) -> list:
    return [
        Cell(first, num=True),
        Cell(str(p.runs), num=True),
        Cell(fmt_rate(p), num=True),
        Cell(fmt_overhead(p), num=True),
        Cell(fmt_median(p), num=True),
        Cell(fmt_outcomes(p), num=True),
        Cell(DASH if p.mean_time is None else f"{p.mean_time:.1f}", num=True),
        Cell(DASH if p.mean_losses is None else f"{p.mean_losses:.1f}", num=True),
    ]


POINT_HEADER = ["runs", "success rate [95% CI]", "overhead mean [95% CI]",
                "overhead median [q1, q3]", "success / wall / timeout / gave up", "mean time (s)",
                "mean losses"]


def _header_blocks(summary: dict, out_dir: Path) -> list:
    claims = summary.get("claims") or []
    counts = {v: 0 for v in VERDICT_STYLE}
    for cl in claims:
        key = (cl.get("verdict") or "").strip().lower()
        if key in counts:
            counts[key] += 1
    meta = [
        ("version", summary.get("version") or DASH),
        ("command", summary.get("generated_by") or DASH),
        ("main reading", summary.get("preset") or DASH),
        ("other readings", ", ".join(r.get("name") for r in _readings(summary)[1:]) or DASH),
        ("master seed", fmt_raw_int(summary.get("seed"))),
        ("runs per point", fmt_value(_num(summary.get("runs_per_point")))),
        ("total runs", fmt_value(_num(summary.get("total_runs")))),
        ("elapsed", _elapsed_text(summary)),
        ("threads", fmt_value(_num(summary.get("threads")))),
    ]
    if claims:
        meta.append(("claims (main reading)",
                     f"{counts['holds']} hold, {counts['does not hold']} do not hold, "
                     f"{counts['unclear']} unclear (of {len(claims)})"))
    rows = [[Cell(k, cls="key"), Cell(v, cls="mono" if k == "command" else None)] for k, v in meta]
    return [
        Para(["The nine experiment sets of Lochmatter & Martinoli (2008), \u201cSimulation "
              "Experiments with Bio-Inspired Algorithms for Odor Source Localization in Laminar "
              "Wind Flow\u201d (its section 3.6), re-run in plumetrace under one or more "
              "readings of what the paper leaves unsaid, with its Figs. 6\u20139 redrawn and the "
              "claims of its section 4 checked (the model and its metrics: ",
              _doc_link(out_dir, "docs/model.md"), "; the sets and their statistics: ",
              _doc_link(out_dir, "docs/experiments.md"), "; the claims: ",
              _doc_link(out_dir, "docs/claims.md"), ")."]),
        Table(header=None, rows=rows),
    ]


def _set_sections(out_dir: Path, fig_dir: Path, sets: list, written: list) -> list:
    intro = Section("sets", "Experiment sets A\u2013I (paper Figs. 7\u20139)", [
        Para(["For each set, left: success rate with its Wilson 95% interval (labels: successes/"
              "runs); right: mean distance overhead d_t/d_u over the successful runs with a 95% "
              "percentile bootstrap interval (it never reaches below 1, the bound of an "
              "overhead; the claims' verdicts use the t interval, see ", _doc_link(out_dir, "docs/claims.md"),
              "), bars drawn from 1 (the straight-line "
              "optimum), diamonds at the median, n = successful runs. The darker bar and the bold "
              "row are the fixed value the other sets use. Outcome counts are success / wall / "
              "timeout / gave up."]),
    ])
    if not sets:
        intro.blocks.append(Para(["This summary has no experiment sets."]))
    sections = [intro]
    stems = []
    for s in sets:
        stem = _safe_name(s.name)
        while stem in stems:
            stem += "_"
        stems.append(stem)
    links = []
    for s, stem in zip(sets, stems):
        links += [" \u00b7 " if links else "Sets: ", ("a", s.name, f"#set-{stem}")]
    if links:
        intro.blocks.append(Para(links))
    for s, stem in zip(sets, stems):
        path = set_figure(s, fig_dir / f"set_{stem}.png")
        written.append(path)
        no_success = [fmt_value(p.value) for p in s.points if p.oh_mean is None]
        caption = (f"Set {s.name} ({s.algorithm or 'algorithm ' + DASH}): {s.title or s.key}. "
                   f"Varies {s.key or s.label}")
        if s.fixed_value is not None:
            caption += f"; fixed value {fmt_value(s.fixed_value)} (darker bar)"
        caption += "."
        if no_success:
            caption += (" No overhead bar where no run succeeded: "
                        f"{s.label} = {', '.join(no_success)}.")
        rows, classes = [], []
        for i, p in enumerate(s.points):
            first = fmt_value(p.value) + (" (fixed)" if i == s.fixed_index else "")
            rows.append(_point_row(p, first))
            classes.append("fixed" if i == s.fixed_index else "")
        rows_cells = [r + [Cell((p.config_hash or DASH)[:12], cls="mono")]
                      for r, p in zip(rows, s.points)]
        title = f"Set {s.name}: {s.title}" if s.title else f"Set {s.name}"
        sections.append(Section(f"set-{stem}", title, [
            Para(["Algorithm ", ("b", s.algorithm or DASH), "; varies ", ("code", s.key or "?"),
                  f" ({s.label})."]),
            _fig(out_dir, path, caption, f"Set {s.name}: success rate and overhead vs {s.label}"),
            Table(header=[s.label] + POINT_HEADER + ["config"], rows=rows_cells,
                  row_classes=classes),
        ], level=3))
    return sections


def _trajectory_section(out_dir: Path, fig_dir: Path, summary: dict, written: list) -> Section:
    path = trajectory_figure(summary, fig_dir / "trajectories.png")
    written.append(path)
    panels = _trajectory_panels(summary)
    missing = list(dict.fromkeys(list(summary.get("trajectories_missing") or [])
                                 + [a for a, k, t in panels if t is None and k == "success"]))
    blocks = [_fig(out_dir, path,
                   "Sample runs at the fixed values (paper Fig. 6): per algorithm the first "
                   "successful and the first failed run (by trial), re-run from their seed and "
                   "trial. Grey: fraction of sampled instants with odor (detection map). Red "
                   "disc: the source; dashed circle: the success radius. The trajectory is "
                   "coloured by controller state; triangle: start, circle: end. Wind blows "
                   "along +x (left to right).",
                   "Sample trajectories of the three algorithms, successful and failed, over "
                   "the detection map")]
    rows = []
    for alg, kind, t in panels:
        if t is None:
            rows.append([alg, DASH, DASH, DASH, DASH, DASH,
                         Cell(f"no {'successful' if kind == 'success' else 'failed'} run",
                              cls="unclear" if kind == "success" else None)])
        else:
            outcome = str(t.get("outcome") or DASH)
            rows.append([alg, str(t.get("set") or DASH), fmt_raw_int(t.get("trial")),
                         fmt_raw_int(t.get("seed")),
                         fmt_oh(_num(t.get("overhead"))) if kind == "success" else DASH,
                         fmt_oh(_num(t.get("closest_m"))),
                         Cell(outcome, cls="holds" if outcome == "success" else "fails")])
    blocks.append(Table(header=["algorithm", "set", "trial", "seed", "overhead",
                                "closest to the source (m)", "outcome"], rows=rows))
    if missing:
        blocks.append(Para(["No successful run at the fixed values for: ",
                            ", ".join(missing), "; those panels show the plume only."]))
    return Section("trajectories", "Sample trajectories, successful and failed (paper Fig. 6)",
                   blocks)


def _claims_section(out_dir: Path, summary: dict) -> Section:
    claims = summary.get("claims") or []
    if not claims:
        return Section("claims", "The paper's claims", [Para(["This summary has no claims."])])
    rows = []
    for cl in claims:
        cls, _, symbol = verdict_style(cl.get("verdict"))
        rows.append([Cell(fmt_count(_int(cl.get("id"))) if _is_number(cl.get("id"))
                          else str(cl.get("id", DASH)), num=True),
                     cl.get("text") or "",
                     Cell(f"{symbol} {cl.get('verdict')}", cls=f"verdict {cls}"),
                     cl.get("evidence") or DASH])
    return Section("claims", f"The claims and their evidence ({summary.get('preset') or 'main'} "
                   "reading)", [
        Para(["Each claim of the paper's section 4, as ", _doc_link(out_dir, "docs/claims.md"),
              " states it, checked against the sets above, never tuned to pass; the rules are "
              "in the same document. Verdicts: holds (green), does not hold "
              "(red), unclear (amber). The verdicts of the other readings are under ",
              ("a", "What was found", "#verdict"), "."]),
        Table(header=["id", "claim", "verdict", "evidence"], rows=rows),
    ])


def _sensitivity_section(out_dir: Path, fig_dir: Path, summary: dict, written: list) -> Section:
    sens = summary.get("sensitivity")
    title = "Sensitivity of the three algorithms at their fixed values"
    if not sens or not sens.get("rows"):
        return Section("sensitivity", title,
                       [Para(["This summary has no sensitivity block."])])
    variants, algorithms, grid = _sensitivity_grid(sens)
    path = sensitivity_figure(sens, fig_dir / "sensitivity.png")
    written.append(path)
    rows = []
    for v in variants:
        row = [Cell(v, cls="mono")]
        for a in algorithms:
            p = grid.get((a, v))
            row.append(Cell(DASH) if p is None else
                       Cell(f"{fmt_rate(p)}\n{fmt_overhead(p)}", num=True))
        rows.append(row)
    return Section("sensitivity", title, [
        Para(["The three algorithms at their fixed values (sets A, D, G) rerun under each "
              "success radius the supervisor accepts (", _doc_link(out_dir, "docs/model.md"),
              " section 8, and ", _doc_link(out_dir, "docs/fidelity.md"), ", unknown 6; "
              "0.185 m is the default). Each cell: success rate [Wilson 95%], then mean overhead "
              "[bootstrap 95%] of the successful runs."]),
        Table(header=["variant"] + algorithms, rows=rows),
        _fig(out_dir, path, "Success rate (left) and mean distance overhead of the successful runs "
             "(right) per algorithm, one bar per variant, with 95% intervals.",
             "Sensitivity: success rate and overhead per algorithm and variant"),
    ])


def _sensitivity_claims_section(out_dir: Path, fig_dir: Path, sens: dict, summary: dict,
                                written: list) -> Section:
    claims = sens.get("claims") or summary.get("claims") or []
    rows_json = sens.get("rows") or []
    n_claims = max([len(claims)] + [len(r["verdicts"]) for r in rows_json] + [0])
    header = ["noise_mode", "kernel", "success_radius"] + [str(j + 1) for j in range(n_claims)] \
        + ["held"]
    rows = []
    held_per_claim = [0] * n_claims
    for r in rows_json:
        cells = [Cell(str(r.get("noise_mode") or DASH), cls="mono"),
                 Cell(str(r.get("kernel") or DASH), cls="mono"),
                 Cell(fmt_value(_num(r.get("success_radius"))), num=True)]
        for j in range(n_claims):
            v = r["verdicts"][j] if j < len(r["verdicts"]) else None
            cls, _, symbol = verdict_style(v)
            if cls == "holds":
                held_per_claim[j] += 1
            cells.append(Cell(symbol, cls=f"cell {cls}", title=f"claim {j + 1}: {v or DASH}"))
        held = _int(r.get("held"))
        if held is None:
            held = sum(verdict_style(v)[0] == "holds" for v in r["verdicts"])
        cells.append(Cell(f"{held}/{n_claims}", num=True))
        rows.append(cells)
    if rows:
        rows.append([Cell("held in", cls="key"), "", ""]
                    + [Cell(str(h), num=True) for h in held_per_claim] + [""])
    blocks = [
        Para(["From ", ("code", SENSITIVITY_NAME), f" (version {sens.get('version') or DASH}): "
              "the nine sets rerun with ", ("b", f"{fmt_value(_num(sens.get('runs_per_point')))} "
                                                 "runs per point"),
              " under every combination of noise_mode, kernel and success radius (",
              _doc_link(out_dir, "docs/experiments.md"), ", ", ("code", "plumetrace sensitivity"),
              f"); elapsed {fmt_duration(_num(sens.get('elapsed_s')))}. Cells: "
              "\u2713 holds (green), \u2717 does not hold (red), ? unclear (amber). The last row "
              "counts the combinations under which each claim holds."]),
        Table(header=header, rows=rows),
    ]
    if rows_json:
        path = claims_matrix_figure(sens, fig_dir / "sensitivity_claims.png")
        written.append(path)
        blocks.append(_fig(out_dir, path, "The same matrix as a picture: one row per combination "
                           "(noise_mode \u00b7 kernel \u00b7 success radius), one column per "
                           "claim.",
                           "Sensitivity claims matrix"))
    if claims:
        blocks.append(Para(["Claims:"]))
        blocks.append(Bullets([[("b", f"{c.get('id', j + 1)}:"), f" {c.get('text') or ''}"]
                               for j, c in enumerate(claims)]))
    return Section("sensitivity-claims", "Sensitivity study: which claims hold", blocks)


def _reproducibility_section(summary: dict, out_dir: Path) -> Section:
    blocks = []
    items = [
        ["version: ", ("code", summary.get("version") or DASH)],
        ["preset: ", ("code", summary.get("preset") or DASH)],
        ["master seed: ", ("code", fmt_raw_int(summary.get("seed"))),
         "; every run's random streams (plume, wind sensor, controller) are derived from "
         "(master seed, trial index, stream), so trial k meets the same plume at every value "
         "of a set and results do not depend on the thread count (",
         _doc_link(out_dir, "docs/model.md"), " section 10)."],
        ["runs per point: ", fmt_value(_num(summary.get("runs_per_point"))),
         "; threads: ", fmt_value(_num(summary.get("threads")))],
    ]
    for t in summary.get("trajectories") or []:
        items.append([f"sample run ({t.get('algorithm')}): set {t.get('set') or DASH}, trial ",
                      ("code", fmt_raw_int(t.get("trial"))), ", seed ",
                      ("code", fmt_raw_int(t.get("seed")))])
    blocks.append(Bullets(items))
    blocks.append(Para(["To regenerate the results and this report:"]))
    command = summary.get("generated_by") or "plumetrace reproduce ..."
    blocks.append(Pre(f"{command}\nPYTHONPATH=python python3 -m plumetrace.report {out_dir}", "sh"))
    sweeps = summary.get("sweeps") or []
    if sweeps:
        blocks.append(Para(["Sweep definitions:"]))
        blocks.append(Table(header=["set", "file", "definition"], rows=[
            [str(sw.get("name", DASH)), Cell(str(sw.get("file") or DASH), cls="mono"),
             Cell(json.dumps(sw.get("definition"), sort_keys=True), cls="mono")]
            for sw in sweeps]))
    config = summary.get("config_toml")
    if config:
        blocks.append(Para(["The resolved base scenario (every key, as ",
                            ("code", "plumetrace config"), " prints it):"]))
        blocks.append(Pre(config, "toml"))
    else:
        blocks.append(Para(["This summary does not include the resolved configuration."]))
    return Section("reproducibility", "Reproducibility", blocks)


# --------------------------------------------------------------------------------------------
# Readings, verdicts and failures


def _doc_link(out_dir: Path, rel: str) -> tuple:
    """A link to one of the repository's documents, relative to the report's folder (the
    repository-relative path when this module does not run from a checkout)."""
    target = REPO_ROOT / rel
    href = rel
    if (REPO_ROOT / "docs").is_dir():
        try:
            href = os.path.relpath(target, Path(out_dir).resolve()).replace(os.sep, "/")
        except ValueError:  # another drive (Windows)
            href = rel
    return ("a", rel, href)


def _readings(summary: dict) -> list:
    """The readings in the summary, the main one first; a summary without them has one, built
    from its own claims."""
    readings = list(summary.get("readings") or [])
    if not readings:
        claims = summary.get("claims") or []
        counts = _verdict_counts(claims)
        readings = [{"name": summary.get("preset") or "main", "main": True, "claims": claims,
                     "held": counts["holds"], "not_held": counts["does not hold"],
                     "unclear": counts["unclear"]}]
    readings.sort(key=lambda r: not r.get("main"))
    return readings


def _verdict_counts(claims: list) -> dict:
    counts = {v: 0 for v in VERDICT_STYLE}
    for cl in claims:
        key = (cl.get("verdict") or "").strip().lower()
        if key in counts:
            counts[key] += 1
    return counts


def _held(reading: dict) -> tuple:
    """(holds, does not hold, unclear, claims) of a reading."""
    claims = reading.get("claims") or []
    counts = _verdict_counts(claims)
    held = _int(reading.get("held"))
    return (counts["holds"] if held is None else held, counts["does not hold"],
            counts["unclear"], len(claims))


def short_figure(claim: dict) -> str:
    """The evidence part that decided the verdict: the first contradicted part of a claim that
    does not hold, the first unclear part of an unclear one, else the first part."""
    parts = [p.strip() for p in (claim.get("evidence") or "").split("; ") if p.strip()]
    if not parts:
        return DASH
    want = {"does not hold": "-> no", "unclear": "-> unclear"}.get(
        (claim.get("verdict") or "").strip().lower())
    chosen = next((p for p in parts if want and p.endswith(want)), parts[0])
    for suffix in ("-> yes", "-> no", "-> unclear"):
        if chosen.endswith(suffix):
            chosen = chosen[: -len(suffix)].rstrip()
    return chosen if len(chosen) <= 140 else chosen[:137] + "..."


def _failure_totals(summary: dict) -> Optional[dict]:
    fails = (summary.get("failures") or {}).get("algorithms") or []
    if not fails:
        return None
    total = {k: sum(_int(a.get(k)) or 0 for a in fails)
             for k in ("runs", "failed", "walls", "timeouts", "gave_up", "examined")}
    ends = [e for a in fails for e in (a.get("ends") or [])]
    src = {a.get("algorithm"): (_num(a.get("source_x")) or 0.0, _num(a.get("source_y")) or 0.0)
           for a in fails}
    upwind_wall = upwind = near = 0
    for a in fails:
        sx, sy = src[a.get("algorithm")]
        for e in a.get("ends") or []:
            x, y = _num(e.get("x")), _num(e.get("y"))
            if x is None or y is None:
                continue
            if x < sx:
                upwind += 1
                upwind_wall += e.get("outcome") == "wall"
            elif math.hypot(x - sx, y - sy) <= 1.0:
                near += 1
    total.update(ends=len(ends), upwind_wall=upwind_wall, upwind_other=upwind - upwind_wall,
                 near=near, far=len(ends) - upwind - near,
                 closest=[_num(a.get("closest_median_m")) for a in fails
                          if _num(a.get("closest_median_m")) is not None])
    return total


def failure_sentence(summary: dict) -> Optional[str]:
    """The main failure mode at the fixed values in one sentence, from the summary's numbers."""
    t = _failure_totals(summary)
    if t is None:
        return None
    if t["failed"] == 0:
        return f"None of the {t['runs']} runs at the paper's fixed values failed."
    head = (f"{t['failed']} of {t['runs']} runs at the paper's fixed values fail "
            f"({fmt_pct(t['failed'] / t['runs'])}): {t['walls']} at a wall, {t['timeouts']} "
            f"by timeout, {t['gave_up']} giving up.")
    n = t["ends"]
    if n == 0:
        return head
    places = [
        (t["upwind_wall"], "end at a wall upwind of the source, after passing beside it"),
        (t["upwind_other"], "end upwind of the source (not at a wall), after passing beside it"),
        (t["near"], "end downwind of the source but within 1 m of it"),
        (t["far"], "end more than 1 m downwind of the source"),
    ]
    count, where = max(places, key=lambda p: p[0])
    share = count / n
    lead = "Most" if share > 0.5 else "The largest group of"
    closest = sorted(t["closest"])
    near_text = ""
    if closest:
        span = (f"{closest[0]:.2f} m" if closest[-1] - closest[0] < 0.005
                else f"{closest[0]:.2f}\u2013{closest[-1]:.2f} m")
        near_text = (f"; on their way they came within a median {span} of its centre "
                     "(per algorithm)")
    sample = "" if n == t["failed"] else f" of the {n} re-run"
    return f"{lead} failed runs ({fmt_pct(share)}{sample}) {where}{near_text}. {head}"


def failures_figure(summary: dict, path: Path) -> Path:
    """Outcomes at the fixed values per algorithm, and where the failed runs end."""
    fails = (summary.get("failures") or {}).get("algorithms") or []
    fig = _new_figure(10, 3.6)
    ax_out, ax_map = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1, 1.6]})
    names = [a.get("algorithm") or "?" for a in fails]
    left = np.zeros(len(fails))
    for key, label in (("success", "success"), ("walls", "wall"), ("timeouts", "timeout"),
                       ("gave_up", "gave up")):
        runs = np.array([max(_int(a.get("runs")) or 0, 1) for a in fails], dtype=float)
        if key == "success":
            counts = np.array([(_int(a.get("runs")) or 0) - (_int(a.get("failed")) or 0)
                               for a in fails], dtype=float)
        else:
            counts = np.array([_int(a.get(key)) or 0 for a in fails], dtype=float)
        share = 100 * counts / runs
        color = OUTCOME_COLORS["gave_up" if key == "gave_up" else label.split()[0]]
        ax_out.barh(range(len(fails)), share, left=left, color=color, edgecolor="white",
                    label=label)
        left += share
    ax_out.set_yticks(range(len(fails)))
    ax_out.set_yticklabels(names)
    ax_out.invert_yaxis()
    ax_out.set_xlim(0, 100)
    ax_out.set_xlabel("share of runs at the fixed values (%)")
    ax_out.set_title("how runs end", fontsize=10)
    ax_out.legend(fontsize=7, loc="lower right", framealpha=0.85)

    x_min, x_max, y_min, y_max = _arena(summary)
    src = summary.get("source") or {}
    sx, sy = _num(src.get("x")) or 1.0, _num(src.get("y")) or 0.0
    markers = ("o", "s", "^", "D", "v")
    for k, a in enumerate(fails):
        ends = a.get("ends") or []
        xs = [_num(e.get("x")) for e in ends]
        ys = [_num(e.get("y")) for e in ends]
        colors = [OUTCOME_COLORS.get(e.get("outcome"), MISSING_COLOR) for e in ends]
        ax_map.scatter(xs, ys, c=colors, marker=markers[k % len(markers)], s=22,
                       edgecolors="black", linewidths=0.3, label=a.get("algorithm"), zorder=3)
    sr = _num(src.get("success_radius"))
    ax_map.add_patch(Circle((sx, sy), _num(src.get("radius")) or 0.12, facecolor="#b2182b",
                            edgecolor="black", linewidth=0.5, zorder=2))
    if sr is not None:
        ax_map.add_patch(Circle((sx, sy), sr, fill=False, edgecolor="#b2182b", linestyle="--",
                                zorder=2))
    ax_map.add_patch(Circle((sx, sy), 1.0, fill=False, edgecolor="#777777", linestyle=":",
                            zorder=1))
    ax_map.axvline(sx, color="#777777", linewidth=0.6, zorder=1)
    ax_map.set_xlim(x_min, min(x_max, x_min + 8.0))
    ax_map.set_ylim(y_min, y_max)
    ax_map.set_aspect("equal")
    ax_map.set_xlabel("x (m), downwind \u2192")
    ax_map.set_ylabel("y (m)")
    ax_map.set_title("where failed runs end (colour: outcome)", fontsize=10)
    if fails:
        handles = [Line2D([], [], marker=markers[k % len(markers)], linestyle="none",
                          color="#cccccc", markeredgecolor="black", label=a.get("algorithm"))
                   for k, a in enumerate(fails)]
        ax_map.legend(handles=handles, fontsize=7, loc="lower right", framealpha=0.85)
    return _save(fig, path)


def _draw_map(ax, dmap: Optional[dict], vmax: Optional[float] = None):
    if not dmap or not dmap.get("x") or not dmap.get("y"):
        return None
    frac = np.array([[np.nan if v is None else v for v in row] for row in dmap["fraction"]],
                    dtype=float)
    top = vmax if vmax is not None else (np.nanmax(frac) if np.isfinite(frac).any() else 1.0)
    return ax.pcolormesh(np.asarray(dmap["x"], float), np.asarray(dmap["y"], float), frac,
                         shading="nearest", cmap=ODOR_CMAP, vmin=0.0, vmax=max(float(top), 1e-9),
                         rasterized=True, zorder=0)


def readings_map_figure(summary: dict, readings: list, path: Path) -> Path:
    """Each reading's detection map over the upwind half of the arena."""
    x_min, x_max, y_min, y_max = _arena(summary)
    x_hi = min(x_max, x_min + 8.0)
    cols = 2 if len(readings) > 1 else 1
    rows = (len(readings) + cols - 1) // cols
    panel_h = 4.4 * (y_max - y_min) / max(x_hi - x_min, 1e-9) + 0.35
    fig = _new_figure(10, rows * panel_h + 0.4)
    axes = fig.subplots(rows, cols, squeeze=False).ravel()
    src = summary.get("source") or {}
    sx, sy = _num(src.get("x")), _num(src.get("y"))
    mesh = None
    for ax, r in zip(axes, readings):
        m = _draw_map(ax, r.get("detection_map"), vmax=1.0)
        mesh = m or mesh
        if m is None:
            ax.text(0.5, 0.5, "no map", transform=ax.transAxes, ha="center", va="center",
                    color=MISSING_COLOR)
        if sx is not None and sy is not None:
            ax.add_patch(Circle((sx, sy), _num(src.get("radius")) or 0.12, facecolor="#b2182b",
                                edgecolor="black", linewidth=0.5, zorder=3))
            sr = _num(r.get("success_radius"))
            if sr is not None:
                ax.add_patch(Circle((sx, sy), sr, fill=False, edgecolor="#b2182b",
                                    linestyle="--", linewidth=1.0, zorder=3))
        ax.set_xlim(x_min, x_hi)
        ax.set_ylim(y_min, y_max)
        ax.set_aspect("equal")
        ax.tick_params(labelsize=7)
        held, no, unclear, n = _held(r)
        ax.set_title(f"{r.get('name')}{' (main)' if r.get('main') else ''}: "
                     f"{held} of {n} claims hold", fontsize=9)
    for ax in axes[len(readings):]:
        ax.axis("off")
    if mesh is not None:
        cbar = fig.colorbar(mesh, ax=list(axes[:len(readings)]), shrink=0.6, pad=0.01)
        cbar.set_label("fraction of instants with odor", fontsize=8)
        cbar.ax.tick_params(labelsize=7)
    return _save(fig, path)


def _fixed_points(reading: dict) -> dict:
    return {p.get("algorithm"): Point.from_json(p) for p in reading.get("fixed") or []}


def readings_success_figure(readings: list, path: Path) -> Path:
    """Success rate at the fixed values per algorithm, one bar per reading (Wilson 95%)."""
    fig = _new_figure(10, 3.4)
    ax = fig.subplots()
    n = max(len(readings), 1)
    width = 0.8 / n
    cmap = colormaps["tab10"]
    for k, r in enumerate(readings):
        pts = _fixed_points(r)
        for ai, alg in enumerate(ALGORITHMS):
            p = pts.get(alg)
            if p is None or p.rate is None:
                continue
            xi = ai + (k - (n - 1) / 2) * width
            ax.bar(xi, 100 * p.rate, width=width, color=cmap(k % 10), edgecolor="#333333",
                   linewidth=0.3, zorder=2,
                   label=(r.get("name") + (" (main)" if r.get("main") else "")) if ai == 0
                   else None)
            ax.errorbar([xi], [100 * p.rate],
                        yerr=_asym_err([p.rate], [p.rate_lo], [p.rate_hi], 100), fmt="none",
                        ecolor="black", elinewidth=0.8, capsize=2, zorder=3)
    ax.set_xticks(range(len(ALGORITHMS)))
    ax.set_xticklabels(ALGORITHMS)
    ax.set_ylim(0, 105)
    ax.set_ylabel("success rate (%)")
    ax.set_title("success at the paper's fixed values (sets A, D, G), Wilson 95%", fontsize=10)
    ax.grid(axis="y", color="#e5e5e5", zorder=0)
    ax.set_axisbelow(True)
    ax.legend(fontsize=8, ncol=min(n, 5), loc="upper center", bbox_to_anchor=(0.5, -0.1),
              frameon=False)
    return _save(fig, path)


def _verdict_section(out_dir: Path, fig_dir: Path, summary: dict, written: list) -> Section:
    readings = _readings(summary)
    main = readings[0]
    held, no, unclear, n = _held(main)
    runs = fmt_value(_num(summary.get("runs_per_point")))
    blocks = [Para([("b", f"Under the {main.get('name')} reading, {held} of {n} claims hold"),
                    f", {no} do not hold and {unclear} are unclear, at {runs} runs per value. ",
                    "A reading fixes what the paper leaves unsaid or prints inconsistently "
                    "(the amount per filament, the plume's noise and kernel, the success "
                    "radius, ...); each is listed with its evidence in ",
                    _doc_link(out_dir, "docs/fidelity.md"), ". The model: ",
                    _doc_link(out_dir, "docs/model.md"), "; how each claim is tested: ",
                    _doc_link(out_dir, "docs/claims.md"), "."])]
    rows = []
    for r in readings:
        h, d, u, total = _held(r)
        rows.append([Cell(r.get("name") + (" (main)" if r.get("main") else ""), cls="key"),
                     Cell(str(r.get("file") or "built-in defaults"), cls="mono"),
                     Cell(str(h), cls="holds", num=True), Cell(str(d), cls="fails", num=True),
                     Cell(str(u), cls="unclear", num=True), Cell(str(total), num=True)])
    blocks.append(Table(header=["reading", "preset file", "hold", "do not hold", "unclear",
                                "claims"], rows=rows))

    sentence = failure_sentence(summary)
    if sentence:
        blocks.append(Para([("b", "Main failure mode: "), sentence]))
        path = failures_figure(summary, fig_dir / "failures.png")
        written.append(path)
        examined = _int((summary.get("failures") or {}).get("examined_max"))
        blocks.append(_fig(out_dir, path,
                           "Left: how the runs at the paper's fixed values end, per algorithm "
                           "(main reading). Right: where failed runs end"
                           + (f" (the first {examined} failed runs per algorithm, re-run from "
                              "their seed and trial)" if examined else "")
                           + "; red disc: source, dashed: success radius, dotted: 1 m around "
                           "the source, vertical line: the source's x. Wind blows along +x.",
                           "Outcomes at the fixed values and where failed runs end"))

    claim_rows = []
    main_claims = {_int(c.get("id")): c for c in main.get("claims") or []}
    by_reading = [{_int(c.get("id")): c for c in r.get("claims") or []} for r in readings]
    for cid in sorted(i for i in main_claims if i is not None):
        c = main_claims[cid]
        row = [Cell(str(cid), num=True),
               Cell("\u201c" + PAPER_QUOTES.get(cid, c.get("text") or "") + "\u201d")]
        for claims in by_reading:
            v = (claims.get(cid) or {}).get("verdict")
            cls, _, symbol = verdict_style(v)
            row.append(Cell(symbol, cls=f"cell {cls}", title=v or DASH))
        row.append(Cell(short_figure(c), cls="mono"))
        claim_rows.append(row)
    if claim_rows:
        blocks.append(Para(["Each claim as the paper words it, the verdict under each reading "
                            "(\u2713 holds, \u2717 does not hold, ? unclear) and what the data say "
                            f"under the {main.get('name')} reading: the figure that decided its "
                            "verdict. The full evidence is under ",
                            ("a", "the claims", "#claims"), "."]))
        blocks.append(Table(header=["id", "the paper says"] + [r.get("name") for r in readings]
                            + [f"what the data say ({main.get('name')})"], rows=claim_rows))
    return Section("verdict", "What was found", blocks)


def _setting_text(v: Any) -> str:
    if _is_number(v):
        return f"{v:g}"
    return json.dumps(v)


def _readings_section(out_dir: Path, fig_dir: Path, summary: dict, written: list) -> Section:
    readings = [r for r in _readings(summary) if r.get("fixed") or r.get("detection_map")]
    title = "The readings side by side"
    if not readings:
        return Section("readings", title, [Para(["This summary has no readings."])])
    keys = list(dict.fromkeys(k for r in readings for k in (r.get("settings") or {})))
    blocks = [Para(["Each reading is a preset file (", ("code", "experiments/lochmatter2008/"
                                                                "presets/NAME.toml"),
                    ") applied on top of every experiment set; ", ("code", "default"),
                    " adds nothing to the sets' own scenario (its column shows the built-in "
                    "values). Why each value: ", _doc_link(out_dir, "docs/fidelity.md"), "."])]

    def value(r, k):
        # the value the reading's runs used; older summaries only have the preset's settings
        if k in (r.get("values") or {}):
            return _setting_text(r["values"][k])
        if k in (r.get("settings") or {}):
            return _setting_text(r["settings"][k])
        return "(default)"

    if keys:
        blocks.append(Table(header=["key"] + [r.get("name") for r in readings], rows=[
            [Cell(k, cls="mono")] + [Cell(value(r, k), cls="mono") for r in readings]
            for k in keys]))
    path = readings_success_figure(readings, fig_dir / "readings_success.png")
    written.append(path)
    blocks.append(_fig(out_dir, path, "Success rate of the three algorithms at the paper's fixed "
                       "values under each reading, with Wilson 95% intervals.",
                       "Success at the fixed values per reading"))
    rows = []
    for r in readings:
        pts = _fixed_points(r)
        row = [Cell(r.get("name") + (" (main)" if r.get("main") else ""), cls="key")]
        for alg in ALGORITHMS:
            p = pts.get(alg)
            row.append(Cell(DASH) if p is None else
                       Cell(f"{p.successes}/{p.runs} = {fmt_rate(p)}\n{fmt_overhead(p)}",
                            num=True))
        rows.append(row)
    blocks.append(Table(header=["reading"] + list(ALGORITHMS), rows=rows,
                        caption="At the fixed values: successes/runs = success rate [Wilson 95%], "
                                "then the mean overhead [bootstrap 95%] of the successful runs."))
    path = readings_map_figure(summary, readings, fig_dir / "readings_map.png")
    written.append(path)
    blocks.append(_fig(out_dir, path, "Detection map of each reading: the fraction of instants "
                       "at which a sensor at that point perceives odor (the same scale, 0 to 1, "
                       "in every panel), over the upwind 8 m of the arena. Red disc: the source; "
                       "dashed circle: the reading's success radius.",
                       "Detection maps of the readings"))
    return Section("readings", title, blocks)


# --------------------------------------------------------------------------------------------
# Entry points


def report_title(summary: dict) -> str:
    """What was done and what it found, never that the paper was reproduced."""
    main = _readings(summary)[0]
    held, _, _, n = _held(main)
    sets = len(summary.get("sets") or [])
    count = {9: "nine"}.get(sets, str(sets))
    return (f"Lochmatter & Martinoli (2008), {count} experiment sets re-run: {held} of {n} "
            f"claims hold under the {main.get('name')} reading")


def build_report(out_dir: Union[str, Path]) -> list:
    """Builds report.html, report.md and figures/*.png in out_dir; returns the written paths.

    Raises ReportError (whose message names the file) if summary.json is missing or malformed,
    or if sensitivity.json exists but is malformed.
    """
    out_dir = Path(out_dir)
    summary = _check_summary(_load_json(out_dir / SUMMARY_NAME), out_dir / SUMMARY_NAME)
    sens_path = out_dir / SENSITIVITY_NAME
    sens = _check_sensitivity(_load_json(sens_path), sens_path) if sens_path.exists() else None

    fig_dir = out_dir / "figures"
    fig_dir.mkdir(parents=True, exist_ok=True)
    figures: list = []
    sets = [SweepSet.from_json(s) for s in summary["sets"]]

    # what was found, the readings, sets (Figs. 7-9), sample runs (Fig. 6), claims,
    # sensitivity, reproducibility
    sections = [_verdict_section(out_dir, fig_dir, summary, figures),
                _readings_section(out_dir, fig_dir, summary, figures)]
    sections += _set_sections(out_dir, fig_dir, sets, figures)
    sections.append(_trajectory_section(out_dir, fig_dir, summary, figures))
    sections.append(_claims_section(out_dir, summary))
    sections.append(_sensitivity_section(out_dir, fig_dir, summary, figures))
    if sens is not None:
        sections.append(_sensitivity_claims_section(out_dir, fig_dir, sens, summary, figures))
    sections.append(_reproducibility_section(summary, out_dir))

    title = report_title(summary)
    intro = _header_blocks(summary, out_dir)
    html_path = out_dir / "report.html"
    md_path = out_dir / "report.md"
    html_path.write_text(render_html(title, intro, sections), encoding="utf-8")
    md_path.write_text(render_markdown(title, intro, sections), encoding="utf-8")
    return [html_path, md_path] + figures


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python3 -m plumetrace.report",
        description="Build report.html, report.md and figures/*.png from OUT_DIR/summary.json "
                    "(and OUT_DIR/sensitivity.json when present).")
    parser.add_argument("out_dir", metavar="OUT_DIR", help="output folder of plumetrace reproduce")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    try:
        written = build_report(args.out_dir)
    except ReportError as err:
        print(f"plumetrace.report: error: {err}", file=sys.stderr)
        return 2
    elapsed = time.perf_counter() - start
    print(f"wrote {written[0]} and {written[1]} with {len(written) - 2} figures "
          f"in {elapsed:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
