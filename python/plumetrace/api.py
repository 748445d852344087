"""Scenarios, runs and sweeps: the Python face of the C++ core (no model logic here)."""

import json
import math
import numbers
import warnings

from . import _core
from .controllers import Param, register_controller  # noqa: F401  (plumetrace.Param, ...)

ConfigError = _core.ConfigError
StoreError = _core.StoreError
__version__ = _core.__version__
MAX_THREADS = _core.MAX_THREADS  # the most worker threads a sweep may ask for (docs/reliability.md)


class ScenarioWarning(UserWarning):
    """A scenario that runs but is unlikely to be tracked: the robot starts outside odor, or the
    plume cannot reach it within the warm-up (docs/scenarios.md); the message names the keys."""


def algorithms():
    """Names of the registered algorithms: the built-in ones, then those registered in this
    process (register_controller)."""
    return list(_core.algorithms())


def result_fields():
    """The per-run metrics in column order, each a dict with ``name``, ``unit`` ("" for none)
    and ``nullable`` (NaN allowed). A run's dict has these keys and a sweep's rows these columns,
    after ``point``, the axis keys, ``trial``, ``agent`` (the robot's index in its team, 0 for a
    robot alone) and ``seed``."""
    return list(_core.result_fields())


class Scenario:
    """A scenario: an optional TOML file plus overrides, resolved and validated by the core.

    Read and change any key by its dotted path (``s["wind.vx"]``) or as nested attributes
    (``s.wind.vx``); an unknown key or a bad value raises ``ConfigError`` naming the key.
    """

    def __init__(self, path=None, **overrides):
        object.__setattr__(self, "_path", None if path is None else str(path))
        object.__setattr__(self, "_overrides", [])
        object.__setattr__(self, "_resolved", None)
        self.update(_dotted(overrides))

    @classmethod
    def load(cls, path):
        """The scenario of a TOML file."""
        return cls(path)

    def copy(self):
        """An independent copy."""
        other = Scenario(self._path)
        other.update(dict(self._overrides))
        return other

    def update(self, settings):
        """Sets several dotted keys at once (a dict); checked together."""
        added = [(str(k), _config_value(str(k), v)) for k, v in dict(settings).items()]
        resolved = _load_json(_core.resolve_json(self._path, self._overrides + added))
        self._overrides.extend(added)
        object.__setattr__(self, "_resolved", resolved)

    def to_dict(self):
        """The fully resolved configuration as a nested dict (as `plumetrace config --json`, with
        infinite numbers as float('inf') where JSON has the string "inf")."""
        return json.loads(json.dumps(self._resolved))  # a copy the caller may change

    def to_toml(self):
        """The fully resolved configuration as TOML (reads back to the same scenario)."""
        return _core.resolve_toml(self._path, self._overrides)

    def warnings(self):
        """Why this scenario is unlikely to be tracked, one sentence each naming the keys to
        change (the robot starts outside odor, the plume cannot reach it); [] if nothing."""
        return list(_core.scenario_warnings(self._path, self._overrides))

    def __getitem__(self, key):
        renamed = _core.renamed_key(str(key))
        if renamed is not None:
            # why: an old name reads as it sets, for one version, with the warning it sets with
            warnings.warn(renamed[1], DeprecationWarning, stacklevel=2)
            key = renamed[0]
        node = self.to_dict()
        for part in str(key).split("."):
            if not isinstance(node, dict) or part not in node:
                raise ConfigError(f"unknown config key '{key}'")
            node = node[part]
        return node

    def __setitem__(self, key, value):
        self.update({key: value})

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        value = self[name]
        return _Section(self, name) if isinstance(value, dict) else value

    def __setattr__(self, name, value):
        self[name] = value

    def __repr__(self):
        return f"Scenario({self._path!r}, {dict(self._overrides)!r})"

    def _settings(self):
        return self._path, list(self._overrides)


class _Section:
    """A table of a scenario, for attribute access (``s.wind.vx``)."""

    def __init__(self, scenario, prefix):
        object.__setattr__(self, "_scenario", scenario)
        object.__setattr__(self, "_prefix", prefix)

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        key = f"{self._prefix}.{name}"
        value = self._scenario[key]
        return _Section(self._scenario, key) if isinstance(value, dict) else value

    def __setattr__(self, name, value):
        self._scenario[f"{self._prefix}.{name}"] = value

    def __repr__(self):
        return f"<{self._prefix}: {self._scenario[self._prefix]!r}>"


def run(scenario=None, algorithm=None, seed=1, trial=0, trace=True, snapshot_interval=None,
        controller=None, overrides=None, view=None, **kwargs):
    """One run. Returns a dict with the keys of `plumetrace run --json` and, with `trace`,
    ``trajectory`` (NumPy arrays per step: time, x, y, heading, odometer, odor,
    concentration, wind_samples, wind_x, wind_y (the last sample, robot frame), true_wind_x,
    true_wind_y (the true wind at the robot, world frame), and state names) and ``snapshots``
    (filaments every `snapshot_interval` s).

    `scenario`: a Scenario, a TOML path or None (defaults). `overrides` (dict of dotted keys)
    and keyword arguments (``wind_sensor__sigma_a=0.3`` for ``wind_sensor.sigma_a``) change
    keys for this run. `controller`: a factory ``f(scenario_dict, rng)`` returning an object
    with ``step(observation, wind) -> Command`` (see plumetrace.controllers) instead of the
    scenario's algorithm. `view`: a ``.html`` path for the animated run viewer or a ``.svg`` path
    for the static figure (as ``plumetrace run --view``); filaments are then recorded every
    0.25 s unless `snapshot_interval` says otherwise (default without a view: none).
    """
    path, settings = _settings(scenario, algorithm, overrides, kwargs)
    for message in _core.scenario_warnings(path, settings):
        warnings.warn(message, ScenarioWarning, stacklevel=2)
    if snapshot_interval is None:
        snapshot_interval = 0.25 if view is not None else 0.0
    return _core.run(path, settings, _whole("seed", seed, 0, 2**64 - 1),
                     _whole("trial", trial, 0, 2**64 - 1), _flag("trace", trace),
                     _interval("snapshot_interval", snapshot_interval), controller,
                     None if view is None else str(view))


def sweep(sweep, runs=0, threads=0, share_plumes=True, controller=None, overrides=None,
          base=None, seed=None, name=None, title=None, fixed=None, labels=None, processes=True,
          **kwargs):
    """Every run of a sweep, in C++ threads with the GIL released. `sweep`: a sweep file (the
    format `plumetrace sweep` reads), or a dict of axes ``{dotted key: values}`` (the first key
    varying slowest) on the base scenario `base` (a Scenario, a scenario file or None), with
    master seed `seed` (default 1), `name` and `title` (plumetrace.sweeps.sweep_spec). `runs`:
    runs per point (0: the file's, 10 for a dict); `threads`: 0 for all cores;
    `overrides`/keyword arguments change keys of the base scenario (not an axis key);
    `controller`: as in run(). Returns SweepRows, one row per robot of each run (column
    ``agent``: its index in the team, 0 for a robot alone), sorted by (point, trial, agent).

    When a controller written in Python decides (`controller`, or one registered with
    register_controller), the runs go to `threads` worker processes forked from this one (0:
    one per core), each deciding in its own interpreter, with the same rows, bit for bit, as one
    process; `processes=False` keeps them in this process, where a Python controller decides one
    step at a time whatever `threads` says (docs/python.md, "On every core: worker processes").
    A worker's objects are its own: what a controller changes outside itself (a list it appends
    to) is not seen here.

    Ctrl-C, or an exception a controller raises, stops the sweep: runs not yet started are
    dropped and the exception is raised here with the rows finished before it as its
    ``partial_rows`` attribute (SweepRows)."""
    from ._workers import can_fork
    from .sweeps import sweep_spec

    runs = _whole("runs", runs, 0, 2**31 - 1)
    spec = sweep_spec(sweep, runs, base, seed, name, title, fixed, labels)
    settings = [(k, _config_value(k, v))
                for k, v in _dotted({**(overrides or {}), **kwargs}).items()]
    try:
        out = _core.sweep(spec, settings, runs, _whole("threads", threads, 0, MAX_THREADS),
                          _flag("share_plumes", share_plumes), controller,
                          _flag("processes", processes) and can_fork())
    except BaseException as e:
        partial = getattr(e, "partial_rows", None)
        if isinstance(partial, dict):
            e.partial_rows = SweepRows(partial["name"], partial["columns"], _info(partial))
        raise
    return SweepRows(out["name"], out["columns"], _info(out))


def _info(out):
    return {k: out[k] for k in ("title", "file", "seed", "runs_per_point", "axes") if k in out}


def probe(scenario=None, points=None, grid=None, warmup=None, duration=60.0, interval=0.32,
          seed=1, centreline=None, slab=0.2, overrides=None, **kwargs):
    """The plume alone, sampled as `plumetrace probe` samples it (the same numbers, bit for
    bit): over `duration` s after `warmup` s (None: the scenario's sim.warmup), every
    `interval` s, with the plume of (seed, trial 0). Give `points` or `grid`:

    - ``points``: an (N, 3) array of x, y, z (m). Returns ``points`` (N, 3) and, per point,
      ``detect_fraction`` (the intermittency: the fraction of instants with concentration at
      or above odor.threshold) and ``mean_concentration``, arrays of shape (N,);
    - ``grid``: ``"arena"`` for the detection map's cells (0.2 x 0.05 m over the arena at the
      odor sensor's height, as ``plumetrace probe --map``), or ``(x, y)`` or ``(x, y, z)`` with
      1-D arrays of x and y (m) and a height z (default: odor.height). Returns ``x``, ``y``,
      ``z`` and ``detect_fraction``, ``mean_concentration`` of shape (len(y), len(x)), ready
      for ``plt.pcolormesh(m["x"], m["y"], m["detect_fraction"])``.

    Both return ``samples`` (the instants sampled) and, with `centreline` (downwind positions
    x, m), ``centrelines``: arrays ``x``, ``mean_y``, ``std_y``, ``samples``, ``empty`` of the
    plume's centreline (the mean y of the filaments within `slab` / 2 of x; docs/model.md,
    "Plume statistics"). `scenario`, `overrides` and keyword arguments as in run().
    """
    import numpy as np

    path, settings = _settings(scenario, None, overrides, kwargs)
    if (points is None) == (grid is None):
        raise ValueError("probe: give either points= (an (N, 3) array) or grid= ('arena' or "
                         "(x, y[, z])), not both or neither")
    if points is not None:
        xyz = _finite_array("points", points)
        if xyz.ndim != 2 or xyz.shape[1] != 3 or xyz.shape[0] == 0:
            raise ValueError(f"points: expected an (N, 3) array of x, y, z with N >= 1, got "
                             f"shape {xyz.shape}")
    elif isinstance(grid, str):
        if grid != "arena":
            raise ValueError(f"grid: expected 'arena' or (x, y[, z]), got {grid!r}")
        x, y, z = _core.arena_grid(path, settings)
    else:
        try:
            parts = list(grid)
        except TypeError:
            raise TypeError(f"grid: expected 'arena' or (x, y[, z]), got {grid!r}") from None
        if len(parts) not in (2, 3):
            raise ValueError(f"grid: expected 'arena' or (x, y[, z]), got {len(parts)} items")
        x, y = (_finite_array(f"grid {n}", v).reshape(-1) for n, v in zip("xy", parts))
        if x.size == 0 or y.size == 0:
            raise ValueError("grid: x and y need at least one value each")
        z = (float(_load_json(_core.resolve_json(path, settings))["odor"]["height"])
             if len(parts) == 2 else _finite_number("grid z", parts[2]))
    if points is None:
        gx, gy = np.meshgrid(x, y)  # row-major by y, as the detection map
        xyz = np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, z)])
    if warmup is not None:
        warmup = _finite_number("warmup", warmup, low=0.0)
    duration = _finite_number("duration", duration, low=0.0, strict=True)
    interval = _finite_number("interval", interval, low=0.0, strict=True)
    if interval > duration:
        raise ValueError(f"interval ({interval}) must be at most duration ({duration}), or no "
                         "sample is taken")
    slab = _finite_number("slab", slab, low=0.0, strict=True)
    xs = [] if centreline is None else list(_finite_array("centreline", centreline).reshape(-1))
    out = _core.probe(path, settings, xyz, warmup, duration, interval,
                      _whole("seed", seed, 0, 2**64 - 1), xs, slab)
    result = {"samples": out["samples"]}
    if points is None:
        shape = (len(y), len(x))
        result.update(x=np.asarray(x), y=np.asarray(y), z=float(z),
                      detect_fraction=out["detect_fraction"].reshape(shape),
                      mean_concentration=out["mean_concentration"].reshape(shape))
    else:
        result.update(points=xyz, detect_fraction=out["detect_fraction"],
                      mean_concentration=out["mean_concentration"])
    if centreline is not None:
        result["centrelines"] = out["centrelines"]
    return result


class SweepRows:
    """The rows of a sweep as columns: ``rows["d_t"]``, ``rows.to_numpy()``, ``rows.to_pandas()``;
    ``rows.summary()`` for the statistics per point. ``rows.info``: the sweep's title, file,
    seed, runs per point and axes (key, label, values, fixed)."""

    def __init__(self, name, columns, info=None):
        self.name = name
        self.columns = columns
        self.info = dict(info or {})

    def summary(self):
        """Per point: its axis values, the count of each outcome, the success rate with its
        Wilson 95% interval and the mean overhead of the successful runs with its percentile
        bootstrap 95% interval (never below 1, as an overhead) and quartiles, as `plumetrace
        sweep` computes them (the same numbers as its summary.csv). Returns SweepRows with one
        row per point."""
        from .sweeps import summary

        return summary(self)

    def __len__(self):
        return len(self.columns["point"])

    def __getitem__(self, key):
        return self.columns[key]

    def keys(self):
        return list(self.columns)

    def __iter__(self):
        for i in range(len(self)):
            yield {k: _item(v[i]) for k, v in self.columns.items()}

    def to_numpy(self):
        """A dict of NumPy arrays, one per column."""
        import numpy as np

        return {k: np.asarray(v) for k, v in self.columns.items()}

    def to_pandas(self):
        """A pandas DataFrame (needs pandas)."""
        import pandas as pd

        return pd.DataFrame(self.to_numpy())


def _load_json(text):
    # why: JSON has no infinity; the core writes an infinite number (plume.cutoff) as "inf"
    def number(v):
        if isinstance(v, dict):
            return {k: number(x) for k, x in v.items()}
        return float(v) if v in ("inf", "-inf") else v

    return number(json.loads(text))


def _item(v):
    return v.item() if hasattr(v, "item") else v


def _dotted(kwargs):
    return {k.replace("__", "."): v for k, v in kwargs.items()}


def _config_value(key, value):
    # why: the core takes bool, int, float or str; NumPy scalars and the like become those
    if isinstance(value, (bool, int, float, str)):
        return value
    if hasattr(value, "item"):
        try:
            return value.item()
        except Exception:
            pass
    raise ConfigError(f"{key}: value {value!r} ({type(value).__name__}) is not a number, bool "
                      "or string")


def _whole(name, value, lo, hi):
    # why: int() would turn seed=1.7 into 1 and True into 1 without a word
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an int, got {type(value).__name__} {value!r}")
    value = int(value)
    if not lo <= value <= hi:
        raise ValueError(f"{name} must be an int from {lo} to {hi}, got {value}")
    return value


def _finite_array(name, value):
    import numpy as np

    try:
        array = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected numbers, got {value!r}") from None
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{name}: every value must be a finite number (m)")
    return array


def _finite_number(name, value, low=None, strict=False):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number, got {type(value).__name__} {value!r}")
    value = float(value)
    if not math.isfinite(value) or (low is not None and (value <= low if strict else value < low)):
        bound = "" if low is None else f" {'>' if strict else '>='} {low:g}"
        raise ValueError(f"{name} must be a finite number{bound}, got {value}")
    return value


def _flag(name, value):
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        return bool(value)
    raise TypeError(f"{name} must be True or False, got {type(value).__name__} {value!r}")


def _interval(name, value):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number, got {type(value).__name__} {value!r}")
    value = float(value)
    if not (math.isfinite(value) and value >= 0.0):
        raise ValueError(f"{name} must be a finite number >= 0, got {value}")
    return value


def _settings(scenario, algorithm, overrides, kwargs):
    if scenario is None:
        path, settings = None, []
    elif isinstance(scenario, Scenario):
        path, settings = scenario._settings()
    else:
        path, settings = str(scenario), []
    extra = _dotted({**(overrides or {}), **kwargs})
    if algorithm is not None:
        extra["controller.algorithm"] = algorithm
    return path, settings + [(k, _config_value(k, v)) for k, v in extra.items()]
