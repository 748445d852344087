"""The run viewer and the report agree on colours, and a JSON trace reads in Python with NumPy
as docs/viewer.md says (trace format 3)."""

import base64
import json
import os
import subprocess
from pathlib import Path

import numpy as np

from conftest import plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()

from plumetrace.controllers import Controller  # noqa: E402
from plumetrace.report.figures import OUTCOME_COLORS, _state_palette  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
CLI = os.environ.get("PLUMETRACE_CLI", str(ROOT / "build" / "plumetrace"))


def page_data(path):
    html = Path(path).read_text()
    start = html.index('<script id="plumetrace-data" type="application/json">')
    start = html.index(">", start) + 1
    return json.loads(html[start:html.index("</script>", start)])


class Wanderer(Controller):
    """Drives upwind, then through states the report names and ones it does not."""

    NAMES = ("upwind", "mine-a", "cast2", "mine-b", "surge", "mine-c")

    def __init__(self, scenario, rng):
        self.steps = 0

    @property
    def state(self):
        return self.NAMES[min(self.steps // 40, len(self.NAMES) - 1)]

    def step(self, observation, wind):
        self.steps += 1
        if self.steps > 40 * len(self.NAMES):
            return self.abandon()
        return self.go(0.0 if self.steps % 80 < 40 else 0.1)


def test_the_viewer_colours_states_and_outcomes_as_the_report_does(tmp_path):
    view = tmp_path / "mine.html"
    result = pt.run(controller=lambda s, rng: Wanderer(s, rng), view=view)
    data = page_data(view)
    assert data["states"] == list(Wanderer.NAMES)
    palette = _state_palette(data["states"])
    assert data["style"]["states"] == [palette[name] for name in data["states"]]
    # every outcome the report colours, in the report's colour
    assert data["style"]["outcomes"] == OUTCOME_COLORS
    assert result["outcome"] == "gave_up"


def decode(snapshot, encoding, column):
    """A filament column of trace format 2: 16-bit little-endian words in base64, each
    origin + unit * word (docs/viewer.md)."""
    words = np.frombuffer(base64.b64decode(snapshot[column]), dtype="<u2")
    return encoding[column]["origin"] + encoding[column]["unit"] * words.astype(float)


def test_a_json_trace_reads_with_numpy_and_matches_the_run(tmp_path):
    trace_path = tmp_path / "run.json"
    subprocess.run([CLI, "run", "--seed", "4", "--trace", str(trace_path), "--snapshot-interval",
                    "5"], check=True, capture_output=True)
    trace = json.loads(trace_path.read_text())
    assert trace["plumetrace_trace"] == 3
    run = pt.run(seed=4, snapshot_interval=5.0)
    steps, traj = trace["steps"], run["trajectory"]
    # the steps as the run computed them; states as indices into their names
    assert np.array_equal(np.array(steps["x"]), traj["x"])
    assert np.array_equal(np.array(steps["true_wind_x"]), traj["true_wind_x"])
    assert [steps["state_names"][i] for i in steps["state"]] == traj["state"]
    assert np.array_equal(np.array(steps["odor"], dtype=bool), traj["odor"])
    # the filaments within half a step of their 16-bit code
    encoding = trace["snapshot_encoding"]
    assert len(trace["snapshots"]) == len(run["snapshots"])
    for stored, live in zip(trace["snapshots"], run["snapshots"]):
        assert stored["time"] == live["time"]
        for column in ("x", "y", "z", "w"):
            values = decode(stored, encoding, column)
            assert values.shape == live[column].shape
            assert np.max(np.abs(values - live[column])) <= 0.5 * encoding[column]["unit"] * 1.000001
