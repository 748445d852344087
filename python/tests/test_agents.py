"""What a Python controller reads and says beyond the paper's robot (docs/agents.md): the
concentration and teammates' messages it asks for, a declared source, messages it sends, and
the snapshot of its state."""

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from conftest import Shows, plumetrace_with_core

pt = plumetrace_with_core()
from plumetrace.controllers import (  # noqa: E402
    READS, Command, Controller, Message, snapshot_of)

ROOT = Path(__file__).resolve().parents[2]
DT = 0.032
THRESHOLD = 100.0  # odor.threshold


def _example():
    spec = importlib.util.spec_from_file_location("python_surge_cast",
                                                  ROOT / "examples" / "python_surge_cast.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    return example


def _upwind_reader(seen, reads):
    """A controller that drives upwind for 600 steps, keeping what it observed."""

    class Reader(Controller):
        def __init__(self, scenario, rng):
            self.heading = None

        def step(self, obs, wind):
            seen.append(obs)
            if self.heading is None:
                self.heading = self.measure_upwind(wind, obs)
            return self.go(self.heading) if len(seen) < 600 else self.abandon()

    Reader.reads = reads
    return Reader


# -- reads ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("model", ["ideal", "first-order"])
def test_a_controller_reading_concentration_gets_the_reading_its_odor_thresholds(model):
    seen = []
    r = pt.run(controller=_upwind_reader(seen, ("concentration",)), seed=2, odor__model=model,
               first_order__noise=5.0, wind_sensor__sigma_a=0.0)
    c = np.array([o.concentration for o in seen])
    odor = np.array([o.odor for o in seen])
    assert r["outcome"] == "gave_up" and len(seen) == 600
    assert np.all(np.isfinite(c)) and np.all(c >= 0.0)
    assert odor.any() and not odor.all()  # it met the plume's edges both ways
    assert np.array_equal(odor, c >= THRESHOLD)
    if model == "ideal":
        # the reading is the concentration the trace records where the robot sensed it
        assert np.array_equal(c, r["trajectory"]["concentration"][1:])


def test_a_controller_that_reads_nothing_more_gets_nan_and_no_messages():
    seen = []
    pt.run(controller=_upwind_reader(seen, ()), seed=2, team__count=2, trace=False)
    assert all(math.isnan(o.concentration) and o.messages == () for o in seen)
    # the base class reads nothing more; a name alone is one name
    assert Controller.reads == () and READS == ("binary", "concentration", "messages")
    seen.clear()
    pt.run(controller=_upwind_reader(seen, "concentration"), seed=2, trace=False)
    assert not math.isnan(seen[0].concentration)


def test_reading_more_leaves_the_run_of_a_controller_that_ignores_it_unchanged():
    # a Python surge-cast equals the built-in (test_controllers.py); asking for the
    # concentration or messages, which it ignores, changes nothing: the binary odor is the same
    # threshold test of the same reading
    example = _example()
    params = pt.Scenario()["py_surge_cast"]
    for reads in ((), ("binary",), ("concentration", "messages")):
        class Reads(example.SurgeCast):
            pass

        Reads.reads = reads
        for trial in range(3):
            mine = pt.run(controller=lambda scenario, rng: Reads(params, rng), seed=5,
                          trial=trial, wind_sensor__sigma_a=0.5)
            builtin = pt.run(algorithm="surge-cast", seed=5, trial=trial,
                             wind_sensor__sigma_a=0.5)
            for key in ("outcome", "time_s", "d_t", "d_u", "losses", "steps", "wind_samples",
                        "odor_fraction", "t_first_odor"):
                assert mine[key] == builtin[key], (reads, trial, key)
            assert np.array_equal(mine["trajectory"]["x"], builtin["trajectory"]["x"])


class _ReadsSmell(Controller):
    reads = ("concentration", "smell", "taste")

    def step(self, obs, wind):
        return self.stop()


def test_unknown_reads_are_refused_naming_them():
    # a class attribute at registration, before any run
    with pytest.raises(ValueError, match="'smell', 'taste'"):
        pt.register_controller("reads-smell", _ReadsSmell)
    assert "reads-smell" not in pt.algorithms()
    # a method, or a factory's object, when a run makes the controller
    with pytest.raises(ValueError, match=r"_ReadsSmell\.reads: unknown 'smell', 'taste'"):
        pt.run(controller=lambda scenario, rng: _ReadsSmell(), trace=False)

    class Method(Controller):
        def reads(self):
            return ["odour"]

        def step(self, obs, wind):
            return self.stop()

    pt.register_controller("reads-method", Method)
    with pytest.raises(ValueError, match="unknown 'odour'"):
        pt.run(algorithm="reads-method", trace=False)
    for bad, kind in ((3, "must be a name or a tuple of names .* got int"),
                      ((1,), r"1 \(int\) is not a name")):
        _ReadsSmell.reads = bad
        try:
            with pytest.raises(TypeError, match=kind):
                pt.register_controller("reads-bad", _ReadsSmell)
        finally:
            _ReadsSmell.reads = ("concentration", "smell", "taste")


# -- messages ------------------------------------------------------------------------------------

def _talkers(made, reads=("messages",)):
    class Talker(Controller):
        def __init__(self, scenario, rng):
            self.me = len(made)  # a team's controllers are made robot 0 first
            made.append(self)
            self.sent, self.got = [], []

        def step(self, obs, wind):
            self.got += [(round(obs.time / DT), m) for m in obs.messages]
            if obs.time > 2.0:
                return self.abandon()
            self.sent.append(round(obs.time / DT))
            return self.stop().with_message([self.me, obs.time, -1.5, 1e300])

    Talker.reads = reads
    return Talker


def test_messages_between_python_robots_of_a_team_arrive_one_step_later():
    made = []
    r = pt.run(controller=_talkers(made), seed=3, team__count=2, trace=False)
    assert r["outcome"] == "gave_up" and len(made) == 2
    for me, other in ((0, 1), (1, 0)):
        got = made[me].got
        assert [step for step, _ in got] == [step + 1 for step in made[other].sent]
        for step, m in got:
            assert isinstance(m, Message) and m.from_ == other
            assert m.data == (other, m.sent, -1.5, 1e300)
            assert round(m.sent / DT) == step - 1
            from_, sent, data = m  # a message unpacks too
            assert (from_, sent, data) == (m.from_, m.sent, m.data)
    assert repr(made[0].got[0][1]).startswith("Message(from_=1, sent=0.032")


def test_messages_reach_only_teammates_in_range_and_only_those_who_read_them():
    made = []
    pt.run(controller=_talkers(made), seed=3, team__count=2, team__range=0.1, trace=False)
    assert made[0].got == [] and made[1].got == []  # the robots start 0.3 m apart
    made = []
    pt.run(controller=_talkers(made, reads=()), seed=3, team__count=2, trace=False)
    assert made[0].got == [] and made[0].sent


# -- commands ------------------------------------------------------------------------------------

def test_commands_declare_and_carry_messages_and_refuse_what_is_not_finite():
    c = Command.declare_source(1.5, -2)
    assert c.declare and c.source == (1.5, -2.0) and not c.send and c.message is None
    m = Command.go(0.3).with_message(np.array([1, 2.5, -3, 4]))
    assert m.send and m.message == (1.0, 2.5, -3.0, 4.0) and m.heading == 0.3
    assert not Command.go(0.3).send and Command.stop().source is None
    for call, error, says in (
            (lambda: Command.declare_source(math.nan, 0.0), ValueError, "x must be a finite"),
            (lambda: Command.declare_source(0.0, math.inf), ValueError, "y must be a finite"),
            (lambda: m.with_message([1, 2, 3]), ValueError, "3 numbers, not 4"),
            (lambda: m.with_message([1, 2, 3, math.nan]), ValueError, "nan is not a finite"),
            (lambda: m.with_message([1, 2, 3, "4"]), TypeError, "'4' .str. is not a real"),
            (lambda: m.with_message([1, 2, 3, True]), TypeError, "True .bool. is not a real"),
            (lambda: m.with_message("abcd"), TypeError, "sequence of numbers, got str"),
            (lambda: m.with_message(None), TypeError, "sequence of numbers, got NoneType")):
        with pytest.raises(error, match=says):
            call()


def _declarer(offset, after=1.0):
    """A controller that stands still, then declares the source `offset` m beyond where it is
    (along the odometry frame's x)."""

    class Declarer(Controller):
        def __init__(self, scenario, rng):
            robot, source = scenario["robot"], scenario["source"]
            h = math.radians(robot["start_heading_deg"])
            dx, dy = source["x"] - robot["start_x"], source["y"] - robot["start_y"]
            # the source in the odometry frame: the release pose is its origin
            self.at = (math.cos(h) * dx + math.sin(h) * dy + offset,
                       -math.sin(h) * dx + math.cos(h) * dy)

        def step(self, obs, wind):
            return self.declare_source(*self.at) if obs.time >= after else self.stop()

    return Declarer


@pytest.mark.parametrize("rule", ["reach", "declare"])
@pytest.mark.parametrize("offset, outcome", [(0.0, "success"), (0.3, "success"),
                                             (2.0, "wrong_declaration")])
def test_a_python_declaration_ends_the_run_scored_by_its_error(rule, offset, outcome):
    r = pt.run(controller=_declarer(offset), seed=1, supervisor__success=rule, trace=False)
    assert r["outcome"] == outcome
    assert r["declaration_error"] == pytest.approx(offset, abs=1e-9)
    assert r["steps"] == round(1.0 / DT) + 1 and r["d_t"] == 0.0  # the declaring step moves not


def test_a_run_without_a_declaration_has_no_declaration_error():
    r = pt.run(controller=_upwind_reader([], ()), seed=1, trace=False)
    assert r["declaration_error"] is None


# -- snapshots -----------------------------------------------------------------------------------

def test_a_snapshot_dict_comes_back_as_a_run_takes_it():
    values = np.arange(6.0).reshape(2, 3)  # ny = 2 rows of nx = 3 cells
    shown = {"points": [(0.0, 1.0), (2.0, -3.5)], "weights": [0.25, 0.75],
             "path": np.array([[0.0, 0.0], [1.0, 0.5], [2.0, 1.0]]),
             "grid": {"x0": -1.0, "y0": 2.0, "dx": 0.5, "dy": 0.25, "values": values},
             "estimate": (4.0, -0.5)}
    back = snapshot_of(Shows(shown))
    assert np.array_equal(back["points"], np.array(shown["points"]))
    assert np.array_equal(back["weights"], shown["weights"])
    assert np.array_equal(back["path"], shown["path"])
    assert back["grid"].pop("values").tolist() == values.tolist()
    assert back["grid"] == {"x0": -1.0, "y0": 2.0, "dx": 0.5, "dy": 0.25, "nx": 3, "ny": 2}
    assert back["estimate"] == (4.0, -0.5)
    # and again: what comes back is a snapshot dict itself
    again = snapshot_of(Shows(snapshot_of(Shows(shown))))
    assert again["grid"]["values"].tolist() == values.tolist()
    # a flat grid with its counts, and nothing
    flat = snapshot_of(Shows({"grid": {"x0": 0, "y0": 0, "dx": 1, "dy": 1, "nx": 3, "ny": 2,
                                        "values": list(range(6))}}))
    assert flat["grid"]["values"].tolist() == values.tolist() and flat["estimate"] is None
    for empty in (snapshot_of(Shows(None)), snapshot_of(Shows({})),
                  snapshot_of(Controller())):
        assert empty["points"].shape == (0, 2) and empty["path"].shape == (0, 2)
        assert empty["grid"] is None and empty["estimate"] is None and empty["weights"].size == 0


@pytest.mark.parametrize("shown, error, says", [
    ([(0, 0)], TypeError, r"Shows\.snapshot\(\) must return a dict"),
    ({"particles": []}, ValueError, "unknown key 'particles'"),
    ({"points": [(0, 0, 1)]}, ValueError, r"points must be \(x, y\) pairs"),
    ({"points": [(0, math.nan)]}, ValueError, "points: nan is not a finite"),
    ({"points": [(0, "a")]}, ValueError, "points: not an array of numbers"),
    ({"points": [(0, 0)], "weights": [1, 2]}, ValueError, "2 weights for 1 points"),
    ({"grid": [1, 2]}, TypeError, "grid must be a dict"),
    ({"grid": {"x0": 0, "y0": 0, "dx": 1, "dy": 1}}, ValueError, "grid: no values"),
    ({"grid": {"x0": 0, "y0": 0, "dx": 0, "dy": 1, "values": [[1]]}}, ValueError, "dx and dy"),
    ({"grid": {"x0": 0, "y0": 0, "dx": 1, "dy": 1, "values": [1, 2]}}, ValueError, "no nx"),
    ({"grid": {"x0": 0, "y0": 0, "dx": 1, "dy": 1, "nx": 2, "ny": 2, "values": [1] * 5}},
     ValueError, "5 values for nx"),
    ({"grid": {"x0": 0, "y0": 0, "dx": 1, "dy": 1, "nx": 2, "values": [[1, 2, 3]]}},
     ValueError, r"values of shape \(1, 3\) for ny = 1, nx = 2"),
    ({"grid": {"x0": 0, "y0": 0, "dx": 1, "dy": 1, "cells": 1, "values": [[1]]}}, ValueError,
     "grid: unknown key 'cells'"),
    ({"estimate": (1, 2, 3)}, ValueError, "estimate must be"),
    ({"points": np.zeros((100_001, 2))}, ValueError, "200002 numbers; a snapshot holds at most"),
])
def test_a_snapshot_that_is_no_snapshot_is_refused_naming_the_key(shown, error, says):
    with pytest.raises(error, match=says):
        snapshot_of(Shows(shown))


# -- mixed teams: a robot's own keys (docs/agents.md, "Mixed teams") ----------------------------

def test_a_robots_own_keys_set_and_read_by_their_dotted_names_and_reach_that_robot_alone():
    s = pt.Scenario(team__count=2, team__contact="off", supervisor__timeout=200.0)
    s["member.1.controller.algorithm"] = "surge-spiral"
    s["member.1.surge_spiral.d_lost"] = 0.5
    assert s["member.1.controller.algorithm"] == "surge-spiral"
    assert s.to_dict()["member"]["1"]["surge_spiral"]["d_lost"] == 0.5
    assert s["controller.algorithm"] == "casting"
    assert "[member.1.controller]" in s.to_toml()
    # robot 1 of the mixed team takes the steps robot 1 of a surge-spiral team takes (contacts
    # off, so the robots never meet; its own streams are robot 1's either way)
    spiral = pt.Scenario(team__count=2, team__contact="off", supervisor__timeout=200.0,
                         controller__algorithm="surge-spiral", surge_spiral__d_lost=0.5)
    mixed_rows = pt.sweep({"team.count": [2]}, base=s, runs=2, seed=3).to_numpy()
    spiral_rows = pt.sweep({"team.count": [2]}, base=spiral, runs=2, seed=3).to_numpy()
    one = mixed_rows["agent"] == 1
    assert one.sum() == 2
    np.testing.assert_array_equal(mixed_rows["d_t"][one], spiral_rows["d_t"][spiral_rows["agent"] == 1])
    np.testing.assert_array_equal(mixed_rows["time_s"][one],
                                  spiral_rows["time_s"][spiral_rows["agent"] == 1])


def test_a_robots_own_key_of_the_world_or_of_a_robot_the_team_lacks_is_refused_naming_it():
    s = pt.Scenario(team__count=2)
    with pytest.raises(pt.ConfigError, match="member.1.wind.vx"):
        s["member.1.wind.vx"] = 0.5
    with pytest.raises(pt.ConfigError, match="member.3.controller.algorithm"):
        s["member.3.controller.algorithm"] = "surge-cast"
