"""The plot helpers draw what they are given (checked on the artists, not by eye)."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from conftest import plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()
from plumetrace import plots  # noqa: E402

GOLDEN = Path(__file__).resolve().parents[2] / "tests" / "golden" / "sweep.toml"


def test_trajectory_draws_the_path_by_state_over_the_filaments(tmp_path):
    r = pt.run(algorithm="surge-cast", seed=2, trial=1, snapshot_interval=5.0)
    ax = plots.trajectory(r)
    labels = [line.get_label() for line in ax.get_lines()]
    for state in set(r["trajectory"]["state"]):
        assert state in labels
    # every step of the path is drawn once, in one state's line
    drawn = sum(np.count_nonzero(~np.isnan(line.get_xdata().astype(float)))
                for line in ax.get_lines() if line.get_label() in set(r["trajectory"]["state"]))
    assert drawn == len(r["trajectory"]["x"])
    assert len(ax.collections[0].get_offsets()) == 1600  # the last snapshot's filaments
    ax.figure.savefig(tmp_path / "t.png")
    assert (tmp_path / "t.png").stat().st_size > 10000


def test_sweep_bars_show_each_value_with_wilson_and_bootstrap_intervals():
    rows = pt.sweep(GOLDEN, runs=4)
    fig = plots.sweep_bars(rows, "wind_sensor.sigma_a")
    left, right = fig.axes[:2]
    heights = [p.get_height() for p in left.patches]
    cols = rows.to_numpy()
    # the golden sweep's other axis, the algorithm, is drawn as colours: a bar per pair
    pairs = [(a, v) for a in ("casting", "surge-spiral", "surge-cast") for v in (0.2, 0.6)]
    assert len(heights) == len(pairs)
    for (a, v), h in zip(pairs, heights):
        sel = (cols["wind_sensor.sigma_a"] == v) & (cols["controller.algorithm"] == a)
        assert h == pytest.approx(100 * cols["success"][sel].mean())
    # the first bar's error bar is its Wilson interval
    sel = (cols["wind_sensor.sigma_a"] == 0.2) & (cols["controller.algorithm"] == "casting")
    lo, hi = pt._core.wilson_interval(int(cols["success"][sel].sum()), 4)
    segments = left.collections[0].get_segments()
    assert segments[0][:, 1].tolist() == pytest.approx([100 * lo, 100 * hi])
    # and the overhead's, the percentile bootstrap interval of its mean
    lo, hi = pt._core.bootstrap_mean_interval(cols["overhead"][sel & cols["success"]].tolist())
    assert right.collections[0].get_segments()[0][:, 1].tolist() == pytest.approx([lo, hi])
    assert right.get_title() == "overhead of successful runs (bootstrap 95%)"
