"""pt.probe: the plume alone as NumPy arrays, equal bit for bit to `plumetrace probe`."""

import json
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()

ROOT = Path(__file__).resolve().parents[2]
CLI = os.environ.get("PLUMETRACE_CLI", str(ROOT / "build" / "plumetrace"))


def cli(*args):
    return subprocess.run([CLI, *map(str, args)], check=True, capture_output=True, text=True).stdout


def test_points_and_centrelines_equal_the_command_exactly():
    points = [(2.0, 0.0, 0.02), (2.0, 0.1, 0.02), (8.0, 0.0, 0.02), (8.0, 0.2, 0.02),
              (14.5, 0.0, 0.02)]
    text = ";".join(",".join(repr(v) for v in p) for p in points)
    want = json.loads(cli("probe", "--points", text, "--warmup", 5, "--duration", 12,
                          "--interval", 0.5, "--seed", 3, "--centreline", "4;8;20",
                          "--slab", 0.3, "--set", "plume.sigma_p=0.05", "--json"))
    got = pt.probe(points=points, warmup=5, duration=12, interval=0.5, seed=3,
                   centreline=[4, 8, 20], slab=0.3, plume__sigma_p=0.05)
    assert isinstance(got["detect_fraction"], np.ndarray) and got["points"].shape == (5, 3)
    assert got["points"].tolist() == [list(p) for p in points]
    assert got["detect_fraction"].tolist() == [p["detect_fraction"] for p in want["points"]]
    assert got["mean_concentration"].tolist() == [p["mean_concentration"] for p in want["points"]]
    # every whole step nearest 0.5 s within the 12 s
    dt = pt.Scenario()["sim.dt"]
    steps = round(12 / dt) // round(0.5 / dt)
    assert got["samples"] == want["points"][0]["samples"] == steps
    # the plume is there: odor on its axis near the source, the concentration falls off it
    assert got["detect_fraction"][0] > 0 and got["mean_concentration"][0] > got["mean_concentration"][1]
    c = got["centrelines"]
    assert c["x"].tolist() == [4.0, 8.0, 20.0]
    for i, w in enumerate(want["centrelines"]):
        for key in ("samples", "empty"):
            assert c[key][i] == w[key], (i, key)
        for key in ("mean_y", "std_y"):  # null in JSON where no instant had a filament
            assert (math.isnan(c[key][i]) if w[key] is None else c[key][i] == w[key]), (i, key)
    assert c["samples"][2] == 0 and c["empty"][2] == steps  # 20 m: past the arena's end


def test_the_arena_grid_equals_the_commands_detection_map_exactly(tmp_path):
    cli("probe", "--points", "1,0,0", "--duration", 6, "--interval", 0.64, "--seed", 5,
        "--map", tmp_path / "map.json")
    want = json.loads((tmp_path / "map.json").read_text())
    got = pt.probe(grid="arena", duration=6, interval=0.64, seed=5)
    assert got["x"].tolist() == want["x"] and got["y"].tolist() == want["y"]
    assert got["z"] == want["z"] == pt.Scenario()["odor.height"]
    assert got["detect_fraction"].shape == (len(want["y"]), len(want["x"]))
    assert got["detect_fraction"].tolist() == want["fraction"]
    assert got["detect_fraction"].max() > 0  # the map is not empty
    assert got["mean_concentration"].shape == got["detect_fraction"].shape


def test_a_grid_is_its_points_row_major_by_y():
    x, y = np.linspace(2.0, 10.0, 5), np.array([-0.1, 0.0, 0.1])
    grid = pt.probe(grid=(x, y), duration=8, seed=2)
    assert grid["z"] == pt.Scenario()["odor.height"]
    xyz = [(xi, yj, grid["z"]) for yj in y for xi in x]
    points = pt.probe(points=xyz, duration=8, seed=2)
    assert grid["detect_fraction"].shape == (3, 5)
    assert grid["detect_fraction"].ravel().tolist() == points["detect_fraction"].tolist()
    assert grid["mean_concentration"].ravel().tolist() == points["mean_concentration"].tolist()
    # another height gives other numbers (the plume is not uniform in z)
    high = pt.probe(grid=(x, y, 0.5), duration=8, seed=2)
    assert high["z"] == 0.5
    assert high["mean_concentration"].tolist() != grid["mean_concentration"].tolist()
    # a scenario object and a file name give the scenario's plume
    s = pt.Scenario(plume__sigma_p=0.05)
    assert pt.probe(s, grid=(x, y), duration=8, seed=2)["mean_concentration"].tolist() == \
        pt.probe(grid=(x, y), duration=8, seed=2, plume__sigma_p=0.05)["mean_concentration"].tolist()


@pytest.mark.parametrize("kwargs, error, words", [
    ({}, ValueError, "either points"),
    ({"points": [(1, 0, 0)], "grid": "arena"}, ValueError, "either points"),
    ({"points": [(1, 0)]}, ValueError, "points"),
    ({"points": []}, ValueError, "points"),
    ({"points": [(1, 0, float("nan"))]}, ValueError, "points"),
    ({"points": "here"}, TypeError, "points"),
    ({"grid": "tunnel"}, ValueError, "grid"),
    ({"grid": ([1.0], [])}, ValueError, "grid"),
    ({"grid": 3}, TypeError, "grid"),
    ({"grid": ([1.0], [0.0], float("inf"))}, ValueError, "grid z"),
    ({"points": [(1, 0, 0)], "duration": 0}, ValueError, "duration"),
    ({"points": [(1, 0, 0)], "duration": 1, "interval": 2}, ValueError, "interval"),
    ({"points": [(1, 0, 0)], "warmup": -1}, ValueError, "warmup"),
    ({"points": [(1, 0, 0)], "seed": 1.5}, TypeError, "seed"),
    ({"points": [(1, 0, 0)], "seed": -1}, ValueError, "seed"),
    ({"points": [(1, 0, 0)], "slab": 0}, ValueError, "slab"),
    ({"points": [(1, 0, 0)], "centreline": [float("inf")]}, ValueError, "centreline"),
])
def test_bad_arguments_name_themselves(kwargs, error, words):
    with pytest.raises(error, match=words):
        pt.probe(**kwargs)


def test_a_bad_key_names_the_key():
    with pytest.raises(pt.ConfigError, match="plume.sigma_q"):
        pt.probe(points=[(1, 0, 0)], plume__sigma_q=1.0)
