"""Controllers written in Python run in the same loop and sweep as the built-in ones."""

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()

ROOT = Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("python_surge_cast", ROOT / "examples" / "python_surge_cast.py")
example = importlib.util.module_from_spec(spec)
spec.loader.exec_module(example)


def test_python_surge_cast_equals_the_built_in_run_for_run():
    for trial in range(6):
        for sigma in (0.0, 0.5):
            mine = pt.run(algorithm="surge-cast", seed=13, trial=trial, controller=example.SurgeCast,
                          wind_sensor__sigma_a=sigma)
            builtin = pt.run(algorithm="surge-cast", seed=13, trial=trial, wind_sensor__sigma_a=sigma)
            for key in ("outcome", "time_s", "d_t", "d_u", "losses", "odor_fraction", "steps",
                        "wind_samples"):
                assert mine[key] == builtin[key], (trial, sigma, key)
            assert mine["trajectory"]["state"] == builtin["trajectory"]["state"]
            assert np.array_equal(mine["trajectory"]["x"], builtin["trajectory"]["x"])


def test_python_surge_cast_sweeps_like_the_built_in(tmp_path):
    sweep = tmp_path / "sc.toml"
    sweep.write_text(f"""
name = "sc"
scenario = "{ROOT / 'scenarios' / 'lochmatter2008.toml'}"
runs = 3
seed = 99
[set]
controller.algorithm = "surge-cast"
robot.start_x = 6.0
[[axis]]
key = "surge_cast.d_cast"
values = [0.135, 0.27, 0.54]
""")
    mine = pt.sweep(sweep, threads=2, controller=example.SurgeCast).to_numpy()
    builtin = pt.sweep(sweep, threads=2).to_numpy()
    for key in ("outcome", "d_t", "d_u", "time_s", "losses", "steps"):
        assert np.array_equal(mine[key], builtin[key]), key


def test_a_controller_sees_measurements_only():
    seen = []

    from plumetrace.controllers import Controller

    class Probe(Controller):
        def __init__(self, scenario, rng):
            pass

        def step(self, obs, wind):
            seen.append((obs.time, obs.odor, obs.odometry.x, obs.odometry.y, obs.odometry.heading))
            return self.go(0.0) if len(seen) < 50 else self.abandon()

    r = pt.run(controller=Probe, seed=1, trace=False)
    assert r["outcome"] == "gave_up" and r["steps"] == 50
    # odometry starts at the release pose: (0, 0) heading 0, whatever the arena frame
    assert seen[0][2:] == (0.0, 0.0, 0.0)


def test_the_examples_run(tmp_path):
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "python_surge_cast.py")],
                         check=True, capture_output=True, text=True).stdout
    assert out.count("identical to the built-in: True") == 3
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "python_env_and_plots.py"),
                          str(tmp_path)], check=True, capture_output=True, text=True).stdout
    assert out.count("episode") == 3
    assert (tmp_path / "trajectory.png").stat().st_size > 10000
    assert (tmp_path / "sweep.png").stat().st_size > 10000


def _page_data(path):
    html = Path(path).read_text()
    start = html.index('<script id="plumetrace-data" type="application/json">')
    start = html.index(">", start) + 1
    return json.loads(html[start:html.index("</script>", start)])


def test_runs_from_python_open_in_the_viewer(tmp_path):
    # a built-in run: the same page as `plumetrace run --view`, byte for byte
    mine = tmp_path / "casting.html"
    pt.run(algorithm="casting", seed=3, trial=1, view=mine, robot__start_x=6.0)
    cli = tmp_path / "cli.html"
    subprocess.run([os.environ["PLUMETRACE_CLI"], "run", "--algorithm", "casting", "--seed", "3",
                    "--trial", "1", "--set", "robot.start_x=6", "--view", str(cli)],
                   check=True, capture_output=True)
    assert mine.read_bytes() == cli.read_bytes()

    # a Python controller's run: its states and its name reach the page and the figure
    r = pt.run(algorithm="surge-cast", seed=13, trial=0, controller=example.SurgeCast,
               view=tmp_path / "mine.html")
    data = _page_data(tmp_path / "mine.html")
    assert data["result"]["algorithm"] == "python"
    assert data["steps"] == r["steps"] + 1
    assert set(data["states"]) == set(r["trajectory"]["state"])
    pt.run(algorithm="surge-cast", controller=example.SurgeCast, view=tmp_path / "mine.svg")
    assert (tmp_path / "mine.svg").read_text().startswith("<svg")

    with pytest.raises(ValueError, match="view 'x.png'"):
        pt.run(view="x.png")
