"""Your own sweeps as the paper's: dict sweeps, their statistics, their bars and their report."""

import csv
import json
import math
import os
import subprocess
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from conftest import overhead_bounds, plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()
from plumetrace import plots  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
CLI = os.environ.get("PLUMETRACE_CLI", str(ROOT / "build" / "plumetrace"))
GOLDEN = ROOT / "tests" / "golden" / "sweep.toml"
TWO_PLUMES = ROOT / "tests" / "support" / "two_plumes.toml"

# a quick base: the robot starts 4 m from the source
QUICK = {"robot.start_x": 4.0, "sim.warmup": 6.0, "supervisor.timeout": 60.0}
QUICK_TOML = "robot.start_x = 4.0\nsim.warmup = 6.0\nsupervisor.timeout = 60.0\n"


def cli(*args):
    return subprocess.run([CLI, *map(str, args)], check=True, capture_output=True, text=True)


def quick_base(**more):
    return pt.Scenario(**{k.replace(".", "__"): v for k, v in {**QUICK, **more}.items()})


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def grid_toml(path, values, seed=5, runs=3):
    path.write_text(f'name = "grid"\nruns = {runs}\nseed = {seed}\n\n[set]\n{QUICK_TOML}'
                    'controller.algorithm = "surge-cast"\n\n[[axis]]\n'
                    f'key = "surge_cast.d_lost"\nvalues = {values}\n')
    return path


# --- dict sweeps -----------------------------------------------------------------------------

def test_a_dict_of_axes_is_the_same_sweep_as_its_file(tmp_path):
    toml = grid_toml(tmp_path / "grid.toml", "[0.1, 0.3]")
    from_file = pt.sweep(toml).to_numpy()
    from_dict = pt.sweep({"surge_cast.d_lost": [0.1, 0.3]}, runs=3, seed=5, name="grid",
                         base=quick_base(**{"controller.algorithm": "surge-cast"})).to_numpy()
    assert list(from_file) == list(from_dict)
    for key in from_file:
        floats = from_file[key].dtype.kind == "f"
        assert np.array_equal(from_file[key], from_dict[key], equal_nan=floats), key
    assert len(from_dict["point"]) == 6


def test_a_dict_sweep_is_a_grid_with_the_first_key_slowest_and_says_its_axes():
    rows = pt.sweep({"controller.algorithm": ["casting", "surge-cast"],
                     "wind_sensor.sigma_a": [0.1, 0.5, 0.9]}, runs=1, base=quick_base(),
                    fixed={"wind_sensor.sigma_a": 0.5}, labels={"wind_sensor.sigma_a": "σ_a"})
    assert rows["controller.algorithm"] == ["casting"] * 3 + ["surge-cast"] * 3
    assert rows["wind_sensor.sigma_a"] == [0.1, 0.5, 0.9] * 2
    assert rows.info["axes"][1] == {"key": "wind_sensor.sigma_a", "label": "σ_a",
                                    "values": [0.1, 0.5, 0.9], "fixed": 0.5}
    assert rows.info["seed"] == 1 and rows.info["runs_per_point"] == 1
    assert rows.name == "sweep"


@pytest.mark.parametrize("sweep, kwargs, error, match", [
    ({"wind.vxx": [1.0]}, {}, pt.ConfigError, r"axis wind\.vxx"),
    ({"sim.dt": [0.1, -1.0]}, {}, pt.ConfigError, r"sim\.dt"),
    ({"sim.dt": []}, {}, ValueError, r"axis sim\.dt: values must not be empty"),
    ({}, {}, ValueError, "no axis"),
    ({"sim.dt": 0.1}, {}, TypeError, r"axis sim\.dt: values must be a list"),
    ({"sim.dt": [0.1]}, {"fixed": {"sim.warmup": 1.0}}, ValueError, r"sim\.warmup is not an axis"),
    (GOLDEN, {"seed": 3}, TypeError, "seed: given with the sweep file"),
])
def test_a_bad_dict_sweep_is_refused_naming_the_key(sweep, kwargs, error, match):
    with pytest.raises(error, match=match):
        pt.sweep(sweep, runs=1, **kwargs)


def test_a_dict_sweep_refuses_an_override_of_its_axis():
    with pytest.raises(pt.ConfigError, match=r"sim\.dt names an axis"):
        pt.sweep({"sim.dt": [0.1]}, runs=1, sim__dt=0.2)


# --- summary() -------------------------------------------------------------------------------

def number(text):
    return math.nan if text == "" else float(text)


def test_summary_agrees_exactly_with_the_command_line_summary(tmp_path):
    rows = pt.sweep(GOLDEN, runs=6)
    summary = rows.summary()
    out = cli("sweep", GOLDEN, "--runs", 6, "--out", tmp_path).stdout
    theirs = read_csv(tmp_path / "summary.csv")
    assert len(summary) == len(theirs) == 6
    for mine, row in zip(summary, theirs):
        assert mine["point"] == int(row["point"])
        assert mine["controller.algorithm"] == row["controller.algorithm"]
        assert mine["wind_sensor.sigma_a"] == float(row["wind_sensor.sigma_a"])
        for key in ("runs", "successes", "walls", "timeouts", "gave_up", "overhead_n"):
            assert mine[key] == int(row[key]), key
        for key in ("success_rate", "success_lo", "success_hi", "overhead_mean", "overhead_lo",
                    "overhead_hi", "overhead_median", "overhead_q1", "overhead_q3"):
            a, b = mine[key], number(row[key])
            assert a == b or (math.isnan(a) and math.isnan(b)), (key, a, b)  # bit for bit
    # the overhead's interval is the C++ percentile bootstrap's (results.json's boot_lo, boot_hi)
    points = json.loads((tmp_path / "results.json").read_text())["sweeps"][0]["points"]
    for mine, point in zip(summary, points):
        oh = point["stats"]["overhead"]
        for key, theirs in (("overhead_lo", oh["boot_lo"]), ("overhead_hi", oh["boot_hi"])):
            a, b = mine[key], math.nan if theirs is None else theirs
            assert a == b or (math.isnan(a) and math.isnan(b)), (key, a, b)  # bit for bit
    # and as the command prints them: "0.88 [0.53, 0.98]" and "1.254 [..."
    first = summary.to_numpy()
    printed = (f"{first['success_rate'][0]:.2f} [{first['success_lo'][0]:.2f}, "
               f"{first['success_hi'][0]:.2f}]")
    assert printed in out
    assert (f"{first['overhead_mean'][0]:.3f} [{first['overhead_lo'][0]:.3f}, "
            f"{first['overhead_hi'][0]:.3f}]") in out


def test_summary_counts_each_outcome_and_a_point_without_success_has_no_overhead():
    rows = pt.sweep(GOLDEN, runs=4)
    cols = rows.to_numpy()
    for s in rows.summary():
        sel = cols["point"] == s["point"]
        assert s["runs"] == sel.sum() == 4
        assert s["successes"] + s["walls"] + s["timeouts"] + s["gave_up"] == 4
        assert s["successes"] == cols["success"][sel].sum()
        lo, hi = pt._core.wilson_interval(s["successes"], 4)
        assert (s["success_lo"], s["success_hi"]) == (lo, hi)
        assert lo <= s["success_rate"] <= hi
        if s["successes"] == 0:
            assert s["overhead_n"] == 0 and math.isnan(s["overhead_mean"])
        else:
            mean = np.mean(cols["overhead"][sel & cols["success"]])
            assert s["overhead_mean"] == pytest.approx(mean, rel=1e-12)


# --- sweep_bars ------------------------------------------------------------------------------

def test_sweep_bars_draw_both_axes_of_a_two_axis_sweep():
    rows = pt.sweep(GOLDEN, runs=4)
    cols = rows.to_numpy()
    for axis, hue in (("controller.algorithm", "wind_sensor.sigma_a"),
                      ("wind_sensor.sigma_a", "controller.algorithm")):
        fig = plots.sweep_bars(rows, axis)
        left, right = fig.axes[:2]
        xs = list(dict.fromkeys(cols[axis].tolist()))
        hues = list(dict.fromkeys(cols[hue].tolist()))
        # one bar per (hue value, x value), group by group; no bar pools the other axis
        heights = [p.get_height() for p in left.patches]
        assert len(heights) == len(xs) * len(hues)
        for g, h in enumerate(hues):
            for i, x in enumerate(xs):
                sel = (cols[axis] == x) & (cols[hue] == h)
                assert sel.sum() == 4
                assert heights[g * len(xs) + i] == pytest.approx(100 * cols["success"][sel].mean())
        legend = [t.get_text() for t in left.get_legend().get_texts()]
        assert legend == [f"{h:g}" if isinstance(h, float) else h for h in hues]
        assert [t.get_text() for t in left.get_xticklabels()] == \
            [f"{x:g}" if isinstance(x, float) else x for x in xs]


def test_sweep_bars_refuse_a_sweep_that_they_would_pool():
    rows = pt.sweep({"controller.algorithm": ["casting", "surge-cast"],
                     "wind_sensor.sigma_a": [0.1, 0.5], "plume.sigma_p": [0.1, 0.15]},
                    runs=1, base=quick_base())
    with pytest.raises(ValueError, match=r"pool the runs over plume\.sigma_p"):
        plots.sweep_bars(rows, "controller.algorithm")
    with pytest.raises(ValueError, match=r"'wind\.vx' is not an axis"):
        plots.sweep_bars(rows, "wind.vx")
    # with one value of the third axis selected by hand it draws
    two = pt.sweep({"controller.algorithm": ["casting", "surge-cast"],
                    "wind_sensor.sigma_a": [0.1, 0.5]}, runs=1, base=quick_base())
    assert len(plots.sweep_bars(two).axes[0].patches) == 4


# --- pt.report -------------------------------------------------------------------------------

def test_report_of_rows_writes_the_pages_the_figure_and_the_table(tmp_path):
    rows = pt.sweep({"surge_cast.d_lost": [0.1, 0.4, 1.2]}, runs=4, name="dl",
                    title="surge-cast: d_lost",
                    base=quick_base(**{"controller.algorithm": "surge-cast"}))
    written = pt.report(rows, out=tmp_path / "r")
    names = {p.name for p in written}
    assert {"report.html", "report.md", "report.csv", "sweep_dl.png"} <= names
    assert (tmp_path / "r" / "figures" / "sweep_dl.png").stat().st_size > 10000
    md = (tmp_path / "r" / "report.md").read_text()
    assert md.startswith("# surge-cast: d_lost: success ")
    assert "data:image/png;base64," in (tmp_path / "r" / "report.html").read_text()
    # report.csv holds summary()'s numbers, one row per point
    table = read_csv(tmp_path / "r" / "report.csv")
    for mine, row in zip(rows.summary(), table):
        assert float(row["surge_cast.d_lost"]) == mine["surge_cast.d_lost"]
        for key in ("success_lo", "success_hi", "overhead_mean", "overhead_lo", "overhead_hi"):
            assert number(row[key]) == mine[key] or math.isnan(mine[key]), key
    assert len(table) == 3


def test_report_title_says_what_the_data_say():
    from plumetrace.report.sweep import report_title, sweep_views

    def results(rates):
        points = [{"index": i, "values": [v], "stats": {"runs": 20, "successes": k,
                                                        "success_rate": k / 20,
                                                        "success_lo": lo, "success_hi": hi}}
                  for i, (v, k, lo, hi) in enumerate(rates)]
        return {"sweeps": [{"name": "s", "title": "", "runs_per_point": 20, "points": points,
                            "axes": [{"key": "a.b", "values": [r[0] for r in rates]}]}]}

    falling = results([(1, 20, 0.84, 1.0), (2, 15, 0.53, 0.89), (3, 4, 0.08, 0.42)])
    assert report_title(sweep_views(falling)) == \
        "s: success falls with b from 100% at 1 to 20% at 3 (95% intervals apart)"
    close = results([(1, 18, 0.7, 0.97), (2, 12, 0.39, 0.78), (3, 16, 0.58, 0.92)])
    assert report_title(sweep_views(close)) == (
        "s: success is highest at b = 1 (90%) and lowest at b = 2 (60%), within each other's 95% "
        "intervals: the data do not separate them")
    # two axes: the one with more values along x, the findings per value of the other
    from plumetrace.report.sweep import per_value_findings, plot_axes
    two = {"sweeps": [{"name": "t", "title": "", "runs_per_point": 20, "points": [
        {"index": 3 * i + j, "values": [a, v],
         "stats": {"runs": 20, "successes": k, "success_lo": k / 20 - 0.3,
                   "success_hi": min(1.0, k / 20 + 0.1)}}
        for i, (a, ks) in enumerate((("x", (20, 12, 2)), ("y", (20, 20, 20))))
        for j, (v, k) in enumerate(zip((0.1, 0.2, 0.3), ks))],
        "axes": [{"key": "controller.algorithm", "values": ["x", "y"]},
                 {"key": "wind.vx", "values": [0.1, 0.2, 0.3]}]}]}
    view = sweep_views(two)[0]
    assert plot_axes(view) == (1, 0)
    assert per_value_findings(view) == [
        ["controller.algorithm = x: success falls with wind.vx from 100% at 0.1 to 10% at 0.3 "
         "(95% intervals apart)."],
        ["controller.algorithm = y: success is 100% at every wind.vx."]]
    flat = results([(1, 20, 0.84, 1.0), (2, 20, 0.84, 1.0)])
    assert report_title(sweep_views(flat)) == "s: success is 100% at every point"


def test_report_from_a_store_names_the_points_with_runs_missing(tmp_path):
    store = tmp_path / "results.sqlite"
    cli("sweep", grid_toml(tmp_path / "a.toml", "[0.1, 0.4]"), "--store", store, "--out",
        tmp_path / "a", "--quiet")
    grown = grid_toml(tmp_path / "b.toml", "[0.1, 0.2, 0.4]")
    with pytest.warns(UserWarning, match=r"surge_cast\.d_lost = 0\.2\): 0 of 3 runs"):
        written = pt.report(grown, store=store)
    assert written[0] == tmp_path / "report.html"  # the store's folder
    md = (tmp_path / "report.md").read_text()
    assert "0 of 3 (incomplete)" in md
    assert f"plumetrace sweep {grown} --store {store}" in md
    # the stored points' numbers are those of the sweep that computed them
    first = read_csv(tmp_path / "a" / "summary.csv")
    now = {r["surge_cast.d_lost"]: r for r in read_csv(tmp_path / "summary.csv")}
    for row in first:
        assert now[row["surge_cast.d_lost"]]["success_lo"] == row["success_lo"]
        assert now[row["surge_cast.d_lost"]]["overhead_mean"] == row["overhead_mean"]


def test_report_refuses_a_store_of_another_sweep_naming_it(tmp_path):
    store = tmp_path / "results.sqlite"
    cli("sweep", grid_toml(tmp_path / "a.toml", "[0.1]"), "--store", store, "--out",
        tmp_path / "a", "--quiet")
    with pytest.raises(pt.StoreError, match="seed 5; this sweep has seed 6"):
        pt.report(grid_toml(tmp_path / "b.toml", "[0.1]", seed=6), store=store)
    with pytest.raises(pt.StoreError, match="holds no run"):
        pt.report(grid_toml(tmp_path / "c.toml", "[0.7]"), store=store, out=tmp_path / "c")
    with pytest.raises(pt.StoreError, match="no such file"):
        pt.report(GOLDEN, store=tmp_path / "missing.sqlite", out=tmp_path / "m")
    with pytest.raises(TypeError, match="out: give the folder"):
        pt.report(pt.sweep(GOLDEN, runs=1))


def test_a_count_whose_interval_runs_off_the_overhead_panel_stays_inside_it():
    # two steady points and one of three successful runs whose t interval spans metres: the
    # limits follow the steady points, and its "n=3" is drawn at the panel's top edge with an arrow
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from plumetrace.report.data import Point
    from plumetrace.report.figures import draw_sweep_panels

    def point(n, mean, lo, hi):
        return Point(value=None, runs=8, successes=n, walls=8 - n, timeouts=0, gave_up=0,
                     rate=n / 8, rate_lo=0.0, rate_hi=1.0, oh_n=n, oh_mean=mean, oh_lo=lo,
                     oh_hi=hi, oh_median=mean, oh_q1=mean, oh_q3=mean, mean_time=None,
                     mean_losses=None, config_hash=None)

    fig = Figure()
    ax_rate, ax_oh = fig.subplots(1, 2)
    points = [point(8, 1.3, 1.2, 1.4), point(7, 1.5, 1.4, 1.6), point(3, 2.1, 0.3, 3.9)]
    draw_sweep_panels(ax_rate, ax_oh, ["a", "b", "c"], [(None, points)], "x")
    top = ax_oh.get_ylim()[1]
    assert top < 3.9
    labels = {t.get_text(): t.xy[1] for t in ax_oh.texts if t.get_text().startswith("n=")}
    assert labels["n=8"] == 1.4 and labels["n=7"] == 1.6
    assert labels["n=3 \u2191"] == top


# --- intervals that no data can contradict ---------------------------------------------------

@pytest.mark.parametrize("sweep, runs", [(TWO_PLUMES, 1), (TWO_PLUMES, 2), ("dict", 5)])
def test_no_printed_or_drawn_overhead_bound_is_below_one(tmp_path, sweep, runs):
    if sweep == "dict":
        sweep = {"surge_cast.d_lost": [0.1, 0.4, 1.2], "wind_sensor.sigma_a": [0.0, 0.6]}
        rows = pt.sweep(sweep, runs=runs, seed=7,
                        base=quick_base(**{"controller.algorithm": "surge-cast"}))
    else:
        rows = pt.sweep(sweep, runs=runs)
    found = overhead_bounds(rows, tmp_path / "report")
    assert not [(where, v) for where, v in found if v < 1.0]
    cols, summary = rows.to_numpy(), rows.summary()
    for r in summary:
        sel = (cols["point"] == r["point"]) & cols["success"]
        sample = cols["overhead"][sel]
        if r["overhead_n"] < 2:
            # one successful run: its mean, and no interval anywhere
            assert math.isnan(r["overhead_lo"]) and math.isnan(r["overhead_hi"])
        else:
            # the bootstrap interval lies within the sample, so within what overheads can be
            assert sample.min() <= r["overhead_lo"] <= r["overhead_hi"] <= sample.max()
    intervals = sum(1 for r in summary if not math.isnan(r["overhead_lo"]))
    assert intervals == 0 if runs == 1 else intervals > 0
    assert any(where.startswith("figure") for where, _ in found)
