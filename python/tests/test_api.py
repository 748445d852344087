"""The Python API against the command line: same scenarios, same runs, same sweeps."""

import csv
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()

ROOT = Path(__file__).resolve().parents[2]
CLI = os.environ.get("PLUMETRACE_CLI", str(ROOT / "build" / "plumetrace"))
GOLDEN = ROOT / "tests" / "golden" / "sweep.toml"


def cli(*args):
    return subprocess.run([CLI, *map(str, args)], check=True, capture_output=True, text=True).stdout


def test_default_scenario_resolves_like_plumetrace_config():
    # the command knows the controllers of the library; this process may have registered more
    # (examples/python_surge_cast.py does, on import), each with a table of its own
    # JSON has no infinity: the command writes "inf" (team.range), Python's dict holds the float
    mine = {t: {k: "inf" if v == float("inf") else v for k, v in keys.items()}
            for t, keys in pt.Scenario().to_dict().items()}
    theirs = json.loads(cli("config", "--json"))
    assert {k: v for k, v in mine.items() if k in theirs} == theirs
    assert set(mine) - set(theirs) <= {t.replace("-", "_") for t in pt.algorithms()}


def test_keys_read_and_change_by_dotted_path_or_attribute():
    s = pt.Scenario()
    assert s["wind.vx"] == 1.0 and s.wind.vx == 1.0  # the default reading (docs/fidelity.md)
    s.wind_sensor.sigma_a = 0.45
    s["controller.algorithm"] = "surge-spiral"
    assert s["wind_sensor.sigma_a"] == 0.45
    assert s.controller.algorithm == "surge-spiral"
    assert s.to_dict()["wind_sensor"]["sigma_a"] == 0.45
    # the TOML it prints reads back to the same scenario
    path = Path(os.environ.get("TMPDIR", "/tmp")) / f"pt_api_{os.getpid()}.toml"
    path.write_text(s.to_toml())
    assert pt.Scenario.load(path).to_dict() == s.to_dict()


def test_a_scenario_file_loads_with_its_preset():
    s = pt.Scenario.load(ROOT / "scenarios" / "paper-literal.toml")
    assert s.plume.kernel == "printed"
    assert math.isinf(s.plume.cutoff)


@pytest.mark.parametrize("key, value, named", [
    ("wind.vxx", 1.0, "wind.vxx"),
    ("controller.algorithm", "no-such-algorithm", "controller.algorithm"),
    ("sim.dt", -1.0, "sim.dt"),
    ("plume.capacity", 2.5, "plume.capacity"),
])
def test_invalid_keys_and_values_raise_naming_the_key(key, value, named):
    s = pt.Scenario()
    with pytest.raises(pt.ConfigError, match=named.replace(".", r"\.")):
        s[key] = value
    # the scenario is unchanged by the refused setting
    assert s.to_dict() == pt.Scenario().to_dict()


def test_ring_warm_up_and_start_follow_the_wind_and_the_source():
    paper = pt.Scenario()
    assert (paper.plume.capacity, paper.sim.warmup, paper.robot.start_x) == (1600, 20.0, 15.5)
    slow = pt.Scenario(wind__vx=0.5)
    assert (slow.plume.capacity, slow.sim.warmup) == (2880, 36.0)
    assert slow.warnings() == []
    moved = pt.Scenario(source__y=1.0, robot__start_offset_x=10.0)
    assert (moved.robot.start_x, moved.robot.start_y) == (11.0, 1.0)
    # set values win; "auto" derives again
    s = pt.Scenario(wind__vx=0.5, plume__capacity=1600)
    assert s.plume.capacity == 1600
    [warning] = s.warnings()
    assert "plume.capacity" in warning and "robot.start_offset_x" in warning
    s.plume.capacity = "auto"
    assert s.plume.capacity == 2880 and s.warnings() == []
    # a run says so too
    with pytest.warns(pt.ScenarioWarning, match="robot.start_y"):
        r = pt.run(source__y=1.0, robot__start_y=0.0, supervisor__timeout=1.0, trace=False)
    assert r["outcome"] == "timeout"


def test_unknown_key_on_read_raises():
    with pytest.raises(pt.ConfigError, match="nope"):
        pt.Scenario()["wind.nope"]


def test_run_equals_the_command_line_run():
    for algorithm, seed, trial in [("casting", 3, 2), ("surge-spiral", 11, 0), ("surge-cast", 5, 4)]:
        mine = pt.run(algorithm=algorithm, seed=seed, trial=trial, wind_sensor__sigma_a=0.3)
        theirs = json.loads(cli("run", "--algorithm", algorithm, "--seed", seed, "--trial", trial,
                                "--set", "wind_sensor.sigma_a=0.3", "--json"))
        traj = mine.pop("trajectory")
        mine.pop("snapshots")
        assert mine == theirs
        # the trajectory: one row at release, then one per step, as NumPy arrays
        assert len(traj["x"]) == mine["steps"] + 1 == len(traj["state"])
        assert traj["x"][0] == pt.Scenario()["robot.start_x"]
        assert isinstance(traj["odor"], np.ndarray) and traj["odor"].dtype == bool
        assert np.all(np.diff(traj["time"]) > 0)
        assert traj["odometer"][-1] == pytest.approx(mine["d_t"], abs=1e-12)


def test_snapshots_hold_the_filaments():
    r = pt.run(seed=2, snapshot_interval=5.0, supervisor__timeout=12.0)
    assert r["snapshots"], "no snapshot"
    first = r["snapshots"][0]
    assert len(first["x"]) == 1600 and first["time"] == 0.0


def read_runs_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_sweep_equals_the_command_line_sweep(tmp_path):
    rows = pt.sweep(GOLDEN, runs=3, threads=2)
    cli("sweep", GOLDEN, "--runs", 3, "--out", tmp_path, "--quiet", "--threads", 2)
    theirs = sorted(read_runs_csv(tmp_path / "runs.csv"),
                    key=lambda r: (int(r["point"]), int(r["trial"]), int(r["agent"])))
    assert len(rows) == len(theirs) == 18
    for mine, row in zip(rows, theirs):
        assert mine["point"] == int(row["point"]) and mine["trial"] == int(row["trial"])
        assert mine["outcome"] == row["outcome"]
        assert mine["controller.algorithm"] == row["controller.algorithm"]
        for key in ("d_t", "d_u", "time_s", "odor_fraction"):
            assert mine[key] == float(row[key]), key
        assert mine["steps"] == int(row["steps"]) and mine["losses"] == int(row["losses"])


def test_runs_sweep_rows_and_runs_csv_have_the_result_fields_in_order(tmp_path):
    names = [f["name"] for f in pt.result_fields()]
    assert names[:2] == ["outcome", "success"] and len(set(names)) == len(names)
    axes = ["controller.algorithm", "wind_sensor.sigma_a"]
    rows = pt.sweep(GOLDEN, runs=1)
    assert rows.keys() == ["point", *axes, "trial", "agent", "seed", *names]
    assert list(rows.to_numpy()) == rows.keys()
    assert set(pt.run(trace=False)) == {"algorithm", "seed", "trial", "agent", "version", *names}
    cli("sweep", GOLDEN, "--runs", 1, "--out", tmp_path, "--quiet")
    header = (tmp_path / "runs.csv").read_text().splitlines()[0].split(",")
    assert header == ["sweep", "point", *axes, "trial", "agent", "seed", "config_hash", *names]


def test_a_teams_sweep_has_a_row_per_robot_like_its_runs_csv(tmp_path):
    rows = pt.sweep(GOLDEN, runs=2, team__count=2)
    cols = rows.to_numpy()
    assert len(rows) == 6 * 2 * 2
    assert cols["agent"].tolist() == [0, 1] * 12
    assert cols["trial"].tolist() == [0, 0, 1, 1] * 6
    cli("sweep", GOLDEN, "--runs", 2, "--set", "team.count=2", "--out", tmp_path, "--quiet")
    theirs = read_runs_csv(tmp_path / "runs.csv")
    assert [(int(r["point"]), int(r["trial"]), int(r["agent"])) for r in theirs] == list(
        zip(cols["point"].tolist(), cols["trial"].tolist(), cols["agent"].tolist()))
    assert [float(r["d_t"]) for r in theirs] == cols["d_t"].tolist()
    teams = read_runs_csv(tmp_path / "teams.csv")
    assert len(teams) == 12 and {t["robots"] for t in teams} == {"2"}


def test_sweep_rows_do_not_depend_on_threads_or_plume_sharing():
    one = pt.sweep(GOLDEN, runs=2, threads=1, share_plumes=False).to_numpy()
    two = pt.sweep(GOLDEN, runs=2, threads=2).to_numpy()
    for key in one:
        floats = one[key].dtype.kind == "f"  # overhead is NaN where d_u <= 0
        assert np.array_equal(one[key], two[key], equal_nan=floats), key


def test_sweep_rows_convert_to_numpy_and_pandas():
    import pandas as pd  # Debian's python3-pandas (scripts/setup.sh): required, never skipped

    rows = pt.sweep(GOLDEN, runs=2)
    arrays = rows.to_numpy()
    assert arrays["d_t"].dtype == np.float64 and len(arrays["success"]) == len(rows) == 12
    df = rows.to_pandas()
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns) == rows.keys() and len(df) == len(rows)
    for key, values in arrays.items():
        if values.dtype.kind == "U":  # text columns become pandas' object columns
            assert df[key].dtype == object and df[key].tolist() == values.tolist(), key
        else:
            assert df[key].dtype == values.dtype, key
            assert np.array_equal(df[key].to_numpy(), values,
                                  equal_nan=values.dtype.kind == "f"), key
    # one DataFrame row per run, as iterating the rows gives them
    for i, row in enumerate(rows):
        assert {k: (None if v != v else v) for k, v in df.iloc[i].items()} == \
            {k: (None if v != v else v) for k, v in row.items()}, i
    # what a user does next: success rate per point, the same as counting the runs
    rate = df.groupby(["controller.algorithm", "wind_sensor.sigma_a"])["success"].mean()
    for (algorithm, sigma), value in rate.items():
        mine = (arrays["controller.algorithm"] == algorithm) & (arrays["wind_sensor.sigma_a"] == sigma)
        assert mine.sum() == 2 and value == arrays["success"][mine].mean()


def test_sweeps_release_the_gil():
    # while a sweep runs in another Python thread, this thread keeps running Python code;
    # were the GIL held for the whole sweep, the counter would barely move
    import threading
    import time

    done = threading.Event()
    worker = threading.Thread(target=lambda: (pt.sweep(GOLDEN, runs=6, threads=1), done.set()))
    ticks = 0
    worker.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    assert ticks > 20


# -- G15 on the Python surfaces: spaces around "auto" or a number are refused alike ------------

def _set_item(key, value):
    s = pt.Scenario()
    s[key] = value


def _set_attribute(key, value):
    table, name = key.split(".")
    setattr(getattr(pt.Scenario(), table), name, value)


def _env(key, value):
    from plumetrace.env import PlumeEnv

    PlumeEnv(**{key.replace(".", "__"): value})


_SURFACES = {
    "Scenario(**kwargs)": lambda k, v: pt.Scenario(**{k.replace(".", "__"): v}),
    "Scenario[key] = ": _set_item,
    "Scenario.table.key = ": _set_attribute,
    "Scenario.update": lambda k, v: pt.Scenario().update({k: v}),
    "run(**kwargs)": lambda k, v: pt.run(trace=False, **{k.replace(".", "__"): v}),
    "run(overrides=)": lambda k, v: pt.run(trace=False, overrides={k: v}),
    "sweep axis": lambda k, v: pt.sweep({k: [v]}, runs=1),
    "sweep overrides": lambda k, v: pt.sweep({"wind_sensor.sigma_a": [0.0]}, runs=1,
                                             overrides={k: v}),
    "sweep base": lambda k, v: pt.sweep({"wind_sensor.sigma_a": [0.0]}, runs=1,
                                        base=pt.Scenario(**{k.replace(".", "__"): v})),
    "sweep fixed": lambda k, v: pt.sweep({k: ["auto", 1.0]}, runs=1, fixed={k: v}),
    "PlumeEnv(**kwargs)": _env,
}


@pytest.mark.parametrize("surface", sorted(_SURFACES))
@pytest.mark.parametrize("value", ["auto ", " auto", "auto\t", "1 ", " 1", "1\n", "\u00a01"])
def test_values_with_spaces_are_refused_on_every_python_surface(surface, value):
    # sim.warmup takes a number or "auto": text with a space is neither, whatever it holds
    with pytest.raises(ValueError) as caught:
        _SURFACES[surface]("sim.warmup", value)
    assert "sim.warmup" in str(caught.value)
    # and a name with a space is no name of a choice key
    if surface != "sweep fixed":
        with pytest.raises(ValueError, match=r"controller\.algorithm"):
            _SURFACES[surface]("controller.algorithm", "casting ")


def test_a_param_default_or_choice_with_spaces_is_refused():
    with pytest.raises(ValueError, match="not one of"):
        pt.Param("left ", choices=["left", "right"])
    with pytest.raises(ValueError, match="without spaces at either end"):
        pt.Param(" left", choices=[" left", "right"])
    with pytest.raises(TypeError, match="default '1 '"):
        pt.Param("1 ")


# -- errors name the key, with no "Python:" before it ------------------------------------------

@pytest.mark.parametrize("call", [
    lambda: pt.Scenario(sim__warmup="x"),
    lambda: pt.Scenario().update({"sim.warmup": "x"}),
    lambda: pt.run(sim__warmup="x"),
    lambda: pt.sweep({"wind_sensor.sigma_a": [0.0]}, runs=1, sim__warmup="x"),
])
def test_errors_start_with_the_key_without_a_python_prefix(call):
    with pytest.raises(pt.ConfigError) as caught:
        call()
    assert str(caught.value) == "sim.warmup: must be a number >= 0 or 'auto' (got 'x')"


def test_an_override_of_an_axis_is_named_without_a_prefix():
    with pytest.raises(pt.ConfigError) as caught:
        pt.sweep({"sim.dt": [0.1]}, runs=1, sim__dt=0.2)
    assert str(caught.value) == "sweep sweep: sim.dt names an axis of the sweep"


def test_the_command_line_still_names_where_a_setting_came_from(tmp_path):
    done = subprocess.run([CLI, "run", "--set", "sim.warmup=x"], capture_output=True, text=True)
    assert done.returncode == 2 and "--set: sim.warmup" in done.stderr
    scenario = tmp_path / "p.toml"
    scenario.write_text("[sim]\nwarmup = \"x\"\n")
    done = subprocess.run([CLI, "run", str(scenario)], capture_output=True, text=True)
    assert done.returncode == 2 and f"{scenario}: sim.warmup" in done.stderr


# -- dir(plumetrace) shows the API --------------------------------------------------------------

def test_dir_lists_the_api_and_the_submodules_and_each_resolves():
    names = dir(pt)
    for name in [*pt.__all__, "controllers", "env", "plots", "report", "studies", "sweeps",
                 "calibrate", "evidence", "vector", "team_env", "learn", "benchmark"]:
        assert name in names, name
        assert getattr(pt, name) is not None
    assert "report" in pt.__all__ and callable(pt.report)
    assert not [n for n in names if n.startswith("_") and not n.startswith("__")], names
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        pt.nothing  # noqa: B018


def test_a_simd_path_the_machine_does_not_run_fails_when_the_core_loads_naming_the_variable():
    env = dict(os.environ, PLUMETRACE_SIMD="fast")
    r = subprocess.run([sys.executable, "-c", "import plumetrace._core"], env=env,
                       capture_output=True, text=True)
    assert r.returncode != 0
    assert 'ImportError: PLUMETRACE_SIMD: unknown path "fast" (one of auto, scalar' in r.stderr
