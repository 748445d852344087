"""Write your own controller in Python.

A controller is an object with ``step(observation, wind) -> Command``; it may also have
``state`` and ``losses`` (attributes or methods) for traces and metrics. It sees only what the
built-in ones see (docs/model.md section 7.1):

- ``observation.time`` (s since release), ``observation.odor`` (bool),
  ``observation.odometry`` (x, y, heading relative to the release pose), ``observation.odometer``;
- ``wind.measure_wind_body()``: one noisy wind sample (m/s, robot frame); take it only when the
  algorithm needs it (each call counts in ``wind_samples``). The probe measures only during the
  ``step()`` call that received it: keep the sample, not the probe (a kept probe raises
  RuntimeError).

It answers with a ``Command``: ``go(heading)`` (turn on the spot, then drive straight),
``turn_to(heading)``, ``curve(curvature)`` (arc at the wheel-speed limit), ``stop()`` or
``abandon()`` (give up; the run fails). Headings are in the odometry frame; a heading or
curvature that is not finite raises ValueError where the command is made, and anything but a
Command returned from ``step`` raises TypeError.

A controller with keys of its own declares them and is registered under a name::

    class Zigzag(Controller):
        params = {"leg": Param(0.5, min=0.1, max=5.0, help="leg length (m)")}

        def step(self, observation, wind):
            ... self.params.leg ...            # this run's value

    register_controller("zigzag", Zigzag)
    pt.run(algorithm="zigzag", zigzag__leg=1.0)

Its keys (``zigzag.leg``) are then config keys of every scenario of this process, like a
built-in controller's: in ``Scenario.to_toml()``, settable, checked against their range, sweep
axes, and part of each sweep point's resolved config. Each run calls ``Zigzag(params, rng)``
with the run's values and its own controller random stream (``rng.uniform()``,
``rng.normal()``, ``rng.sign()``). Register before running; registering the same name again
replaces the Python controller of that name.

Without keys of its own, a factory ``f(scenario_dict, rng)`` may also be passed to
``plumetrace.run(controller=...)`` or ``plumetrace.sweep(controller=...)``: it is called once per
run with the resolved scenario and the run's controller random stream.
"""

import math
import numbers
from collections.abc import Mapping

from . import _core

Command = _core.Command
upwind_heading = _core.upwind_heading
guess_plume_side = _core.guess_plume_side
wrap_angle = _core.wrap_angle
controller_rng = _core.controller_rng  # controller_rng(seed, trial): the stream runs hand out


class Param:
    """A config key a controller declares: its default, range and one line of help.

    ``Param(0.5, min=0.1, max=5.0, help="leg length (m)")`` is a number (``min_open`` and
    ``max_open`` exclude a bound), ``Param(3, min=1, max=9)`` an integer (its default is an int),
    ``Param("left", choices=["left", "right"])`` one of some names. Bounds are inclusive."""

    def __init__(self, default, min=None, max=None, help="", choices=None, min_open=False,
                 max_open=False):
        if isinstance(default, bool):
            raise TypeError("Param: a default of True or False has no key type; use choices")
        if choices is not None:
            self.kind = "choice"
            choices = [str(c) for c in choices]
            if not isinstance(default, str) or default not in choices:
                raise ValueError(f"Param: the default {default!r} is not one of {choices}")
        elif isinstance(default, numbers.Integral):
            self.kind = "integer"
        elif isinstance(default, numbers.Real):
            self.kind = "number"
            if not math.isfinite(default):
                raise ValueError(f"Param: the default {default!r} is not finite")
        else:
            raise TypeError(f"Param: the default must be a number or, with choices, a str; got "
                            f"{type(default).__name__} {default!r}")
        self.default, self.min, self.max, self.help = default, min, max, str(help)
        self.choices, self.min_open, self.max_open = choices, bool(min_open), bool(max_open)

    def __repr__(self):
        return f"Param({self.default!r}, min={self.min!r}, max={self.max!r}, help={self.help!r})"

    def _spec(self, name):
        return {"name": str(name), "kind": self.kind, "default": self.default,
                "min": self.min, "max": self.max, "min_open": self.min_open,
                "max_open": self.max_open, "help": self.help, "choices": self.choices or []}


class ParamValues(Mapping):
    """One run's values of a controller's keys: ``params.leg`` or ``params["leg"]``."""

    def __init__(self, values):
        self._values = dict(values)

    def __getattr__(self, name):
        try:
            return self.__dict__["_values"][name]
        except KeyError:
            raise AttributeError(f"no key {name!r} (keys: {sorted(self._values)})") from None

    def __getitem__(self, name):
        return self._values[name]

    def __iter__(self):
        return iter(self._values)

    def __len__(self):
        return len(self._values)

    def __repr__(self):
        return f"ParamValues({self._values!r})"


def register_controller(name, factory, params=None):
    """Registers `factory` (a class or function ``f(params, rng)``) as the controller `name` of
    every run of this process, with the keys `params` declares (default: ``factory.params``), a
    dict of key name to Param. Returns `factory`. Raises ConfigError for a bad name or key, a
    name that is a table of the scenario or taken by a C++ controller."""
    declared = getattr(factory, "params", None) if params is None else params
    declared = {} if declared is None else declared
    if not isinstance(declared, Mapping):
        raise TypeError(f"register_controller('{name}'): params must be a dict of key name to "
                        f"Param, got {type(declared).__name__}")
    keys = []
    for key, p in declared.items():
        if not isinstance(p, Param):
            raise TypeError(f"{name}.{key}: declare it with plumetrace.Param(...), got "
                            f"{type(p).__name__} {p!r}")
        keys.append(p._spec(key))

    def make(values, rng):
        return factory(ParamValues(values), rng)

    _core.register_controller(str(name), keys, make)
    return factory


class Controller:
    """Optional base class: the motion primitives and the wind measurement as methods.

    On the class, ``params`` declares the controller's keys (a dict of Param); on an instance
    made by a run, ``self.params`` holds that run's values and ``self.rng`` its random stream."""

    state = "python"
    losses = 0
    params = {}

    def __init__(self, params=None, rng=None):
        self.params = params
        self.rng = rng

    def step(self, observation, wind):
        raise NotImplementedError

    @staticmethod
    def go(heading):
        """Turn toward `heading` (rad, odometry frame), then drive straight."""
        return Command.go(heading)

    @staticmethod
    def turn_to(heading):
        """Turn on the spot toward `heading`."""
        return Command.turn_to(heading)

    @staticmethod
    def curve(curvature):
        """Drive an arc of signed curvature (1/m) at the wheel-speed limit."""
        return Command.curve(curvature)

    @staticmethod
    def stop():
        """Stand still."""
        return Command.stop()

    @staticmethod
    def abandon():
        """Give up: the run ends as a failure."""
        return Command.abandon()

    @staticmethod
    def measure_upwind(wind, observation):
        """One wind sample turned into the upwind heading (rad, odometry frame)."""
        return upwind_heading(wind.measure_wind_body(), observation.odometry.heading)
