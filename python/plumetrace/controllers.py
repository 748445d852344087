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

A controller that says so reads more (``reads``, a class attribute or a method: a tuple of
names from ``READS``; docs/agents.md): with ``"concentration"``, ``observation.concentration``
is the odor sensor's reading after the sensor model (``odor.model``; NaN otherwise), whose
threshold test is ``observation.odor``; with ``"messages"``, ``observation.messages`` holds the
teammates' messages delivered this step (``Message``: ``from_``, the sender's index, ``sent``,
its time, ``data``, four numbers; also unpacked as ``from_, sent, data``), ordered by (sent,
from_), else it is empty. An unknown name raises ValueError naming it, at registration for a
class attribute, else when a run makes the controller.

It answers with a ``Command``: ``go(heading)`` (turn on the spot, then drive straight),
``turn_to(heading)``, ``curve(curvature)`` (arc at the wheel-speed limit), ``stop()``,
``abandon()`` (give up; the run fails) or ``declare_source(x, y)`` (the source is there, in the
odometry frame: the run ends, a success within ``supervisor.declaration_radius`` of it, else
``wrong_declaration``). ``command.with_message([a, b, c, d])`` also broadcasts four numbers to
the teammates in range (``team.range``), who read them from the next step on. Headings are in the
odometry frame; a heading, curvature, declared position or message number that is not finite
raises ValueError where the command is made, and anything but a Command returned from ``step``
raises TypeError.

A controller may show its state (``snapshot()``, for traces and the viewer): a dict with any of
``points`` (N x 2, odometry frame), ``weights`` (N), ``path`` (M x 2), ``grid`` (``x0``, ``y0``,
``dx``, ``dy``: the first cell's centre and the cell size; ``values``, an (ny, nx) array, rows
by y, or a flat one with ``nx`` and ``ny``) and ``estimate`` ((x, y) or None), or None.
``snapshot_of(controller)`` gives it back as a run takes it: checked (finite numbers, at most
200,000 of them, shapes that agree; a TypeError or ValueError names the key) and converted.

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
Message = _core.Message
READS = _core.READS  # the names a controller's ``reads`` may hold
upwind_heading = _core.upwind_heading
guess_plume_side = _core.guess_plume_side
wrap_angle = _core.wrap_angle
controller_rng = _core.controller_rng  # controller_rng(seed, trial): the stream runs hand out


# the range of an integer key: a C++ int
_INT_MIN, _INT_MAX = -2**31, 2**31 - 1


class Param:
    """A config key a controller declares: its default, range and one line of help.

    ``Param(0.5, min=0.1, max=5.0, help="leg length (m)")`` is a number (``min_open`` and
    ``max_open`` exclude a bound), ``Param(3, min=1, max=9)`` an integer (its default is an int,
    its bounds ints, all within +-2^31), ``Param("left", choices=["left", "right"])`` one of some
    names. Bounds are inclusive. Every field is checked here and again when the key is
    registered: a wrong type raises TypeError, a wrong value ValueError, naming the field (and,
    at registration, the key)."""

    def __init__(self, default, min=None, max=None, help="", choices=None, min_open=False,
                 max_open=False):
        (self.kind, self.default, self.min, self.max, self.help, self.choices, self.min_open,
         self.max_open) = _param_fields("Param", default, min, max, help, choices, min_open,
                                        max_open)

    def __repr__(self):
        return f"Param({self.default!r}, min={self.min!r}, max={self.max!r}, help={self.help!r})"

    def _spec(self, where, name):
        # why: checked again, as a field may have been changed since the Param was made
        kind, default, lo, hi, help_, choices, min_open, max_open = _param_fields(
            where, self.default, self.min, self.max, self.help, self.choices, self.min_open,
            self.max_open)
        return {"name": name, "kind": kind, "default": default, "min": lo, "max": hi,
                "min_open": min_open, "max_open": max_open, "help": help_,
                "choices": choices or []}


def _shown(value):
    """A value and its type for a message, short even for a huge or odd value."""
    try:
        text = repr(value)
    except Exception:  # noqa: BLE001 -- a repr that raises is shown by its type alone
        text = "?"
    text = text if len(text) <= 60 else text[:57] + "..."
    return f"{text} ({type(value).__name__})"


def _is_bool(value):
    return isinstance(value, bool) or type(value).__name__ == "bool_"


def _name_text(where, field, value):
    """`value` checked as one line of text (a help line or a choice's name)."""
    if not isinstance(value, str):
        raise TypeError(f"{where}: {field} {_shown(value)} is not a str")
    try:
        value.encode("utf-8")
    except UnicodeEncodeError:
        raise ValueError(f"{where}: {field} {_shown(value)} is not valid Unicode text") from None
    if any(c < " " or c == "\x7f" for c in value):
        raise ValueError(f"{where}: {field} {_shown(value)} holds a control character (one "
                         "line of text)")
    return value


def _param_fields(where, default, lo, hi, help_, choices, min_open, max_open):
    """A Param's fields checked and made plain Python values: (kind, default, min, max, help,
    choices, min_open, max_open); a TypeError or ValueError names `where` and the field."""
    help_ = _name_text(where, "help", help_)
    for field, flag in (("min_open", min_open), ("max_open", max_open)):
        if not _is_bool(flag):
            raise TypeError(f"{where}: {field} {_shown(flag)} is not True or False")
    min_open, max_open = bool(min_open), bool(max_open)
    if choices is not None:
        if not isinstance(choices, (list, tuple)):
            raise TypeError(f"{where}: choices {_shown(choices)} is not a list of names")
        choices = [_name_text(where, "choices", c) for c in choices]
        if not choices or any(not c or c != c.strip() for c in choices) or \
                len(set(choices)) != len(choices):
            raise ValueError(f"{where}: choices {_shown(choices)}: one or more distinct, "
                             "non-empty names without spaces at either end")
        for field, value, unset in (("min", lo, lo is None), ("max", hi, hi is None),
                                    ("min_open", min_open, not min_open),
                                    ("max_open", max_open, not max_open)):
            if not unset:
                raise ValueError(f"{where}: {field} {_shown(value)}: a key with choices has no "
                                 "range")
        if not isinstance(default, str) or default not in choices:
            raise ValueError(f"{where}: default {_shown(default)} is not one of {choices}")
        return "choice", default, None, None, help_, choices, False, False
    if _is_bool(default):
        raise TypeError(f"{where}: default {_shown(default)}: True or False has no key type; "
                        "use choices")
    if isinstance(default, numbers.Integral):
        kind = "integer"
        default = _bound_int(where, "default", default)
        lo = None if lo is None else _bound_int(where, "min", lo)
        hi = None if hi is None else _bound_int(where, "max", hi)
        if min_open or max_open:
            field = "min_open" if min_open else "max_open"
            raise ValueError(f"{where}: {field}: an integer key's bounds are inclusive (give "
                             "the next whole number instead)")
    elif isinstance(default, numbers.Real):
        kind = "number"
        default = _real(where, "default", default)
        if not math.isfinite(default):
            raise ValueError(f"{where}: default {default!r} is not finite")
        lo = None if lo is None else _real(where, "min", lo)
        hi = None if hi is None else _real(where, "max", hi)
    else:
        hint = " without choices" if isinstance(default, str) else ""
        raise TypeError(f"{where}: default {_shown(default)}{hint}: the default is a number "
                        "(an int for an integer key) or, with choices, one of them")
    if lo is not None and hi is not None and (lo > hi or (lo == hi and (min_open or max_open))):
        raise ValueError(f"{where}: min {lo!r} and max {hi!r} leave no value")
    below = lo is not None and (default <= lo if min_open else default < lo)
    above = hi is not None and (default >= hi if max_open else default > hi)
    if below or above:
        raise ValueError(f"{where}: the default {default!r} is not within the declared range "
                         f"(min {lo!r}, max {hi!r})")
    return kind, default, lo, hi, help_, None, min_open, max_open


def _bound_int(where, field, value):
    if _is_bool(value) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{where}: {field} {_shown(value)} is not an int (an integer key's "
                        "default and bounds are ints)")
    value = int(value)
    if not _INT_MIN <= value <= _INT_MAX:
        raise ValueError(f"{where}: {field} {value} is out of an integer key's range "
                         f"({_INT_MIN} to {_INT_MAX})")
    return value


def _real(where, field, value):
    if _is_bool(value) or not isinstance(value, numbers.Real):
        raise TypeError(f"{where}: {field} {_shown(value)} is not a number")
    try:
        value = float(value)
    except (OverflowError, ValueError):
        raise ValueError(f"{where}: {field} {_shown(value)} is out of a float's range") from None
    if math.isnan(value):
        raise ValueError(f"{where}: {field} is NaN")
    return value


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


# lists that register_controller appends each name it registers to, while code that wants to
# know what a file registers runs it (plumetrace.benchmark.load_controllers)
_RECORDERS = []


def register_controller(name, factory, params=None):
    """Registers `factory` (a class or function ``f(params, rng)``) as the controller `name` of
    every run of this process, with the keys `params` declares (default: ``factory.params``), a
    dict of key name to Param. Returns `factory`. Raises ConfigError for a bad name or key, a
    name that is a table of the scenario or taken by a C++ controller; TypeError or ValueError
    naming the key and the field for a declaration of the wrong type or value."""
    if not isinstance(name, str):
        raise TypeError(f"register_controller: the name {_shown(name)} is not a str")
    name = _name_text("register_controller", "the name", name)
    if not callable(factory):
        raise TypeError(f"register_controller('{name}'): the factory must be callable (a class "
                        f"or a function f(params, rng)), got {_shown(factory)}")
    reads = getattr(factory, "reads", None)
    if reads is not None and not callable(reads):
        # why: a class attribute is checked now, not at the first run
        _core.reads_flags(reads, f"register_controller('{name}')")
    declared = getattr(factory, "params", None) if params is None else params
    declared = {} if declared is None else declared
    if not isinstance(declared, Mapping):
        raise TypeError(f"register_controller('{name}'): params must be a dict of key name to "
                        f"Param, got {type(declared).__name__}")
    keys = []
    for key, p in declared.items():
        if not isinstance(key, str):
            raise TypeError(f"register_controller('{name}'): the key {_shown(key)} is not a str")
        key = _name_text(f"register_controller('{name}')", "the key", key)
        if not isinstance(p, Param):
            raise TypeError(f"{name}.{key}: declare it with plumetrace.Param(...), got "
                            f"{_shown(p)}")
        keys.append(p._spec(f"{name}.{key}", key))

    def make(values, rng):
        return factory(ParamValues(values), rng)

    _core.register_controller(name, keys, make)
    for names in _RECORDERS:
        names.append(name)
    return factory


class Controller:
    """Optional base class: the motion primitives and the wind measurement as methods.

    On the class, ``params`` declares the controller's keys (a dict of Param); on an instance
    made by a run, ``self.params`` holds that run's values and ``self.rng`` its random stream."""

    state = "python"
    losses = 0
    params = {}
    reads = ()  # what it reads besides the binary odor: names of READS

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
    def declare_source(x, y):
        """Declare the source at (x, y) (m, odometry frame): the run ends, scored there."""
        return Command.declare_source(x, y)

    @staticmethod
    def measure_upwind(wind, observation):
        """One wind sample turned into the upwind heading (rad, odometry frame)."""
        return upwind_heading(wind.measure_wind_body(), observation.odometry.heading)


def snapshot_of(controller):
    """The snapshot of `controller` (an object with ``snapshot()``) as a run takes it: checked and
    converted, as a dict of ``points`` (N x 2 array), ``weights`` (N), ``path`` (M x 2),
    ``grid`` (x0, y0, dx, dy, nx, ny and values of shape (ny, nx); None where there is none)
    and ``estimate`` ((x, y) or None). Raises the TypeError or ValueError a run would raise."""
    return _core.controller_snapshot(controller)
