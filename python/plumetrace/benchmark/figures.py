"""The leaderboard's figures (matplotlib, Agg, no pyplot): the success heat map, the scores with
their intervals, and the time-to-source and distance-overhead panels per task."""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np
from matplotlib import colormaps
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from .._files import write_whole

__all__ = ["heat_map", "metric_panels", "score_figure"]

DPI = 100
ENTRANT_COLOR = "#2c5d8f"
NULL_COLOR = "#999999"
EMPTY_COLOR = "#dddddd"


def _new_figure(width: float, height: float) -> Figure:
    fig = Figure(figsize=(width, height), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _save(fig: Figure, path: Path) -> Path:
    png = io.BytesIO()
    # why: no timestamp or version in the file, so a leaderboard is the same byte for byte
    fig.savefig(png, format="png", dpi=DPI, metadata={"Software": None})
    return write_whole(path, png.getvalue())


def _label(score: dict) -> str:
    return f"{score['controller']} (null)" if score["null_model"] else score["controller"]


def heat_map(path: Path, board: dict) -> Path:
    """Success rate per controller (rows, in the leaderboard's order) and task (columns), each
    cell with its rate and k/n; "no runs" on grey; "*" where runs are missing."""
    tasks = [t["name"] for t in board["suite"]["tasks"]]
    scores = board["scores"]
    cells = {(c["task"], c["controller"]): c for c in board["cells"]}
    rates = np.full((len(scores), len(tasks)), np.nan)
    for i, s in enumerate(scores):
        for j, t in enumerate(tasks):
            rate = cells[(t, s["controller"])]["success_rate"]
            rates[i, j] = np.nan if rate is None else rate
    fig = _new_figure(max(6.0, 1.25 * len(tasks) + 2.5), max(2.5, 0.55 * len(scores) + 1.6))
    ax = fig.add_subplot()
    cmap = colormaps["viridis"].with_extremes(bad=EMPTY_COLOR)
    image = ax.imshow(np.ma.masked_invalid(rates), cmap=cmap, vmin=0.0, vmax=1.0,
                      aspect="auto")
    for i, s in enumerate(scores):
        for j, t in enumerate(tasks):
            c = cells[(t, s["controller"])]
            if c["runs"] == 0:
                ax.text(j, i, "no runs", ha="center", va="center", fontsize=8, color="#555555")
                continue
            mark = "*" if c["missing"] else ""
            ax.text(j, i, f"{c['success_rate']:.2f}\n{c['successes']}/{c['runs']}{mark}",
                    ha="center", va="center", fontsize=8,
                    color="white" if c["success_rate"] < 0.55 else "black")
    ax.set_xticks(range(len(tasks)), tasks, rotation=30, ha="right")
    ax.set_yticks(range(len(scores)), [_label(s) for s in scores])
    ax.set_title("success rate (successes/runs; * runs missing)", fontsize=10)
    fig.colorbar(image, ax=ax, label="success rate", shrink=0.8)
    return _save(fig, path)


def score_figure(path: Path, board: dict) -> Path:
    """Each ranked controller's score (mean success over tasks) with its bootstrap 95% interval,
    and its rank with the rank's 95% interval at the right."""
    ranked = [s for s in board["scores"] if s["score"] is not None]
    fig = _new_figure(7.5, max(2.2, 0.42 * len(ranked) + 1.2))
    ax = fig.add_subplot()
    for i, s in enumerate(ranked):
        color = NULL_COLOR if s["null_model"] else ENTRANT_COLOR
        if s["lo"] is not None:
            ax.plot([s["lo"], s["hi"]], [i, i], color=color, lw=2.5, solid_capstyle="butt")
        ax.plot([s["score"]], [i], "o", color=color, ms=6)
        ranks = (f"{s['rank_lo']}" if s["rank_lo"] == s["rank_hi"]
                 else f"{s['rank_lo']}\u2013{s['rank_hi']}")
        ax.annotate(f"rank {s['rank']} ({ranks})", (1.0, i), xycoords=("axes fraction", "data"),
                    xytext=(6, 0), textcoords="offset points", va="center", fontsize=8)
    ax.set_yticks(range(len(ranked)), [_label(s) for s in ranked])
    ax.set_ylim(max(1, len(ranked)) - 0.5, -0.5)
    if not ranked:
        ax.text(0.5, 0.0, "no controller has runs on every task", ha="center", va="center")
    ax.set_xlim(-0.03, 1.03)  # why: a score of 0 or 1 is drawn whole, inside the frame
    ax.set_xlabel("score: mean success rate over tasks (95% paired bootstrap interval)")
    ax.grid(axis="x", color="#e5e5e5")
    return _save(fig, path)


def metric_panels(path: Path, board: dict, metric: str, label: str) -> Path:
    """One panel per task: each controller's mean `metric` ("time" or "overhead") over its
    successful runs with the bootstrap 95% interval; "none" where it has no such run."""
    tasks = board["suite"]["tasks"]
    scores = board["scores"]
    cells = {(c["task"], c["controller"]): c for c in board["cells"]}
    cols = min(3, len(tasks))
    rows = math.ceil(len(tasks) / cols)
    fig = _new_figure(4.2 * cols + 1.2, rows * (0.32 * len(scores) + 1.3))
    axes = fig.subplots(rows, cols, squeeze=False)
    for k, task in enumerate(tasks):
        ax = axes[k // cols][k % cols]
        for i, s in enumerate(scores):
            m = cells[(task["name"], s["controller"])][metric]
            color = NULL_COLOR if s["null_model"] else ENTRANT_COLOR
            if m["mean"] is None:
                ax.annotate("none", (0.02, i), xycoords=("axes fraction", "data"), va="center",
                            fontsize=7, color="#777777")
                continue
            if m["lo"] is not None:
                ax.plot([m["lo"], m["hi"]], [i, i], color=color, lw=2.0, solid_capstyle="butt")
            ax.plot([m["mean"]], [i], "o", color=color, ms=4)
        ax.set_yticks(range(len(scores)), [_label(s) if k % cols == 0 else "" for s in scores],
                      fontsize=8)
        ax.set_ylim(len(scores) - 0.5, -0.5)
        ax.set_title(task["name"], fontsize=9)
        ax.tick_params(axis="x", labelsize=8)
        ax.grid(axis="x", color="#e5e5e5")
        if k // cols == rows - 1:
            ax.set_xlabel(label, fontsize=8)
    for k in range(len(tasks), rows * cols):
        axes[k // cols][k % cols].set_visible(False)
    return _save(fig, path)
