"""The report of any sweep: the paper's two panels, the summary tables and what the data say.

    python3 -m plumetrace.report.sweep OUT [--regenerate=COMMAND] [--complete=COMMAND]...

reads OUT/results.json (as `plumetrace report`, `export` and `sweep` write it) and writes
OUT/report.html (self-contained), OUT/report.md, OUT/report.csv (one row per point) and
OUT/figures/sweep_NAME.png. `plumetrace report SWEEP.toml --store S` runs it; from Python,
``plumetrace.report(...)`` does the same from a store or from the rows of ``plumetrace.sweep``.

Per sweep: success rate with its Wilson 95% interval and the mean distance overhead of the
successful runs with its percentile bootstrap 95% interval (the numbers `plumetrace sweep`
prints; within the sample's range, so never below 1), against the first axis; a second axis is
drawn as colours (hue) beside each other, or as one row of panels per value when it has more
than MAX_HUE values; each further axis gives one row of panels per
combination of its values (nothing is pooled), up to MAX_FACETS rows. The title states what the
data say: where success is highest and lowest, and whether the 95% intervals separate them.
Points with fewer runs than their sweep asks for are named, with the command that computes them.
Uses the report's machinery (data.py, figures.py, page.py) and not the C++ module.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math
import os
import re
import shlex
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional, Sequence

from .._files import BadPath, exit_status, output_folder
from .data import (DASH, Point, ReportError, _Checker, _json_type, _load_json, fmt_count,
                   fmt_median, fmt_overhead, fmt_rate, fmt_value, write_whole)
from .figures import sweep_figure
from .page import Bullets, Fig, Para, Pre, Section, Table, _doc_link, write_pages
from .wording import counted, verb

RESULTS_NAME = "results.json"
RESULTS_FORMAT = 1
MAX_HUE = 8  # a second axis with more values is drawn as one row of panels per value
MAX_FACETS = 12  # more rows than this: no figure, and the report says so

CSV_COLUMNS = ("runs", "runs_per_point", "successes", "walls", "timeouts", "gave_up",
               "success_rate", "success_lo", "success_hi", "overhead_n", "overhead_mean",
               "overhead_lo", "overhead_hi", "overhead_median", "overhead_q1", "overhead_q3")


@dataclass
class AxisView:
    key: str
    label: str
    values: list
    fixed_index: Optional[int]


@dataclass
class PointView:
    index: int
    values: tuple
    point: Point  # the overhead with its bootstrap interval
    stats: dict


@dataclass
class SweepView:
    name: str
    title: str
    file: str
    seed: Any
    runs_per_point: int
    axes: list
    points: list

    def drawn(self, values: Sequence) -> Optional[Point]:
        """The statistics of the point of these axis values, or None where it has no run."""
        p = self.at(values)
        return p.point if p is not None and p.point.runs > 0 else None

    def at(self, values: Sequence) -> Optional[PointView]:
        """The point of these axis values, or None."""
        key = tuple(_value_key(v) for v in values)
        for p in self.points:
            if tuple(_value_key(v) for v in p.values) == key:
                return p
        return None

    @property
    def incomplete(self) -> list:
        return [p for p in self.points if p.point.runs < self.runs_per_point]


def _value_key(v: Any) -> str:
    return json.dumps(v, sort_keys=True)


def fmt_axis_value(v: Any) -> str:
    """An axis value as the reader sees it: 0.2, 45, casting, true."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return fmt_value(float(v)) if math.isfinite(v) else str(v)
    return str(v)


def where(s: SweepView, p: PointView, short: bool = False) -> str:
    """"key = value, ..." of a point; `short`: each key by its last part where the sweep's axes
    keep apart that way ("sigma_a = 0.2" for wind_sensor.sigma_a)."""
    keys = [a.key for a in s.axes]
    if short:
        lasts = [k.rsplit(".", 1)[-1] for k in keys]
        keys = lasts if len(set(lasts)) == len(lasts) else keys
    return ", ".join(f"{k} = {fmt_axis_value(v)}" for k, v in zip(keys, p.values))


# --- reading ---------------------------------------------------------------------------------

def load_results(path: Path) -> dict:
    """results.json, checked as far as the report reads it; ReportError names the file and the
    JSON path of anything missing or mistyped."""
    data = _load_json(path)
    c = _Checker(path)
    if not isinstance(data, dict):
        raise ReportError(f"{path}: expected a JSON object at the top, got {_json_type(data)}")
    if data.get("plumetrace_results") != RESULTS_FORMAT:
        raise ReportError(f"{path}: not a plumetrace results file of format {RESULTS_FORMAT} "
                          f'("plumetrace_results" is {data.get("plumetrace_results")!r})')
    sweeps = c.lst(data.get("sweeps"), "sweeps")
    for i, s in enumerate(sweeps):
        where_ = f"sweeps[{i}]"
        c.obj(s, where_)
        c.text(s.get("name"), f"{where_}.name")
        c.num(s.get("runs_per_point"), f"{where_}.runs_per_point", nullable=False)
        axes = c.lst(s.get("axes"), f"{where_}.axes")
        for j, a in enumerate(axes):
            c.obj(a, f"{where_}.axes[{j}]")
            c.text(a.get("key"), f"{where_}.axes[{j}].key")
            c.lst(a.get("values"), f"{where_}.axes[{j}].values")
        for j, p in enumerate(c.lst(s.get("points"), f"{where_}.points")):
            at = f"{where_}.points[{j}]"
            c.obj(p, at)
            if len(c.lst(p.get("values"), f"{at}.values")) != len(axes):
                c.fail(f"{at}.values", f"has {len(p['values'])} entries for {len(axes)} axes")
            stats = c.obj(p.get("stats"), f"{at}.stats")
            for key in ("runs", "successes"):
                c.num(stats.get(key), f"{at}.stats.{key}", nullable=False)
    return data


def sweep_views(results: dict) -> list:
    views = []
    for s in results.get("sweeps") or []:
        axes = []
        for a in s["axes"]:
            fixed = a.get("fixed")
            index = None
            if fixed is not None:
                keys = [_value_key(v) for v in a["values"]]
                index = keys.index(_value_key(fixed)) if _value_key(fixed) in keys else None
            axes.append(AxisView(a["key"], a.get("label") or a["key"], list(a["values"]), index))
        points = [PointView(int(p.get("index", k)), tuple(p["values"]),
                            Point.from_json(p["stats"]), p["stats"])
                  for k, p in enumerate(s["points"])]
        views.append(SweepView(str(s["name"]), s.get("title") or "", s.get("file") or "",
                               s.get("seed"), int(s["runs_per_point"]), axes, points))
    return views


def results_from_rows(rows) -> dict:
    """results.json's content for the rows of plumetrace.sweep (SweepRows), from its summary()."""
    summary = rows.summary()
    info = rows.info
    keys = [a["key"] for a in info.get("axes") or []]
    if not keys:
        names = list(rows.columns)
        keys = names[names.index("point") + 1:names.index("trial")]
    axes = info.get("axes") or [{"key": k, "label": k, "fixed": None,
                                 "values": list(dict.fromkeys(rows.columns[k]))} for k in keys]
    points = []
    for r in summary:
        number = lambda k: None if r[k] is None or (isinstance(r[k], float)  # noqa: E731
                                                     and math.isnan(r[k])) else r[k]
        stats = {k: number(k) for k in ("runs", "successes", "walls", "timeouts", "gave_up",
                                         "success_rate", "success_lo", "success_hi")}
        # why: summary()'s interval is the bootstrap's, given under both names as the C++
        # writes it
        stats["overhead"] = {"n": r["overhead_n"], "mean": number("overhead_mean"),
                             "lo": number("overhead_lo"), "hi": number("overhead_hi"),
                             "boot_lo": number("overhead_lo"), "boot_hi": number("overhead_hi"),
                             "median": number("overhead_median"), "q1": number("overhead_q1"),
                             "q3": number("overhead_q3")}
        points.append({"index": r["point"], "values": [r[k] for k in keys], "stats": stats})
    runs = info.get("runs_per_point") or max([p["stats"]["runs"] for p in points] + [0])
    return {"plumetrace_results": RESULTS_FORMAT,
            "sweeps": [{"name": rows.name, "title": info.get("title") or "",
                        "file": info.get("file") or "", "seed": info.get("seed"),
                        "runs_per_point": runs, "axes": axes, "points": points}]}


# --- what the data say -----------------------------------------------------------------------

def _pct(v: Optional[float]) -> str:
    return DASH if v is None else f"{100 * v:.0f}%"


def _separated(a: Point, b: Point) -> Optional[bool]:
    """Whether the Wilson intervals of two points do not overlap (None when unknown)."""
    if None in (a.rate_lo, a.rate_hi, b.rate_lo, b.rate_hi):
        return None
    return a.rate_hi < b.rate_lo or b.rate_hi < a.rate_lo


def series_finding(key: str, series: list, every: str) -> str:
    """What success does along one axis: `series` is [(value, Point)] in the axis' order. A
    rate that rises or falls throughout (three values or more, numeric) is a trend; otherwise
    where it is highest and lowest; either way whether the Wilson intervals of the two keep them
    apart. `every`: the words for "at every ..." when the rate does not change."""
    pts = [(v, p) for v, p in series if p is not None and p.runs > 0]
    if not pts:
        return "no runs stored"
    best = max(pts, key=lambda vp: vp[1].rate)
    worst = min(pts, key=lambda vp: vp[1].rate)
    if best[1].rate == worst[1].rate:
        return f"success is {_pct(best[1].rate)} at every {every}"
    seq = [p.rate for _, p in pts]
    numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v, _ in pts)
    monotone = numeric and len(pts) >= 3 and (all(a <= b for a, b in zip(seq, seq[1:])) or
                                              all(a >= b for a, b in zip(seq, seq[1:])))
    a, b = (pts[0], pts[-1]) if monotone else (best, worst)
    apart = _separated(a[1], b[1])
    tail = ("" if apart is None else " (95% intervals apart)" if apart else
            ", within each other's 95% intervals: the data do not separate them")
    if monotone:
        verb = "rises" if seq[-1] > seq[0] else "falls"
        return (f"success {verb} with {key} from {_pct(seq[0])} at {fmt_axis_value(a[0])} to "
                f"{_pct(seq[-1])} at {fmt_axis_value(b[0])}{tail}")
    return (f"success is highest at {key} = {fmt_axis_value(a[0])} ({_pct(a[1].rate)}) and "
            f"lowest at {key} = {fmt_axis_value(b[0])} ({_pct(b[1].rate)}){tail}")


def success_finding(s: SweepView, short: bool = False) -> str:
    """One clause on success over the whole sweep: along its axis for one axis, else where it is
    highest and lowest; `short`: the keys by their last part (for the title)."""
    if len(s.axes) == 1:
        key = s.axes[0].key
        return series_finding(key.rsplit(".", 1)[-1] if short else key,
                              [(v, s.drawn((v,))) for v in s.axes[0].values], "point")
    pts = [p for p in s.points if p.point.runs > 0]
    if not pts:
        return "no runs stored"
    best = max(pts, key=lambda p: p.point.rate)
    worst = min(pts, key=lambda p: p.point.rate)
    if best.point.rate == worst.point.rate:
        return f"success is {_pct(best.point.rate)} at every point"
    apart = _separated(best.point, worst.point)
    tail = ("" if apart is None else " (95% intervals apart)" if apart else
            ", within each other's 95% intervals: the data do not separate them")
    return (f"success is highest at {where(s, best, short)} ({_pct(best.point.rate)}) and "
            f"lowest at {where(s, worst, short)} ({_pct(worst.point.rate)}){tail}")


def overhead_finding(s: SweepView) -> Optional[str]:
    pts = [p for p in s.points if p.point.oh_mean is not None]
    if len(pts) < 2:
        return None
    low = min(pts, key=lambda p: p.point.oh_mean)
    high = max(pts, key=lambda p: p.point.oh_mean)
    a, b = low.point, high.point
    apart = None if None in (a.oh_hi, b.oh_lo) else a.oh_hi < b.oh_lo
    tail = ("" if apart is None else " (bootstrap 95% intervals apart)" if apart else
            ", within each other's bootstrap 95% intervals")
    return (f"the successful runs' distance overhead d_t/d_u is lowest at {where(s, low)} "
            f"({fmt_overhead(a)}) and highest at {where(s, high)} ({fmt_overhead(b)}){tail}")


def per_value_findings(s: SweepView) -> list:
    """For a sweep of two axes: for each value of the colour axis, what success does along the
    x axis (plot_axes)."""
    if len(s.axes) != 2:
        return []
    xi, hi = plot_axes(s)
    along, per = s.axes[xi], s.axes[hi]
    items = []
    for h in per.values:
        series = []
        for x in along.values:
            values = [None, None]
            values[xi], values[hi] = x, h
            series.append((x, s.drawn(values)))
        text = series_finding(along.key, series, along.key)
        items.append([f"{per.key} = {fmt_axis_value(h)}: {text}."])
    return items


def report_title(views: list) -> str:
    """What the data say, sweep by sweep."""
    parts = []
    for s in views:
        name = s.title or s.name
        parts.append(f"{name}: {success_finding(s, short=True)}")
    if len(views) == 1:
        return parts[0]
    return f"{len(views)} sweeps: " + "; ".join(parts)


# --- figures and tables ----------------------------------------------------------------------

def plot_axes(s: SweepView) -> tuple:
    """(index of the x axis, index of the colour axis or None): of the first two axes, the one
    with more values goes along x (the first on a tie), the other is drawn as colours."""
    if len(s.axes) == 1:
        return 0, None
    a, b = s.axes[0], s.axes[1]
    return (1, 0) if len(b.values) > len(a.values) else (0, 1)


def figure_facets(s: SweepView) -> tuple:
    """(facets for figures.sweep_figure, the x axis, hue title or None, a note on the layout or
    None); facets None when there would be more than MAX_FACETS rows of panels."""
    xi, hi = plot_axes(s)
    x_axis = s.axes[xi]
    labels = [fmt_axis_value(v) for v in x_axis.values]

    def drawn(x, h, combo):
        values = [None] * len(s.axes)
        values[xi] = x
        if hi is not None:
            values[hi] = h
        values[2:] = combo
        return s.drawn(values)

    if hi is None:
        return [(None, labels, [(None, [drawn(v, None, ()) for v in x_axis.values])],
                 x_axis.fixed_index)], x_axis, None, None
    other, rest = s.axes[hi], s.axes[2:]
    combos = [()]
    for a in rest:
        combos = [c + (v,) for c in combos for v in a.values]
    hue = len(other.values) <= MAX_HUE
    rows = len(combos) * (1 if hue else len(other.values))
    if rows > MAX_FACETS:
        note = (f"The sweep has {len(s.points)} points over {len(s.axes)} axes: drawn, they would "
                f"take {rows} rows of panels (more than {MAX_FACETS}), so the figure is left out; "
                "the table lists every point.")
        return None, x_axis, None, note
    facets = []
    for combo in combos:
        fixed_rest = ", ".join(f"{a.key} = {fmt_axis_value(v)}" for a, v in zip(rest, combo))
        if hue:
            groups = [(fmt_axis_value(h), [drawn(x, h, combo) for x in x_axis.values])
                      for h in other.values]
            facets.append((fixed_rest or None, labels, groups, x_axis.fixed_index))
            continue
        for h in other.values:
            title = ", ".join(t for t in (f"{other.key} = {fmt_axis_value(h)}", fixed_rest) if t)
            facets.append((title, labels, [(None, [drawn(x, h, combo) for x in x_axis.values])],
                           x_axis.fixed_index))
    how = (f"colours: {other.key}" if hue else
           f"one row of panels per value of {other.key} (it has {len(other.values)} values, "
           f"more than {MAX_HUE} colours)")
    note = f"The x axis is {x_axis.key}; {how}"
    if rest:
        note += (f"; one row per combination of {', '.join(a.key for a in rest)} "
                 f"({len(s.axes)} axes: every point is drawn, nothing is pooled)")
    return facets, x_axis, other.key if hue else None, note + "."


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("._") or "sweep"


def table_rows(s: SweepView) -> tuple:
    header = [a.label for a in s.axes] + ["runs", "success [Wilson 95%]",
                                          "success / wall / timeout / gave up",
                                          "overhead [bootstrap 95%]",
                                          "median overhead [IQR]"]
    rows, classes = [], []
    for p in s.points:
        pt = p.point
        runs = (str(pt.runs) if pt.runs >= s.runs_per_point
                else f"{pt.runs} of {s.runs_per_point} (incomplete)")
        outcomes = " / ".join(fmt_count(v) for v in (pt.successes, pt.walls, pt.timeouts,
                                                       pt.gave_up))
        overhead = fmt_overhead(pt) if pt.runs > 0 else DASH
        rows.append([fmt_axis_value(v) for v in p.values]
                    + [runs, fmt_rate(pt), outcomes, overhead, fmt_median(pt)])
        fixed = len(s.axes) == 1 and s.axes[0].fixed_index is not None and \
            p.values[0] == s.axes[0].values[s.axes[0].fixed_index]
        classes.append("fixed" if fixed else ("incomplete" if pt.runs < s.runs_per_point
                                              else None))
    return header, rows, classes


def write_csv(out: Path, views: list) -> Path:
    """report.csv: one row per point of every sweep, full precision, empty where undefined."""
    keys = list(dict.fromkeys(a.key for s in views for a in s.axes))
    text = io.StringIO()
    w = csv.writer(text, lineterminator="\n")
    w.writerow(["sweep", "point", *keys, *CSV_COLUMNS])
    for s in views:
        for p in s.points:
            st = p.stats
            oh = st.get("overhead") or {}
            values = {a.key: v for a, v in zip(s.axes, p.values)}
            cells = {"runs": st.get("runs"), "runs_per_point": s.runs_per_point,
                     **{k: st.get(k) for k in ("successes", "walls", "timeouts", "gave_up",
                                               "success_rate", "success_lo", "success_hi")},
                     **{f"overhead_{k}": oh.get(k) for k in ("n", "mean", "median", "q1",
                                                             "q3")},
                     "overhead_lo": p.point.oh_lo, "overhead_hi": p.point.oh_hi}
            w.writerow([s.name, p.index]
                       + [_csv_cell(values[k]) if k in values else "" for k in keys]
                       + [_csv_cell(cells[k]) for k in CSV_COLUMNS])
    return write_whole(out / "report.csv", text.getvalue())


def _csv_cell(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else ""
    return str(v)


# --- the document ----------------------------------------------------------------------------

def build_sweep_report(out_dir, results: Optional[dict] = None,
                       regenerate: Optional[str] = None,
                       complete: Optional[Sequence[str]] = None,
                       made_from: Optional[str] = None) -> list:
    """Writes report.html, report.md, report.csv and figures/sweep_*.png into out_dir, from
    `results` (results.json's content) or out_dir/results.json; returns the paths written.
    `regenerate`: the command that redraws it; `complete`: per sweep, the command that computes
    its missing runs; `made_from`: a sentence on where the runs come from. Raises ReportError
    naming the file when results.json is missing or malformed."""
    out = Path(out_dir)
    if results is None:
        results = load_results(out / RESULTS_NAME)
    views = sweep_views(results)
    if not views:
        raise ReportError(f"{out / RESULTS_NAME}: no sweep in it")
    fig_dir = output_folder(out / "figures", "the report's figures")
    complete = list(complete or [])
    written: list = []
    title = report_title(views)

    findings = []
    for s in views:
        lead = f"{s.title or s.name}: " if len(views) > 1 else ""
        findings.append([lead + _capital(success_finding(s)) + "."])
        oh = overhead_finding(s)
        if oh:
            findings.append([lead + _capital(oh) + "."])
        findings += per_value_findings(s)
    intro = [Para(["What the data say (success rates with Wilson 95% intervals; the mean "
                   "distance overhead d_t/d_u of the successful runs with percentile bootstrap "
                   "95% intervals, the numbers plumetrace sweep prints; ",
                   _doc_link(out, "docs/experiments.md"), "):"]), Bullets(findings)]
    missing = [(s, p) for s in views for p in s.incomplete]
    if missing:
        k = len(missing)
        their = verb(k, "its", "their")
        intro.append(Para([("b", "Incomplete:"),
                           f" {counted(k, sum(len(s.points) for s in views), 'point', 'points')} "
                           f"{verb(k, 'has', 'have')} fewer runs than {their} sweep asks for; "
                           f"{their} numbers rest on the runs stored (see each sweep's section, "
                           "and below how to compute the rest)."]))
    if made_from:
        intro.append(Para([made_from]))

    sections = []
    for k, s in enumerate(views):
        blocks = [Para(_describe(s))]
        facets, x_axis, hue, note = figure_facets(s)
        if note:
            blocks.append(Para([note]))
        if facets:
            name = f"sweep_{_safe(s.name)}" + (f"_{k}" if len(views) > 1 else "")
            png = sweep_figure(facets, x_axis.label, fig_dir / f"{name}.png", hue_title=hue,
                               runs_per_point=s.runs_per_point)
            written.append(png)
            blocks.append(Fig(path=png, rel=png.relative_to(out).as_posix(),
                              caption=f"{s.title or s.name}: success rate (Wilson 95%) and "
                                      "mean distance overhead of the successful runs "
                                      "(bootstrap 95%) against "
                                      f"{x_axis.key}" + (f", one colour per {hue}" if hue
                                                            else "") + ".",
                              alt=f"success rate and overhead panels of sweep {s.name}"))
        header, rows, classes = table_rows(s)
        blocks.append(Table(header=header, rows=rows, row_classes=classes))
        if s.incomplete:
            items = [[f"({where(s, p)}): {p.point.runs} of {s.runs_per_point} runs"]
                     for p in s.incomplete[:20]]
            if len(s.incomplete) > 20:
                items.append([f"and {len(s.incomplete) - 20} more"])
            blocks.append(Para([("b", "Points with runs missing:"),
                                f" {len(s.incomplete)} of {len(s.points)}."]))
            blocks.append(Bullets(items))
            if k < len(complete) and complete[k]:
                blocks.append(Para(["Compute them (the runs already stored are kept):"]))
                blocks.append(Pre(complete[k], "sh"))
        sections.append(Section(anchor=f"sweep-{_safe(s.name)}",
                                title=f"{s.name}: {s.title}" if s.title else s.name,
                                blocks=blocks))
    again = [Para(["Every run is a pure function of its point's resolved scenario, the master "
                   "seed and the trial; the results store keeps them by the points' values, so "
                   "a sweep given more values computes only the new points' runs."])]
    if regenerate:
        again += [Para(["Redraw this report:"]), Pre(regenerate, "sh")]
    sections.append(Section(anchor="regenerate", title="How to regenerate", blocks=again))
    written.append(write_csv(out, views))
    return write_pages(out, title, intro, sections) + written


def _capital(text: str) -> str:
    return text[:1].upper() + text[1:]


def _describe(s: SweepView) -> list:
    axes = "; ".join(f"{a.key} ({len(a.values)} values: "
                     f"{', '.join(fmt_axis_value(v) for v in a.values[:12])}"
                     f"{', ...' if len(a.values) > 12 else ''})" for a in s.axes)
    runs = sum(p.point.runs for p in s.points)
    spans = [f"{len(s.points)} points, {s.runs_per_point} runs per point ({runs} stored), master "
             f"seed {s.seed}. Axes: {axes}."]
    if s.file:
        spans += [" Sweep file: ", ("code", s.file), "."]
    return spans


def report_sweep(sweep, store=None, out=None, runs=0, overrides=None, base=None, seed=None,
                 name=None, title=None, fixed=None, labels=None, **kwargs) -> list:
    """The report of any sweep, as `plumetrace report` draws it; returns the paths written
    (report.html, report.md, the figures, report.csv). Called as ``plumetrace.report(...)``.

    `sweep`: the SweepRows of plumetrace.sweep, drawn from its rows (give `out`); or a sweep
    file or dict of axes as plumetrace.sweep takes them (with `base`, `seed`, `name`, `title`,
    `fixed`, `labels`, `runs` and `overrides`/keyword arguments as there) together with `store`,
    the results store its runs were computed into (`plumetrace sweep SWEEP.toml --store FILE`):
    `out` then defaults to the store's folder, which also gets the exports (runs.csv,
    summary.csv, results.json). Points with runs missing are named in the report and in a
    warning. Raises StoreError naming the store when it was not made from this sweep or holds
    none of its runs, ConfigError for a bad sweep, ReportError for a bad results file."""
    from ..api import StoreError, SweepRows, _config_value, _dotted, _whole

    if isinstance(sweep, SweepRows):
        if store is not None:
            raise TypeError("store: the rows of plumetrace.sweep are drawn as they are; pass a "
                            "sweep file or dict of axes with a store")
        if out is None:
            raise TypeError("out: give the folder to write the report into")
        out = output_folder(out, "out")
        return build_sweep_report(out, results_from_rows(sweep), made_from=(
            "Drawn from the rows of plumetrace.sweep in Python (no results store): run the same "
            "script again to redraw it."))
    if store is None:
        raise TypeError("store: the results store the sweep was run into (plumetrace sweep "
                        "SWEEP.toml --store FILE); or pass the rows of plumetrace.sweep")
    from .. import _core
    from ..sweeps import sweep_spec

    runs = _whole("runs", runs, 0, 2**31 - 1)
    spec = sweep_spec(sweep, runs, base, seed, name, title, fixed, labels)
    settings = [(k, _config_value(k, v))
                for k, v in _dotted({**(overrides or {}), **kwargs}).items()]
    store = os.fspath(store)
    out = Path(out) if out is not None else Path(store).parent
    incomplete = _core.export_store(spec, settings, store, str(out), runs)
    results = load_results(out / RESULTS_NAME)
    if all(p["stats"]["runs"] == 0 for s in results["sweeps"] for p in s["points"]):
        raise StoreError(f"results store '{store}' holds no run of this sweep's points: nothing "
                         "to report (compute them with plumetrace sweep SWEEP.toml --store "
                         f"{store})")
    options = "".join(f" --set {shlex.quote(f'{k}={_cli_value(v)}')}" for k, v in settings)
    options += f" --runs {runs}" if runs > 0 else ""
    regenerate = complete = None
    if isinstance(spec, str):
        regenerate = (f"plumetrace report {shlex.quote(spec)} --store {shlex.quote(store)} "
                      f"--out {shlex.quote(str(out))}{options}")
        complete = [f"plumetrace sweep {shlex.quote(spec)} --store {shlex.quote(store)}{options}"]
    if incomplete:
        named = "; ".join(f"({p['values']}): {p['stored']} of {p['runs']} runs"
                          for p in incomplete[:10])
        more = f" and {len(incomplete) - 10} more" if len(incomplete) > 10 else ""
        warnings.warn(f"results store '{store}': {len(incomplete)} point(s) of sweep "
                      f"{incomplete[0]['sweep']} have runs missing: {named}{more}"
                      + (f"; compute them with: {complete[0]}" if complete else ""),
                      stacklevel=2)
    return build_sweep_report(out, results, regenerate=regenerate, complete=complete)


def _cli_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    return repr(v) if isinstance(v, float) else str(v)


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python3 -m plumetrace.report.sweep",
        description="Build report.html, report.md, report.csv and figures/ from "
                    "OUT_DIR/results.json (any sweep).")
    parser.add_argument("out_dir", metavar="OUT_DIR")
    parser.add_argument("--regenerate", help="the command that redraws the report")
    parser.add_argument("--complete", action="append", default=[],
                        help="per sweep, in order: the command that computes its missing runs")
    args = parser.parse_args(argv)
    try:
        written = build_sweep_report(args.out_dir, regenerate=args.regenerate,
                                     complete=args.complete)
    except (ReportError, BadPath, OSError) as err:
        print(f"plumetrace.report.sweep: error: {err}", file=sys.stderr)
        return exit_status(err)
    print(f"wrote {written[0]}, {written[1]} and {written[-1]} with {len(written) - 3} "
          "figure(s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
