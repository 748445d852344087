"""Matplotlib helpers: a trajectory over the plume, and a sweep's success and overhead bars.

    import plumetrace as pt
    from plumetrace import plots
    r = pt.run(algorithm="surge-spiral", seed=1, snapshot_interval=10.0)
    ax = plots.trajectory(r, scenario=pt.Scenario())
    rows = pt.sweep("studies/lochmatter2008/sets/A.toml", runs=10)
    fig = plots.sweep_bars(rows, "casting.beta_deg")
"""

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


def sweep_bars(rows, axis_key=None, hue=None, fig=None):
    """Success rate (Wilson 95% intervals) and mean overhead of the successful runs (percentile
    bootstrap 95% intervals, as rows.summary()) per value of `axis_key` (default: the sweep's
    first axis), from plumetrace.sweep rows, drawn as the reports draw them. A second axis is drawn as colours side by side (`hue`:
    its key, by default the sweep's next axis); a sweep of more axes is refused with ValueError,
    as its points would be pooled (plumetrace.report draws every point of any sweep). Returns
    the figure."""
    import matplotlib.pyplot as plt

    from .report.figures import draw_sweep_panels
    from .report.sweep import fmt_axis_value, results_from_rows, sweep_views
    from .sweeps import axis_keys

    keys = axis_keys(rows)
    axis_key = keys[0] if axis_key is None else axis_key
    if axis_key not in keys:
        raise ValueError(f"{axis_key!r} is not an axis of sweep '{rows.name}' (axes: "
                         f"{', '.join(keys)})")
    others = [k for k in keys if k != axis_key]
    if hue is None and others:
        hue = others[0]
    if hue is not None and hue not in others:
        raise ValueError(f"hue {hue!r} is not another axis of sweep '{rows.name}' (axes: "
                         f"{', '.join(keys)})")
    pooled = [k for k in others if k != hue]
    if pooled:
        raise ValueError(f"sweep '{rows.name}' has {len(keys)} axes ({', '.join(keys)}): "
                         f"sweep_bars draws {axis_key} with {hue} as colours, and would pool "
                         f"the runs over {', '.join(pooled)}; draw every point with "
                         "plumetrace.report(rows, out=...), which gives each of its values a row "
                         "of panels")
    view = sweep_views(results_from_rows(rows))[0]
    order = {a.key: i for i, a in enumerate(view.axes)}
    x_axis = view.axes[order[axis_key]]

    def at(x, h):
        values = [None] * len(view.axes)
        values[order[axis_key]] = x
        if hue is not None:
            values[order[hue]] = h
        return view.drawn(values)

    hue_values = view.axes[order[hue]].values if hue is not None else [None]
    groups = [(None if h is None else fmt_axis_value(h), [at(x, h) for x in x_axis.values])
              for h in hue_values]
    if fig is None:
        fig = plt.figure(figsize=(10, 3.6), layout="constrained")
    left, right = fig.subplots(1, 2)
    draw_sweep_panels(left, right, [fmt_axis_value(v) for v in x_axis.values], groups, axis_key,
                      x_axis.fixed_index if hue is None else None)
    if hue is not None:
        left.legend(title=hue, fontsize=7, title_fontsize=7, loc="lower left")
    fig.suptitle(rows.name)
    return fig
