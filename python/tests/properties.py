"""Property checks of the Python layer (hypothesis): any config dict, any sweep arguments and any
controller behaviour give a result or a Python exception that names the problem, never a dead
interpreter. test_properties.py runs each check_* in a child interpreter, so that a crash fails
the test instead of ending pytest; the last line a check prints names the example it was on.

PLUMETRACE_PROPERTIES=long: ten times the examples, drawn at random (the default draws the same
examples every time, so that the suite is repeatable)."""

import math
import os
import re
import tempfile
import time
from datetime import timedelta
from numbers import Integral, Real
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import plumetrace as pt
from plumetrace.controllers import Command

LONG = os.environ.get("PLUMETRACE_PROPERTIES") == "long"


def bounded(examples):
    """Settings of a check: `examples` examples (ten times more, at random, when LONG)."""
    # why: no deadline per example on a shared machine; a hang is caught by the child's timeout
    return settings(max_examples=examples * (10 if LONG else 1), derandomize=not LONG,
                    database=None, deadline=timedelta(seconds=30),
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def show(kind, example):
    """Prints the example about to run (the last line names it when the interpreter dies)."""
    print(f"{kind}: {example!r}"[:2000], flush=True)


# -- config dicts -------------------------------------------------------------------------------

def _flat(prefix, tree):
    for k, v in tree.items():
        if isinstance(v, dict):
            yield from _flat(f"{prefix}{k}.", v)
        else:
            yield f"{prefix}{k}", v


DEFAULTS = dict(_flat("", pt.Scenario().to_dict()))
KEYS = sorted(DEFAULTS)
NAMES = sorted({v for v in DEFAULTS.values() if isinstance(v, str)} | set(pt.algorithms())
               | {"paper-literal", "disc", "ball", "constant", "surge-spiral"})

# why: with these left alone, a run lasts at most the sweep files' 2 s timeout at the default
# step; the rest (steps, filaments, samples per reading) decide how long a run takes
SLOW_KEYS = {"sim.dt", "sim.warmup", "supervisor.timeout", "plume.release_rate",
             "plume.capacity", "wind_sensor.samples"}
RUN_KEYS = [k for k in KEYS if k not in SLOW_KEYS]


class BadStr:
    """An object whose str() raises."""

    def __str__(self):
        raise ValueError("bad str")

    def __repr__(self):
        return "BadStr()"


def plausible(key):
    """Values near a key's default: a multiple of a number, another whole number, a name."""
    default = DEFAULTS[key]
    if isinstance(default, str):
        return st.sampled_from(NAMES)
    if isinstance(default, int):
        return st.integers(-2, 2 * default + 2)
    return st.one_of(st.floats(-3.0, 3.0).map(lambda f: f * (default or 1.0)),
                     st.floats(-100.0, 100.0), st.just(default))


def config_dicts(keys=KEYS, max_size=4):
    """Dicts of dotted keys: half of them near valid, the rest anything."""
    near = st.sampled_from(keys).flatmap(lambda k: st.tuples(st.just(k), plausible(k)))
    anything = st.tuples(config_keys(keys), config_values)
    return st.lists(st.one_of(near, anything), max_size=max_size).map(dict)


def config_keys(keys=KEYS):
    return st.one_of(st.sampled_from(keys), st.sampled_from(keys).map(str.upper),
                     st.sampled_from(keys).map(lambda k: k + ".x"),
                     st.sampled_from(keys).map(lambda k: k.split(".")[0]),
                     st.lists(st.text(min_size=0, max_size=8), min_size=1, max_size=40)
                     .map(".".join),
                     st.text(max_size=30))


numbers = st.one_of(st.integers(), st.integers(-10, 10), st.floats(),
                    st.floats(-1e3, 1e3, allow_nan=False), st.sampled_from([math.nan, math.inf,
                                                                            -math.inf, 0.0, -0.0,
                                                                            5e-324, 1e308]))
config_values = st.one_of(
    numbers, st.booleans(), st.none(), st.sampled_from(NAMES), st.text(max_size=20),
    st.integers().map(str), st.floats().map(str),
    st.sampled_from([np.float64(0.5), np.int64(3), np.bool_(True), np.float32(math.nan),
                     np.array([1.0, 2.0]), [1, 2], {"a": 1}, (0.5,), b"0.5", BadStr(),
                     object(), 1 + 2j]))


def _names_a_key(error, keys):
    # why: a check across keys (the start inside the arena) may name another key than the one set
    text = str(error)
    return any(str(k) in text or repr(k) in text for k in [*keys, *KEYS])


@bounded(1000)
@given(config_dicts())
def check_config_dicts_resolve_or_raise_naming_a_key(settings_):
    show("config", settings_)
    s = pt.Scenario()
    try:
        s.update(settings_)
    except (pt.ConfigError, TypeError, ValueError) as e:
        assert _names_a_key(e, settings_), f"{type(e).__name__}: {e}"
        return
    # what was taken reads back
    for key, value in settings_.items():
        got = s[key]
        assert got is not None


@bounded(150)
@given(config_dicts(RUN_KEYS, 3), st.integers(0, 2**64 - 1), st.booleans())
def check_runs_under_any_overrides_give_a_result_or_name_a_key(overrides, seed, trace):
    show("run", (overrides, seed, trace))
    fixed = {"sim.warmup": 0.0, "supervisor.timeout": 2.0}
    try:
        r = pt.run(seed=seed, trace=trace, overrides={**overrides, **fixed})
    except (pt.ConfigError, TypeError, ValueError) as e:
        assert _names_a_key(e, overrides), f"{type(e).__name__}: {e}"
        return
    assert r["outcome"] in ("success", "wall", "timeout", "gave_up")


# -- sweep arguments ----------------------------------------------------------------------------

SWEEP = """
name = "p"
runs = 1
seed = 3

[set]
sim.warmup = 0.0
supervisor.timeout = 2.0

[[axis]]
key = "wind_sensor.sigma_a"
values = [0.0, 0.3]
"""

_folder = Path(tempfile.mkdtemp(prefix="plumetrace_properties_"))
(_folder / "ok.toml").write_text(SWEEP)
(_folder / "empty.toml").write_text("")
(_folder / "junk.toml").write_text("name = [[[\n\x00\xff")
(_folder / "axisless.toml").write_text('name = "n"\nruns = 1\n')
PATHS = [_folder / "ok.toml", str(_folder / "ok.toml"), _folder / "empty.toml",
         _folder / "junk.toml", _folder / "axisless.toml", _folder / "missing.toml", _folder]

# why: a valid count runs that many runs, so valid counts stay small; the others are refused
# before any run (more than 10^7 runs in all, or not a whole number >= 0)
# (three branches of four valid)
valid_runs = st.integers(0, 2)
run_counts = st.one_of(valid_runs, valid_runs, valid_runs,
                       st.integers(max_value=-1), st.integers(min_value=5_000_001),
                       st.sampled_from([1.0, 1.5, math.nan, True, None, "2", np.int64(1)]))
valid_threads = st.sampled_from([0, 1, 2, 3, pt.MAX_THREADS, np.int64(2)])
thread_counts = st.one_of(valid_threads, valid_threads, valid_threads,
                          st.one_of(st.integers(max_value=-1),
                                    st.integers(min_value=pt.MAX_THREADS + 1),
                                    st.sampled_from([2.0, True, None, "2"])))
valid_flags = st.sampled_from([True, False, np.bool_(False)])
flags = st.one_of(valid_flags, valid_flags, valid_flags,
                  st.sampled_from([0, 1, "yes", None]))
paths = st.one_of(st.sampled_from(PATHS[:2]), st.sampled_from(PATHS[:2]), st.sampled_from(PATHS))


@bounded(300)
@given(paths, run_counts, thread_counts, flags,
       st.one_of(st.just({}), st.just({}), config_dicts(RUN_KEYS, 2)))
def check_sweeps_under_any_arguments_give_rows_or_name_the_argument(path, runs, threads, share,
                                                                      overrides):
    show("sweep", (path, runs, threads, share, overrides))
    names = ["runs", "threads", "share_plumes", str(path), *map(str, overrides)]
    try:
        rows = pt.sweep(path, runs=runs, threads=threads, share_plumes=share, overrides=overrides)
    except (pt.ConfigError, TypeError, ValueError, OSError) as e:
        assert any(n in str(e) for n in names), f"{type(e).__name__}: {e}"
        return
    assert len(rows) == 2 * (runs or 1)
    assert set(rows["outcome"]) <= {"success", "wall", "timeout", "gave_up"}


# -- controller behaviour -----------------------------------------------------------------------

class Refused(Exception):
    """An exception of the controller's own."""


EXCEPTIONS = {"ValueError": ValueError, "KeyError": KeyError, "RuntimeError": RuntimeError,
              "ZeroDivisionError": ZeroDivisionError, "Refused": Refused,
              "KeyboardInterrupt": KeyboardInterrupt}
JUNK = {"None": None, "0": 0, "1.5": 1.5, "'go'": "go", "(1, 2)": (1, 2), "[]": [],
        "Command": Command, "True": True, "object": object()}
JUNK_TYPE = {"None": "NoneType", "0": "int", "1.5": "float", "'go'": "str", "(1, 2)": "tuple",
             "[]": "list", "Command": "pybind11_type", "True": "bool", "object": "object"}

# one step's behaviour: (what, argument)
actions = st.one_of(
    st.tuples(st.sampled_from(["go", "turn_to", "curve"]), st.floats()),
    st.tuples(st.sampled_from(["stop", "abandon", "keep_probe", "use_kept", "sleep"]), st.none()),
    st.tuples(st.just("measure"), st.integers(0, 3)),
    st.tuples(st.just("raise"), st.sampled_from(sorted(EXCEPTIONS))),
    st.tuples(st.just("junk"), st.sampled_from(sorted(JUNK))),
    st.tuples(st.just("declare"), st.floats()),
    st.tuples(st.just("message"), st.lists(st.floats(), max_size=5)),
    st.tuples(st.just("state"), st.sampled_from(["lost", "", "\u00e9t\u00e9", 7, "bad"])),
    st.tuples(st.just("losses"), st.one_of(st.integers(), st.integers(0, 5),
                                           st.sampled_from(["2", 2.0, True, None,
                                                            np.int64(1)]))))


# what a controller says it reads (Controller.reads)
READS = [(), ("concentration",), ("messages", "concentration"), "binary",
         ("concentration", "smell")]
reads_of = st.sampled_from(READS)


def expected_error(plan, factory, reads=()):
    """What the plan makes a run raise: (type, text the message starts with), or None."""
    if factory == "raise":
        return ValueError, "the factory says no"
    if factory == "none":
        return TypeError, "the controller factory must return an object with a step"
    if "smell" in reads:
        return ValueError, "Planned.reads: unknown 'smell'"
    kept = False
    for what, arg in plan:
        if what in ("go", "turn_to", "curve") and not math.isfinite(arg):
            name = "curvature" if what == "curve" else "heading"
            return ValueError, f"Command.{what}: {name} must be a finite number"
        if what == "abandon":
            return None
        if what == "declare":
            if not math.isfinite(arg):
                return ValueError, "Command.declare_source: x must be a finite number"
            return None
        if what == "message" and (len(arg) != 4 or not all(map(math.isfinite, arg))):
            return ValueError, "Command.with_message: data"
        if what == "keep_probe":
            kept = True
        if what == "use_kept" and kept:
            return RuntimeError, "the wind probe is valid only during the step()"
        if what == "raise":
            return EXCEPTIONS[arg], f"raised by plan {arg}"
        if what == "junk":
            return TypeError, f"controller.step must return a Command, got {JUNK_TYPE[arg]}"
        if what == "state" and arg == "bad":
            return ValueError, "bad str"
        if what == "losses":
            value = arg
            if isinstance(value, (bool, str, float)) or value is None:
                return TypeError, "controller.losses must be an int, got"
            if not 0 <= int(value) <= 2**31 - 1:
                return ValueError, "controller.losses must be an int from 0 to"
    return None


def controller_of(plan, factory_kind, kept, reads=()):
    """A controller factory following `plan` step by step (then standing still), reading
    `reads`; probes it keeps go to `kept`."""

    class Planned:
        state = "python"
        losses = 0

        def __init__(self, scenario, rng):
            self.k = 0
            self.kept = None

        def step(self, obs, wind):
            # it sees the concentration if it asks for it; alone, no messages
            assert math.isnan(obs.concentration) != ("concentration" in reads)
            assert obs.messages == ()
            what, arg = plan[self.k] if self.k < len(plan) else ("stop", None)
            self.k += 1
            if what in ("go", "turn_to", "curve"):
                return getattr(Command, what)(arg)
            if what == "abandon":
                return Command.abandon()
            if what == "declare":
                return Command.declare_source(arg, 0.0)
            if what == "message":
                return Command.stop().with_message(arg)
            if what == "keep_probe":
                self.kept = wind
                kept.append(wind)
            elif what == "use_kept" and self.kept is not None:
                self.kept.measure_wind_body()
            elif what == "sleep":
                time.sleep(0.0005)
            elif what == "measure":
                for _ in range(arg):
                    x, y = wind.measure_wind_body()
                    assert math.isfinite(x) and math.isfinite(y)
            elif what == "raise":
                raise EXCEPTIONS[arg](f"raised by plan {arg}")
            elif what == "junk":
                return JUNK[arg]
            elif what == "state":
                self.state = BadStr() if arg == "bad" else arg
            elif what == "losses":
                self.losses = arg
            return Command.stop()

    Planned.reads = reads

    def factory(scenario, rng):
        if factory_kind == "raise":
            raise ValueError("the factory says no")
        if factory_kind == "none":
            return None
        return Planned(scenario, rng)

    return factory


def _check_outcome(call, plan, factory_kind, reads=()):
    kept = []
    expected = expected_error(plan, factory_kind, reads)
    try:
        result = call(controller_of(plan, factory_kind, kept, reads))
    except BaseException as e:  # noqa: B902 -- KeyboardInterrupt from a controller included
        assert expected is not None, f"unexpected {type(e).__name__}: {e}"
        kind, text = expected
        assert type(e) is kind and str(e).strip("'").startswith(text), (
            f"expected {kind.__name__}: {text}..., got {type(e).__name__}: {e}")
        result = None
    else:
        assert expected is None, f"expected {expected}, got a result"
    # a probe kept past its step refuses, whenever it is called
    for probe in kept:
        try:
            probe.measure_wind_body()
            raise AssertionError("a kept probe measured after its step")
        except RuntimeError as e:
            assert "valid only during the step()" in str(e)
    return result


plans = st.lists(actions, max_size=30)
factories = st.sampled_from(["ok", "ok", "ok", "ok", "raise", "none"])


@bounded(300)
@given(plans, factories, st.booleans(), reads_of)
def check_runs_with_any_controller_give_a_result_or_its_error(plan, factory_kind, trace, reads):
    show("run controller", (plan, factory_kind, trace, reads))
    r = _check_outcome(lambda f: pt.run(controller=f, trace=trace, sim__warmup=0.0,
                                        supervisor__timeout=2.0), plan, factory_kind, reads)
    if r is not None:
        assert r["outcome"] in ("timeout", "gave_up", "wall", "success", "wrong_declaration")
        if r["declaration_error"] is not None:
            assert r["outcome"] in ("success", "wrong_declaration")
        if r["outcome"] == "wrong_declaration":
            assert r["declaration_error"] is not None


# why: worker processes in one example of four, as each costs a fork of this interpreter
@bounded(300)
@given(plans, factories, st.integers(1, 3), st.booleans(),
       st.sampled_from([False, False, False, True]))
def check_sweeps_with_any_controller_give_rows_or_its_error(plan, factory_kind, threads, share,
                                                            processes):
    show("sweep controller", (plan, factory_kind, threads, share, processes))
    rows = _check_outcome(lambda f: pt.sweep(PATHS[0], runs=2, threads=threads,
                                             share_plumes=share, controller=f,
                                             processes=processes),
                          plan, factory_kind)
    if rows is not None:
        assert len(rows) == 4


@bounded(500)
@given(st.sampled_from(["go", "turn_to", "curve"]), st.one_of(st.floats(), numbers))
def check_commands_take_finite_numbers_and_refuse_the_rest(kind, value):
    show("command", (kind, value))
    try:
        c = getattr(Command, kind)(value)
    except ValueError as e:
        assert not math.isfinite(value) and "finite" in str(e)
    except TypeError:
        assert not isinstance(value, float)  # a huge int is no double
    else:
        assert math.isfinite(float(value))
        assert c.heading == (0.0 if kind == "curve" else float(value))


# -- a learning agent's actions (plumetrace.env) -------------------------------------------------

env_actions = st.one_of(st.floats(), st.integers(), st.lists(st.floats(), max_size=3),
                        st.sampled_from([None, "0.5", np.array([0.5]), np.array([[0.1]]),
                                         np.array([]), Command.stop(), Command.abandon(),
                                         Command.curve(2.0), object()]))


@bounded(150)
@given(st.one_of(st.integers(0, 2**64 - 1), st.integers(), st.floats(), st.none()),
       st.lists(st.one_of(env_actions, st.integers(-2, 5)), max_size=40), st.integers(1, 20),
       st.sampled_from([None, 1, 4]),
       st.sampled_from([("binary", "ideal"), ("concentration", "ideal"),
                        ("concentration", "first-order"), ("binary", "first-order")]))
def check_env_episodes_under_any_actions_step_or_name_the_action(seed, actions, interval,
                                                                  headings, sensing):
    from plumetrace.env import PlumeEnv

    show("env", (seed, actions, interval, headings, sensing))
    observation, model = sensing
    env = PlumeEnv(sim__warmup=0.0, supervisor__timeout=2.0, decision_interval=interval,
                   discrete_headings=headings, observation=observation, odor__model=model,
                   first_order__noise=50.0)
    try:
        env.reset(seed=seed)
    except (TypeError, ValueError) as e:
        assert "seed" in str(e)
        return
    for action in actions:
        try:
            obs, reward, terminated, truncated, info = env.step(action)
        except (TypeError, ValueError) as e:
            assert "action" in str(e) or "finite" in str(e), f"{type(e).__name__}: {e}"
            continue
        except RuntimeError as e:
            assert "reset()" in str(e)
            break
        assert obs.shape == (8,) and obs in env.observation_space and np.all(np.isfinite(obs))
        wind = env.measure_wind()
        assert all(math.isfinite(w) for w in wind)


@bounded(500)
@given(st.one_of(st.lists(st.one_of(st.floats(), numbers, st.sampled_from(["1", None, True])),
                          max_size=6),
                 st.sampled_from([None, "abcd", 4, b"1234", np.zeros(4), np.zeros((2, 2)),
                                  {"a": 1}])))
def check_messages_take_four_finite_numbers_and_refuse_the_rest(data):
    show("message", data)
    try:
        c = Command.go(0.5).with_message(data)
    except (TypeError, ValueError) as e:
        assert str(e).startswith("Command.with_message: data"), str(e)
    else:
        values = [float(v) for v in np.asarray(data, dtype=object).ravel()]
        assert c.send and c.message == tuple(values) and len(values) == 4
        assert all(map(math.isfinite, values)) and c.heading == 0.5


# a controller's snapshot: dicts of its keys with values of the right shape or of any kind, and
# other things
coords = st.floats(-1e3, 1e3)
# why: mapped, one branch of a one_of below rather than five
anything = st.one_of(st.none(), st.floats(), st.text(max_size=3),
                     st.sampled_from([object(), (1.0, 2.0), np.zeros((2, 3)), np.zeros(0),
                                      []])).map(lambda v: v)
pairs = st.one_of(st.lists(st.tuples(coords, coords), max_size=4),
                  st.lists(st.tuples(st.floats(), st.floats()), max_size=3), anything)
number_lists = st.one_of(st.lists(coords, max_size=5), st.lists(st.floats(), max_size=3),
                         anything)
grid_keys = {"x0": st.one_of(coords, anything), "y0": st.one_of(coords, anything),
             "dx": st.one_of(st.floats(0.01, 10.0), anything),
             "dy": st.one_of(st.floats(0.01, 10.0), anything),
             "nx": st.one_of(st.integers(-1, 4), anything),
             "ny": st.one_of(st.integers(-1, 4), anything),
             "values": st.one_of(st.lists(st.lists(coords, min_size=2, max_size=2), max_size=3),
                                 number_lists)}
grids = st.one_of(
    st.fixed_dictionaries({"x0": coords, "y0": coords, "dx": st.floats(0.01, 10.0),
                           "dy": st.floats(0.01, 10.0),
                           "values": st.lists(st.lists(coords, min_size=2, max_size=2),
                                              min_size=1, max_size=3)},
                          optional={"nx": st.integers(1, 3), "ny": st.integers(1, 3)}),
    st.fixed_dictionaries({}, optional={**grid_keys, "cells": anything}), anything)
snapshot_keys = {"points": pairs, "weights": number_lists, "path": pairs, "grid": grids,
                 "estimate": st.one_of(st.tuples(coords, coords), number_lists)}
snapshot_dicts = st.fixed_dictionaries({}, optional=snapshot_keys)


@bounded(500)
@given(snapshot_dicts)
def check_snapshots_convert_or_name_what_is_wrong(shown):
    from conftest import Shows
    from plumetrace.controllers import snapshot_of

    show("snapshot", shown)
    try:
        back = snapshot_of(Shows(shown))
    except (TypeError, ValueError) as e:
        assert str(e).startswith("Shows.snapshot()"), str(e)
        return
    assert back["points"].shape[1:] == (2,) and back["path"].shape[1:] == (2,)
    assert back["weights"].size in (0, len(back["points"]))
    for key in ("points", "weights", "path"):
        assert np.all(np.isfinite(back[key]))
    if back["grid"] is not None:
        g = back["grid"]
        assert g["values"].shape == (g["ny"], g["nx"]) and g["dx"] > 0 and g["dy"] > 0
    # what comes back converts to itself
    again = snapshot_of(Shows(back))
    for key in ("points", "weights", "path"):
        assert np.array_equal(again[key], back[key])
    assert again["estimate"] == back["estimate"]


# -- a controller's keys (Param) and its registration -------------------------------------------

class Abandons:
    """A controller that gives up at its first step, keeping the values it was made with."""

    made = []

    def __init__(self, params, rng):
        Abandons.made.append(dict(params))

    def step(self, obs, wind):
        return Command.abandon()


ODD = st.one_of(
    st.none(), st.booleans(), st.integers(), st.integers(-3, 3), st.floats(), st.text(max_size=4),
    st.sampled_from([np.float64(0.5), np.int64(3), np.bool_(True), np.float32(math.nan),
                     np.int8(-1), np.uint64(2**64 - 1), 2**70, -2**31 - 1, 10**400, 1 + 2j,
                     [1.0], (0.5,), {"a": 1}, b"x", BadStr(), object(), ["a", "b"], ("b", "a"),
                     [], ["a", "a"], [" a"], ["a\n"], [1, 2], "a\nb", "\ud800", math.inf,
                     -math.inf, math.nan, 0, 1.0]))
PARAM_FIELDS = ("min", "max", "min_open", "max_open", "help", "choices")
plausible_fields = {"min": st.one_of(st.none(), st.integers(-5, 0), st.floats(-5.0, 0.0)),
                    "max": st.one_of(st.none(), st.integers(5, 9), st.floats(5.0, 9.0)),
                    "min_open": st.booleans(), "max_open": st.booleans(),
                    "help": st.text(st.characters(min_codepoint=32, max_codepoint=0xd7ff),
                                    max_size=8),
                    "choices": st.just(["a", "b"])}
param_defaults = st.one_of(st.integers(-3, 3), st.floats(-3.0, 3.0), st.just("a"), ODD)
param_fields = st.fixed_dictionaries({}, optional={
    f: st.one_of(plausible_fields[f], plausible_fields[f], ODD) for f in PARAM_FIELDS})


def _quiet_run(**kwargs):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pt.ScenarioWarning)
        return pt.run(trace=False, sim__warmup=0.0, supervisor__timeout=1.0, **kwargs)


@bounded(300)
@given(param_defaults, param_fields)
def check_params_of_any_fields_register_and_run_or_name_the_field(default, fields):
    show("param", (default, fields))
    try:
        p = pt.Param(default, **fields)
    except (TypeError, ValueError) as e:
        named = ["default", *fields]
        assert str(e).startswith("Param: ") and any(
            re.search(rf"\b{f}\b", str(e)) for f in named), f"{type(e).__name__}: {e}"
        return
    # taken: the key registers, reads back, is set and reaches a run with its value
    pt.register_controller("prop_param", Abandons, params={"k": p})
    assert pt.Scenario()["prop_param.k"] == p.default
    assert pt.Scenario().update({"prop_param.k": p.default}) is None
    Abandons.made.clear()
    assert _quiet_run(algorithm="prop_param")["outcome"] == "gave_up"
    assert Abandons.made == [{"k": p.default}]
    assert type(Abandons.made[0]["k"]) is type(p.default)


def _factory(params, rng):
    return Abandons(params, rng)


class NoStep:
    def __init__(self, params, rng):
        pass


class FailsToStart:
    def __init__(self, params, rng):
        raise ValueError("this controller does not start")


FACTORIES = {"class": Abandons, "function": _factory, "no step": NoStep,
             "fails": FailsToStart, "not callable": 3, "None": None}
PLAIN = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_-]*")
controller_names = st.one_of(
    st.sampled_from(["prop-a", "prop_b", "Prop9", "robot", "sim", "surge-cast", "-x", "", "a b",
                     "a.b", "\u00e9t\u00e9", "a\x00", "\ud800", 7, None, b"x", BadStr()]),
    st.text(max_size=6), st.from_regex(PLAIN, fullmatch=True).map(lambda s: "p_" + s[:8]))
key_names = st.one_of(st.sampled_from(["leg", "k_2", "a-b", "", "two words", "x.y", 1, None]),
                      st.text(max_size=4))
declared = st.one_of(st.none(), st.sampled_from([3, "leg", ["leg"]]),
                     st.dictionaries(key_names, st.one_of(
                         st.just(pt.Param(0.5, min=0.0)), st.just(pt.Param(2, max=5)),
                         st.just(pt.Param("a", choices=["a", "b"])), ODD), max_size=3))


@bounded(300)
@given(controller_names, declared, st.sampled_from(sorted(FACTORIES)))
def check_register_controller_takes_any_names_params_and_classes_or_names_the_problem(
        name, params, factory):
    show("register", (name, params, factory))
    before = pt.algorithms()
    try:
        pt.register_controller(name, FACTORIES[factory], params=params)
    except (TypeError, ValueError) as e:  # ConfigError is a ValueError
        assert pt.algorithms() == before, "a refused registration registered"
        assert str(e) and "Unable to cast" not in str(e), f"{type(e).__name__}: {e}"
        return
    # registered: a plain name and a callable factory, whose keys run with their defaults
    assert isinstance(name, str) and PLAIN.fullmatch(name) and callable(FACTORIES[factory])
    assert name in pt.algorithms()
    try:
        r = _quiet_run(algorithm=name)
    except TypeError as e:
        assert factory == "no step" and "step" in str(e), str(e)
    except ValueError as e:
        assert factory == "fails" and "does not start" in str(e), str(e)
    else:
        assert factory in ("class", "function") and r["outcome"] == "gave_up"


# -- PlumeEnv.step: every argument type ----------------------------------------------------------

any_actions = st.one_of(
    st.floats(), st.integers(), st.integers(-2, 5), st.booleans(), st.none(), st.text(max_size=3),
    st.binary(max_size=2), st.complex_numbers(), st.lists(st.floats(), max_size=2),
    st.lists(st.integers(-1, 4), max_size=2),
    st.sampled_from([np.bool_(True), np.array([True]), np.float32(0.5), np.float16(math.inf),
                     np.int64(2), np.uint8(3), np.int64(-1), np.array([1]), np.array(2),
                     np.array([[0.25]]), np.array([0.1, 0.2]), np.array([]), np.array(["1"]),
                     np.array([None]), np.complex128(1j), 2**70, 10**400, [[1], [2, 3]],
                     {"a": 1}, (0.5,), object(), BadStr(), Command.stop(), Command.go(0.3),
                     math.nan, -math.inf]))


def _is_bool_action(a):
    return isinstance(a, (bool, np.bool_)) or (isinstance(a, np.ndarray) and a.dtype == bool)


@bounded(300)
@given(st.lists(any_actions, min_size=1, max_size=12), st.sampled_from([None, 4]))
def check_env_step_takes_a_heading_index_or_command_and_refuses_every_other_type(actions, n):
    from plumetrace.env import PlumeEnv

    show("env step", (actions, n))
    env = PlumeEnv(sim__warmup=0.0, supervisor__timeout=60.0, discrete_headings=n)
    env.reset(seed=3)
    for action in actions:
        before = env._world.time()
        try:
            env.step(action)
        except (TypeError, ValueError) as e:
            assert type(e) in (TypeError, ValueError) and str(e).startswith("action "), (
                f"{type(e).__name__}: {e}")
            assert env._world.time() == before, "a refused action moved the world"
            assert not isinstance(action, Command)
            continue
        # taken: a Command, or one real number that is no bool (finite; an index in range)
        assert not _is_bool_action(action) and action is not None
        if isinstance(action, Command):
            continue
        if isinstance(action, Real):
            value = action
        else:
            array = np.asarray(action).reshape(-1)
            assert array.size == 1 and array.dtype.kind in "iuf", repr(action)
            value = array[0].item()
        if n is None:
            assert math.isfinite(float(value))
        else:
            assert isinstance(value, Integral) and 0 <= int(value) < n
        if env._world.done():
            env.reset()


# -- intervals: no printed or drawn overhead bound below 1 ---------------------------------------

def synthetic_rows(points):
    """SweepRows of one axis "k" whose point i has the runs points[i]: an overhead (>= 1) for
    each successful run, None for a run that hit a wall."""
    from plumetrace.api import SweepRows

    cols = {k: [] for k in ("point", "k", "trial", "outcome", "success", "overhead")}
    for i, runs in enumerate(points):
        for t, overhead in enumerate(runs):
            cols["point"].append(i)
            cols["k"].append(0.5 * i)
            cols["trial"].append(t)
            cols["outcome"].append("wall" if overhead is None else "success")
            cols["success"].append(overhead is not None)
            cols["overhead"].append(math.nan if overhead is None else overhead)
    axes = [{"key": "k", "label": "k", "values": [0.5 * i for i in range(len(points))],
             "fixed": None}]
    return SweepRows("synthetic", {k: np.asarray(v) for k, v in cols.items()},
                     {"axes": axes, "runs_per_point": max(len(r) for r in points), "seed": 1})


overheads = st.one_of(st.none(), st.just(1.0), st.floats(1.0, 1.0 + 1e-9),
                      st.floats(1.0, 3.0), st.floats(1.0, 1e6))
sweep_points = st.lists(st.lists(overheads, min_size=1, max_size=6), min_size=1, max_size=5)


@bounded(400)
@given(sweep_points)
def check_summary_overhead_intervals_lie_within_the_successful_runs(points):
    show("summary", points)
    for r, runs in zip(synthetic_rows(points).summary(), points):
        sample = [v for v in runs if v is not None]
        lo, hi = r["overhead_lo"], r["overhead_hi"]
        if len(sample) < 2:
            assert math.isnan(lo) and math.isnan(hi)
        else:
            # within the sample (to rounding: a resample's mean of equal values may differ from
            # them by an ulp) and never below 1, as no mean of numbers >= 1 rounds below 1
            assert lo >= 1.0 and lo <= hi
            assert min(sample) * (1 - 1e-15) <= lo and hi <= max(sample) * (1 + 1e-15)


@bounded(10)
@given(sweep_points)
def check_no_printed_or_drawn_overhead_bound_is_below_one(points):
    import matplotlib

    matplotlib.use("Agg")
    from conftest import overhead_bounds

    show("report", points)
    out = Path(tempfile.mkdtemp(prefix="plumetrace_bounds_"))
    found = overhead_bounds(synthetic_rows(points), out)
    assert not [(where, v) for where, v in found if v < 1.0], found
