"""Benchmarks run from Python and with controllers written in Python (plumetrace.benchmark,
docs/benchmark.md): the example controller enters in one call and gives the built-in's results,
a file that defines no controller is refused naming it, and worker processes write what one
process writes."""

import csv
import json
import multiprocessing
import os
import sqlite3
import subprocess
from pathlib import Path

import pytest

from conftest import plumetrace_with_core

ROOT = Path(__file__).resolve().parents[2]
SUITE = ROOT / "tests" / "support" / "mini_suite.toml"
EXAMPLE = ROOT / "examples" / "python_surge_cast.py"
CLI = os.environ.get("PLUMETRACE_CLI", str(ROOT / "build" / "plumetrace"))


@pytest.fixture(scope="module")
def pt():
    return plumetrace_with_core()


def _rows(out):
    with open(Path(out) / "runs.csv", newline="") as f:
        return list(csv.DictReader(f))


# the files a benchmark writes besides its store
EXPORTS = ("benchmark.json", "results.json", "runs.csv", "summary.csv", "teams.csv")


def _store(path):
    """What a results store holds, but its epoch (a random id of each store)."""
    with sqlite3.connect(path) as db:
        tables = {t: db.execute(f"SELECT * FROM {t} ORDER BY 1, 2, 3").fetchall()
                  for t in ("points", "runs")}
        tables["meta"] = db.execute(
            "SELECT * FROM meta WHERE key != 'epoch' ORDER BY key").fetchall()
    return tables


def _same_results(a, b):
    for name in EXPORTS:
        assert (a / name).read_bytes() == (b / name).read_bytes(), name
    assert _store(a / "results.sqlite") == _store(b / "results.sqlite")


def test_two_worker_processes_write_what_one_process_writes(pt, tmp_path):
    # the example beside the suite's built-in controllers, on the same plumes
    done = {n: pt.benchmark(SUITE, controllers=[EXAMPLE], runs=2, threads=n, out=tmp_path / str(n),
                            leaderboard=False) for n in (1, 2)}
    assert done[1]["computed"] == done[2]["computed"] == 12
    _same_results(tmp_path / "1", tmp_path / "2")
    assert {r["controller.algorithm"] for r in _rows(tmp_path / "2")} == {
        "py-surge-cast", "surge-spiral", "crw"}


def test_a_benchmark_stopped_in_worker_processes_resumes_to_the_same_results(pt, tmp_path,
                                                                           monkeypatch):
    # a controller whose runs take 0.1 s at least while stopped, each run on a plume of its own:
    # stopped at the first progress report (0.25 s in), two workers have finished at most 2 x 2
    # of the 8 runs and have 2 more in hand, which they finish
    slow = tmp_path / "slow.py"
    slow.write_text(
        "import os, time\n"
        "from plumetrace.controllers import Controller\n"
        "class SlowUpwind(Controller):\n"
        "    def __init__(self, params, rng):\n"
        "        super().__init__(params, rng)\n"
        "        time.sleep(float(os.environ.get('SLOW_UPWIND_DELAY', '0')))\n"
        "    def step(self, obs, wind):\n"
        "        return self.go(self.measure_upwind(wind, obs))\n")
    mine = dict(controllers=[slow], only=True, runs=4, share_plumes=False, leaderboard=False,
                supervisor__timeout=8.0)
    pt.benchmark(SUITE, threads=1, out=tmp_path / "one", **mine)

    def stop(done, total, seconds):
        raise KeyboardInterrupt

    with monkeypatch.context() as m, pytest.raises(KeyboardInterrupt):
        m.setenv("SLOW_UPWIND_DELAY", "0.1")
        pt.benchmark(SUITE, threads=2, out=tmp_path / "two", progress=stop, **mine)
    assert multiprocessing.active_children() == []
    again = pt.benchmark(SUITE, threads=2, out=tmp_path / "two", **mine)
    assert 1 <= again["skipped"] <= 6 and again["computed"] == 8 - again["skipped"]
    _same_results(tmp_path / "one", tmp_path / "two")


def test_a_python_controller_enters_beside_the_built_ins_with_their_results(pt, tmp_path):
    board = pt.benchmark(SUITE, controllers=[EXAMPLE, "surge-cast"], runs=3, out=tmp_path,
                         threads=2)
    manifest = json.loads((tmp_path / "benchmark.json").read_text())
    origins = {c["name"]: (c["origin"], c["file"]) for c in manifest["controllers"]}
    # the file as results record paths: relative to the current folder when inside it
    assert origins["py-surge-cast"][0] == "python"
    assert origins["py-surge-cast"][1].endswith("examples/python_surge_cast.py")
    assert origins["surge-cast"] == ("built-in", None)
    assert origins["crw"] == ("built-in", None)
    assert board["suite"]["digest"] == manifest["suite"]["digest"]
    assert (tmp_path / "leaderboard.html").is_file()
    # the Python surge-cast is the built-in one, run for run (examples/python_surge_cast.py)
    rows = _rows(tmp_path)
    fields = ("sweep", "trial", "outcome", "time_s", "d_t", "losses")
    mine = [tuple(r[k] for k in fields) for r in rows if r["controller.algorithm"] == "py-surge-cast"]
    theirs = [tuple(r[k] for k in fields) for r in rows if r["controller.algorithm"] == "surge-cast"]
    assert len(mine) == 6 and mine == theirs


def test_the_digest_is_the_same_with_or_without_a_python_controller(pt, tmp_path):
    a = pt.benchmark(SUITE, runs=2, out=tmp_path / "a", leaderboard=False)
    b = pt.benchmark(SUITE, controllers=[EXAMPLE], runs=2, out=tmp_path / "b", leaderboard=False)
    assert a["digest"] == b["digest"]
    assert (a["computed"], b["computed"]) == (8, 12)


def test_a_class_that_is_not_registered_enters_under_its_kebab_name(pt, tmp_path):
    mine = tmp_path / "mine.py"
    mine.write_text(
        "from plumetrace.controllers import Controller\n"
        "class StraightUpwindWalk(Controller):\n"
        "    def step(self, obs, wind):\n"
        "        return self.go(self.measure_upwind(wind, obs))\n")
    assert pt.benchmark.load_controllers(mine) == ["straight-upwind-walk"]
    done = pt.benchmark(SUITE, controllers=["straight-upwind-walk"], only=True, runs=2,
                        tasks=["near"], out=tmp_path / "out", leaderboard=False)
    assert done["total"] == 2


@pytest.mark.parametrize("text, words", [
    ("x = 1\n", "defines no controller"),
    ("raise RuntimeError('broken on purpose')\n", "importing it raised RuntimeError: broken on purpose"),
])
def test_a_file_without_a_controller_is_refused_naming_it(pt, tmp_path, text, words):
    bad = tmp_path / "bad.py"
    bad.write_text(text)
    with pytest.raises(ValueError) as e:
        pt.benchmark.load_controllers(bad)
    assert str(bad) in str(e.value) and words in str(e.value)


def test_the_command_hands_a_python_controller_to_python_and_refuses_a_bad_file(pt, tmp_path):
    out = tmp_path / "out"
    done = subprocess.run([CLI, "benchmark", str(SUITE), "--controller", str(EXAMPLE), "--only",
                           "--task", "near", "--runs", "2", "--out", str(out),
                           "--no-leaderboard"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "4 runs" not in done.stdout and "2 runs (2 computed now" in done.stdout
    assert {r["controller.algorithm"] for r in _rows(out)} == {"py-surge-cast"}
    bad = tmp_path / "nothing.py"
    bad.write_text("VALUE = 3\n")
    refused = subprocess.run([CLI, "benchmark", str(SUITE), "--controller", str(bad), "--out",
                              str(tmp_path / "o2")], capture_output=True, text=True)
    assert refused.returncode == 2
    assert f"--controller '{bad}': defines no controller" in refused.stderr


def test_compare_through_the_command_refuses_results_of_another_suite(pt, tmp_path):
    other = tmp_path / "other.toml"
    other.write_text(SUITE.read_text().replace('version = "1"', 'version = "2"')
                     .replace('"../../scenarios/', f'"{ROOT}/scenarios/'))
    pt.benchmark(SUITE, runs=2, out=tmp_path / "a")
    pt.benchmark(other, runs=2, out=tmp_path / "b")
    done = subprocess.run([CLI, "benchmark", "--compare", str(tmp_path / "a"),
                           str(tmp_path / "b")], capture_output=True, text=True)
    assert done.returncode == 2
    assert str(tmp_path / "a") in done.stderr and str(tmp_path / "b") in done.stderr
    same = subprocess.run([CLI, "benchmark", "--compare", str(tmp_path / "a"),
                           str(tmp_path / "a")], capture_output=True, text=True)
    assert same.returncode == 0, same.stderr


def test_the_command_reports_a_controller_that_raises_in_a_worker_with_its_traceback(pt, tmp_path):
    bad = tmp_path / "breaks.py"
    bad.write_text(
        "from plumetrace.controllers import Controller\n"
        "class Breaks(Controller):\n"
        "    def step(self, obs, wind):\n"
        "        return self.look(obs)\n"
        "    def look(self, obs):\n"
        "        raise LookupError('no plume here')\n")
    done = subprocess.run([CLI, "benchmark", str(SUITE), "--controller", str(bad), "--only",
                           "--runs", "2", "--threads", "2", "--out", str(tmp_path / "out")],
                          capture_output=True, text=True)
    assert done.returncode == 2, done.stderr
    # the controller's own traceback, down to its line, then what happened
    assert f'File "{bad}", line 6, in look' in done.stderr
    assert done.stderr.rstrip().endswith(
        "plumetrace: error: a controller raised LookupError: no plume here (traceback above); "
        "the runs finished before it are in the store: run the same command again once it is "
        "fixed")
