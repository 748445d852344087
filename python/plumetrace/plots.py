"""Matplotlib helpers: a trajectory over the plume, and a sweep's success and overhead bars.

    import plumetrace as pt
    from plumetrace import plots
    r = pt.run(algorithm="surge-spiral", seed=1, snapshot_interval=10.0)
    ax = plots.trajectory(r, scenario=pt.Scenario())
    rows = pt.sweep("studies/lochmatter2008/sets/A.toml", runs=10)
    fig = plots.sweep_bars(rows, "casting.beta_deg")
"""

import math

import numpy as np


def trajectory(result, scenario=None, snapshot=-1, ax=None):
    """Draws a run's path coloured by controller state over the filaments of one snapshot
    (the last by default; none without snapshots), the source, the success radius and the
    arena. `result`: what plumetrace.run returned (with its trajectory). Returns the axes."""
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle, Rectangle

    from .api import Scenario
    from .report.figures import _state_palette

    cfg = (scenario or Scenario()).to_dict()
    if ax is None:
        _, ax = plt.subplots(figsize=(10, 3.2))
    arena, source = cfg["arena"], cfg["source"]
    ax.add_patch(Rectangle((arena["x_min"], arena["y_min"]), arena["x_max"] - arena["x_min"],
                           arena["y_max"] - arena["y_min"], fill=False, lw=1.5, color="0.3"))
    snaps = result.get("snapshots") or []
    if snaps:
        s = snaps[snapshot]
        ax.scatter(s["x"], s["y"], s=4 + 400 * np.asarray(s["w"]) ** 2, c="tab:gray", alpha=0.25,
                   lw=0, label=f"filaments at {s['time']:.0f} s")
    traj = result["trajectory"]
    states = np.asarray(traj["state"])
    # why: the report's and the run viewer's colour for each state
    palette = _state_palette(traj["state"])
    for name, color in palette.items():
        mask = states == name
        ax.plot(np.where(mask, traj["x"], np.nan), np.where(mask, traj["y"], np.nan), lw=1.6,
                color=color, label=name)
    ax.add_patch(Circle((source["x"], source["y"]), source["radius"], color="tab:red"))
    ax.add_patch(Circle((source["x"], source["y"]), cfg["supervisor"]["success_radius"],
                        fill=False, ls="--", color="tab:red"))
    ax.plot(traj["x"][0], traj["y"][0], "k^", ms=7)
    ax.plot(traj["x"][-1], traj["y"][-1], "ko", ms=5)
    ax.set_xlim(arena["x_min"] - 0.2, arena["x_max"] + 0.2)
    ax.set_ylim(arena["y_min"] - 0.2, arena["y_max"] + 0.2)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m), wind along +x")
    ax.set_ylabel("y (m)")
    ax.set_title(f"{result.get('algorithm', '')}: {result['outcome']}, d_t {result['d_t']:.1f} m")
    ax.legend(loc="upper right", fontsize=7)
    return ax


def sweep_bars(rows, axis_key, fig=None):
    """Success rate (with Wilson 95% intervals) and mean overhead of successful runs (with t 95%
    intervals) per value of `axis_key`, from plumetrace.sweep rows. Returns the figure."""
    import matplotlib.pyplot as plt

    from . import _core

    cols = rows.to_numpy()
    values = list(dict.fromkeys(cols[axis_key].tolist()))
    rate, lo, hi, mean, half = [], [], [], [], []
    for v in values:
        sel = cols[axis_key] == v
        n, k = int(sel.sum()), int(cols["success"][sel].sum())
        a, b = _core.wilson_interval(k, n)
        r = k / n
        rate.append(100 * r)
        lo.append(100 * (r - a))
        hi.append(100 * (b - r))
        m, mlo, mhi = _core.mean_ci(cols["overhead"][sel & cols["success"]].tolist())
        mean.append(m)
        half.append(0.0 if math.isnan(mhi) else mhi - m)
    if fig is None:
        fig = plt.figure(figsize=(9, 3.2))
    left, right = fig.subplots(1, 2)
    pos = np.arange(len(values))
    left.bar(pos, rate, yerr=[lo, hi], capsize=3, color="tab:blue")
    left.set_ylabel("success rate (%)")
    left.set_ylim(0, 105)
    right.bar(pos, np.asarray(mean) - 1.0, bottom=1.0, yerr=half, capsize=3, color="tab:orange")
    right.set_ylabel("overhead d_t / d_u")
    for ax in (left, right):
        ax.set_xticks(pos, [str(v) for v in values])
        ax.set_xlabel(axis_key)
    fig.suptitle(rows.name)
    fig.tight_layout()
    return fig
