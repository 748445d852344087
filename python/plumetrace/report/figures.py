"""The report's figures (matplotlib, Agg, no pyplot) and their colours."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Iterable, Optional, Sequence

import numpy as np
from matplotlib import colormaps
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.colors import LinearSegmentedColormap, to_rgb
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Patch

from .data import (DASH, VERDICT_STYLE, Point, SweepSet, _centreline, _fixed_points, _held, _int,
                   _is_number, _num, _sensitivity_grid, fmt_value, verdict_style, write_whole)
from .wording import counted, verb

DPI = 100
BAR_COLOR = "#8fb3d9"
FIXED_COLOR = "#2c5d8f"
MISSING_COLOR = "#999999"


OUTCOME_COLORS = {"success": "#4c9a4c", "wall": "#d9534f", "timeout": "#f0ad4e",
                  "gave_up": "#8c6bb1", "wrong_declaration": "#5b7fa6"}


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


def _new_figure(width: float, height: float) -> Figure:
    fig = Figure(figsize=(width, height), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _save(fig: Figure, path: Path) -> Path:
    png = io.BytesIO()
    fig.savefig(png, format="png", dpi=DPI)
    return write_whole(path, png.getvalue())


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


def _rate_axis(ax, x, points: Sequence[Point], colors: Sequence[str], width: float = 0.7,
               label_counts: bool = True, label: Optional[str] = None, count_rotation: int = 0):
    """Success-rate bars (%) with their Wilson intervals, and "k/n" above each; returns the
    bars."""
    rates = [p.rate for p in points]
    heights = [100 * r if r is not None else 0.0 for r in rates]
    bars = ax.bar(x, heights, width=width, color=colors, edgecolor="#333333", linewidth=0.4,
                  zorder=2, label=label)
    err = _asym_err(rates, [p.rate_lo for p in points], [p.rate_hi for p in points], 100)
    ax.errorbar(x, heights, yerr=err, fmt="none", ecolor="black", elinewidth=1, capsize=3,
                zorder=3)
    if label_counts:
        for xi, p in zip(x, points):
            top = 100 * (p.rate_hi if p.rate_hi is not None else (p.rate or 0.0))
            ax.annotate(f"{p.successes}/{p.runs}", (xi, top), xytext=(0, 2),
                        textcoords="offset points", ha="center", va="bottom", fontsize=7,
                        rotation=count_rotation)
    ax.set_ylim(0, 112)
    ax.set_yticks(range(0, 101, 20))
    ax.set_ylabel("success rate (%)")
    return bars


def _overhead_axis(ax, x, points: Sequence[Point], colors: Sequence[str], label_n: bool = True,
                   width: float = 0.7, count_rotation: int = 0):
    """Overhead bars from 1 (the straight-line optimum) with their percentile bootstrap
    intervals and medians.

    Returns the indices of points that have no mean overhead (no successful run).
    """
    means = [p.oh_mean for p in points]
    have = [i for i, m in enumerate(means) if m is not None]
    missing = [i for i, m in enumerate(means) if m is None]
    if have:
        hx = np.asarray(x, dtype=float)[have]
        heights = [means[i] - 1.0 for i in have]
        ax.bar(hx, heights, bottom=1.0, width=width, color=[colors[i] for i in have],
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
                            textcoords="offset points", ha="center", va="bottom", fontsize=7,
                            rotation=count_rotation)
    else:
        ax.set_ylim(0.95, 1.5)
        ax.text(0.5, 0.5, "no successful runs", transform=ax.transAxes, ha="center",
                va="center", color=MISSING_COLOR)
    # why: at the bottom of the panel whatever limits it gets later (x in data, y in the axes)
    for i in missing:
        ax.text(x[i], 0.0, " none", rotation=90, ha="center", va="bottom", fontsize=7,
                color=MISSING_COLOR, transform=ax.get_xaxis_transform())
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

    _rate_axis(ax_rate, x, s.points, colors)
    if n == 0:
        ax_rate.text(0.5, 0.5, "no points in this set", transform=ax_rate.transAxes,
                     ha="center", va="center", color=MISSING_COLOR)
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


# Colours of the values of a sweep's second axis (hue), after the paper's blue.
HUE_COLORS = ("#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2", "#b07aa1", "#edc948",
              "#9c755f")


def draw_sweep_panels(ax_rate, ax_oh, x_labels: Sequence[str], groups: Sequence[tuple],
                      x_title: str, fixed_index: Optional[int] = None,
                      interval: str = "bootstrap 95%",
                      runs_per_point: Optional[int] = None) -> None:
    """The paper's two panels on two axes: success rate (Wilson 95%) and overhead of the
    successful runs (`interval`), a bar per value of the x axis for each group. `groups`: (label
    or None, [Point or None per x value]); with several groups the bars of one x value stand side
    by side, each group in its colour (hue). A point without runs (None) is marked "no runs"; one
    with fewer runs than `runs_per_point` is hatched."""
    n = len(x_labels)
    k = max(len(groups), 1)
    width = 0.7 if k == 1 else 0.8 / k
    counts = k * n <= 30
    no_overhead: list = []
    for g, (label, points) in enumerate(groups):
        offset = (g - (k - 1) / 2) * width
        at = [i for i, p in enumerate(points) if p is not None]
        xs = [i + offset for i in at]
        pts = [points[i] for i in at]
        if k == 1:
            colors = _bar_colors(n, fixed_index)
            colors = [colors[i] for i in at]
        else:
            colors = [HUE_COLORS[g % len(HUE_COLORS)]] * len(at)
        bars = _rate_axis(ax_rate, xs, pts, colors, width=width, label_counts=counts,
                          label=label, count_rotation=90 if k > 1 else 0)
        for bar, p in zip(bars, pts):
            if runs_per_point is not None and p.runs < runs_per_point:
                bar.set_hatch("///")
        for i, p in enumerate(points):
            if p is None:
                ax_rate.text(i + offset, 2, "no runs", rotation=90, ha="center", va="bottom",
                             fontsize=7, color=MISSING_COLOR)
        if any(p.oh_mean is not None for p in pts):
            _overhead_axis(ax_oh, xs, pts, colors, label_n=counts, width=width,
                           count_rotation=90 if k > 1 else 0)
        else:
            no_overhead += xs
    means = [p for _, pts in groups for p in pts if p is not None and p.oh_mean is not None]
    if means:
        # why: each group set the limits for its own bars; the panel shows them all. The
        # interval of two or three runs can span the whole spread of their overheads: the
        # limits follow the points of four runs or more where there are any (longer bars run
        # off the panel)
        steady = [p for p in means if p.oh_n >= 4] or means
        tops = [p.oh_hi if p.oh_hi is not None else p.oh_mean for p in steady]
        lows = [p.oh_lo if p.oh_lo is not None else p.oh_mean for p in steady]
        top = max(tops + [p.oh_mean for p in means] + [1.0])
        bottom = min(lows + [1.0])
        span = max(top - bottom, 0.05)
        ax_oh.set_ylim(min(1.0, bottom) - 0.05 * span, top + 0.18 * span)
        # a count whose interval runs off the panel is drawn at its top edge, marked with an arrow
        for text in ax_oh.texts:
            if text.get_text().startswith("n=") and getattr(text, "xy", (0, 0))[1] > top:
                text.xy = (text.xy[0], ax_oh.get_ylim()[1])
                text.xyann = (3, -3)
                text.set_verticalalignment("top")
                text.set_horizontalalignment("left")
                text.set_text(text.get_text() + " \u2191")
        for xi in no_overhead:
            ax_oh.text(xi, 0.0, " none", rotation=90, ha="center", va="bottom", fontsize=7,
                       color=MISSING_COLOR, transform=ax_oh.get_xaxis_transform())
    else:
        _overhead_axis(ax_oh, [], [], [])  # "no successful runs"
    ax_rate.set_title("success rate (Wilson 95%)", fontsize=10)
    ax_oh.set_title(f"overhead of successful runs ({interval})", fontsize=10)
    for ax in (ax_rate, ax_oh):
        ax.set_xticks(range(n))
        ax.set_xticklabels(list(x_labels), fontsize=8, rotation=30 if n > 8 else 0)
        ax.set_xlabel(x_title)
        ax.set_xlim(-0.6, n - 0.4)
        ax.grid(axis="y", color="#e5e5e5", zorder=0)
        ax.set_axisbelow(True)
        if fixed_index is not None and 0 <= fixed_index < n:
            ax.get_xticklabels()[fixed_index].set_fontweight("bold")


def _panel_legend(ax_legend, groups: Sequence[tuple], hue_title: Optional[str],
                  fixed: bool, medians: bool, interval: str, hatched: bool = False) -> None:
    if len(groups) > 1:
        handles = [Patch(color=HUE_COLORS[g % len(HUE_COLORS)], label=str(label))
                   for g, (label, _) in enumerate(groups)]
    else:
        handles = [Patch(color=BAR_COLOR, label="varied value")]
        if fixed:
            handles.append(Patch(color=FIXED_COLOR, label="fixed value"))
    handles.append(Line2D([], [], color="black", marker="_", markersize=8, linewidth=1,
                          label="95% interval"))
    if medians:
        handles.append(Line2D([], [], linestyle="none", marker="D", markersize=4,
                              color="#f2b134", markeredgecolor="black", label="median overhead"))
    if hatched:
        handles.append(Patch(facecolor="white", edgecolor="#333333", hatch="///",
                             label="fewer runs than asked"))
    ax_legend.legend(handles=handles, loc="center", ncol=min(len(handles), 6), fontsize=8,
                     frameon=False, title=hue_title if len(groups) > 1 else None,
                     title_fontsize=8)


def sweep_figure(facets: Sequence[tuple], x_title: str, path: Path,
                 hue_title: Optional[str] = None, interval: str = "bootstrap 95%",
                 runs_per_point: Optional[int] = None) -> Path:
    """Any sweep's figure: one row of the two panels per facet. `facets`: (title or None,
    x labels, groups as draw_sweep_panels takes them, index of the fixed x value or None); the
    groups' labels are the values of `hue_title`'s axis, the same in every facet."""
    rows = max(len(facets), 1)
    fig = _new_figure(10, 3.6 * rows + 0.55)
    grid_spec = fig.add_gridspec(rows + 1, 2, height_ratios=[14] * rows + [1.4])
    medians = False
    for r, (title, labels, groups, fixed) in enumerate(facets):
        ax_rate, ax_oh = fig.add_subplot(grid_spec[r, 0]), fig.add_subplot(grid_spec[r, 1])
        draw_sweep_panels(ax_rate, ax_oh, labels, groups, x_title, fixed, interval,
                          runs_per_point)
        if title:
            ax_rate.set_title(f"{title}: success rate (Wilson 95%)", fontsize=10)
            ax_oh.set_title(f"{title}: overhead ({interval})", fontsize=10)
        medians = medians or any(p is not None and p.oh_median is not None
                                 for _, pts in groups for p in pts)
    ax_legend = fig.add_subplot(grid_spec[rows, :])
    ax_legend.axis("off")
    first = facets[0] if facets else (None, [], [], None)
    hatched = runs_per_point is not None and any(
        p is not None and p.runs < runs_per_point
        for _, _, groups, _ in facets for _, pts in groups for p in pts)
    _panel_legend(ax_legend, first[2], hue_title, first[3] is not None, medians, interval,
                  hatched)
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


def _wind_text(summary: dict) -> str:
    """The main reading's wind as the figures state it; older summaries do not carry it."""
    wind = summary.get("wind") or {}
    vx, vy = wind.get("vx"), wind.get("vy")
    if not _is_number(vx):
        return "(wind along +x)"
    if _is_number(vy) and vy != 0.0:
        return f"(wind {vx:g}, {vy:g} m/s)"
    return f"(wind {vx:g} m/s along +x)"


def _arena(summary: dict):
    a = summary.get("arena") or {}
    get = lambda k, d: _num(a.get(k)) if _num(a.get(k)) is not None else d  # noqa: E731
    return get("x_min", 0.0), get("x_max", 16.0), get("y_min", -2.0), get("y_max", 2.0)


def trajectory_figure(summary: dict, panels: list, path: Path) -> Path:
    """Fig. 6: one panel per (algorithm, "success" or "failure", trajectory or None) over the
    detection map."""
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
        if traj is not None and traj.get("wind_field"):
            _draw_wind_field(ax, traj["wind_field"])
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


def _draw_wind_field(ax, w: dict) -> None:
    """The true wind at release on the trace's grid, light arrows under the trajectory."""
    nx, ny = int(w["nx"]), int(w["ny"])
    if nx * ny == 0 or len(w["u"]) != nx * ny:
        return
    xs = float(w["x0"]) + float(w["dx"]) * np.arange(nx)
    ys = float(w["y0"]) + float(w["dy"]) * np.arange(ny)
    gx, gy = np.meshgrid(xs, ys)
    u = np.asarray(w["u"], float).reshape(ny, nx)
    v = np.asarray(w["v"], float).reshape(ny, nx)
    # why: 0.5 m of arrow per m/s, as in the viewer's scale of the arena
    ax.quiver(gx, gy, u, v, angles="xy", scale_units="xy", scale=2.0, color="#9a9a9a",
              width=0.0015, headwidth=4, zorder=1)


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


def sensitivity_figure(sens: dict, order: Sequence[str], path: Path) -> Path:
    """Grouped bars: success rate and overhead per algorithm (those in `order` first), one bar
    per variant."""
    variants, algorithms, grid = _sensitivity_grid(sens, order)
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
                     f"{counted(held, n, 'claim', 'claims')} {verb(held, 'holds', 'hold')}",
                     fontsize=9)
    for ax in axes[len(readings):]:
        ax.axis("off")
    if mesh is not None:
        cbar = fig.colorbar(mesh, ax=list(axes[:len(readings)]), shrink=0.6, pad=0.01)
        cbar.set_label("fraction of instants with odor", fontsize=8)
        cbar.ax.tick_params(labelsize=7)
    return _save(fig, path)


def readings_success_figure(readings: list, algorithms: Sequence[str], path: Path) -> Path:
    """Success rate at the fixed values per algorithm, one bar per reading (Wilson 95%)."""
    fig = _new_figure(10, 3.4)
    ax = fig.subplots()
    n = max(len(readings), 1)
    width = 0.8 / n
    cmap = colormaps["tab10"]
    for k, r in enumerate(readings):
        pts = _fixed_points(r)
        for ai, alg in enumerate(algorithms):
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
    ax.set_xticks(range(len(algorithms)))
    ax.set_xticklabels(algorithms)
    ax.set_ylim(0, 105)
    ax.set_ylabel("success rate (%)")
    ax.set_title("success at the paper's fixed values (sets A, D, G), Wilson 95%", fontsize=10)
    ax.grid(axis="y", color="#e5e5e5", zorder=0)
    ax.set_axisbelow(True)
    ax.legend(fontsize=8, ncol=min(n, 5), loc="upper center", bbox_to_anchor=(0.5, -0.1),
              frameon=False)
    return _save(fig, path)


def plume_gaps_figure(readings: list, marks: Sequence[tuple], path: Path) -> Path:
    """The gaps between detections of a sensor moving upwind along the plume's centreline, per
    reading: the share of gaps at least as long as L, against L (log scales), with the lengths
    of `marks` ((length, label) pairs: d_lost and the smallest d_lost of the sets) drawn as
    vertical lines (docs/plume-statistics.md)."""
    fig = _new_figure(10, 3.8)
    ax = fig.subplots()
    cmap = colormaps["tab10"]
    shortest, longest = None, 1.0
    for k, r in enumerate(readings):
        line = _centreline(r.get("plume_stats"))
        label = r.get("name") + (" (main)" if r.get("main") else "")
        lengths = sorted(x for x in (line or {}).get("lengths") or [] if _is_number(x) and x > 0)
        if not lengths:
            ax.plot([], [], color=cmap(k % 10), label=f"{label}: no gap")
            continue
        n = len(lengths)
        share = 1.0 - np.arange(n) / n  # the share of gaps at least as long as each
        ax.step(lengths, share, where="post", color=cmap(k % 10), linewidth=1.4,
                label=f"{label}: {n} gaps, longest {lengths[-1]:.2f} m")
        shortest = lengths[0] if shortest is None else min(shortest, lengths[0])
        longest = max(longest, lengths[-1])
    for length, text in marks:
        ax.axvline(length, color="#b2182b", linestyle="--", linewidth=1.0)
        ax.text(length, 1.0, f" {text}", color="#b2182b", fontsize=8, va="top",
                transform=ax.get_xaxis_transform())
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(left=min([shortest or 1e-3] + [m for m, _ in marks]) * 0.8,
                right=max([m for m, _ in marks] + [longest]) * 1.5)
    ax.set_xlabel("gap between detections along the centreline, L (m)")
    ax.set_ylabel("share of gaps at least L long")
    ax.grid(color="#e5e5e5", which="both", zorder=0)
    ax.legend(fontsize=8, loc="lower left", frameon=False)
    return _save(fig, path)
