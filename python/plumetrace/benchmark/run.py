"""Runs a benchmark from Python: controllers written in Python enter beside the built-in ones
(docs/benchmark.md, "Your own controller")."""

import importlib.util
import os
import re
import sys
from pathlib import Path

from .._files import BadPath

__all__ = ["benchmark", "default_suite", "load_controllers"]

_HERE = Path(__file__).resolve().parent


def default_suite():
    """The built-in suite's file: the package's copy (studies/benchmark/suite.toml shipped with
    it), else the repository's (python/plumetrace/benchmark is three levels below its root)."""
    for candidate in (_HERE.parent / "studies" / "benchmark" / "suite.toml",
                      _HERE.parents[2] / "studies" / "benchmark" / "suite.toml"):
        if candidate.is_file():
            return str(candidate)
    raise BadPath("the built-in suite studies/benchmark/suite.toml is not installed with this "
                  "package; name a suite file")


def _kebab(name):
    return re.sub(r"(?<!^)(?=[A-Z])", "-", name).lower()


def load_controllers(path):
    """Imports the Python file `path` and returns the names of the controllers it enters: those
    it registers (plumetrace.register_controller), else each subclass of
    plumetrace.controllers.Controller it defines, registered under its `name` attribute or its
    class name in kebab case ("MyWalk" -> "my-walk"). Raises BadPath naming the file when it
    cannot be read, fails on import, or defines no controller."""
    from .. import api
    from .. import controllers
    from ..controllers import Controller

    p = Path(path)
    if p.suffix != ".py" or not p.is_file():
        raise BadPath(f"--controller '{path}': not a Python file (.py) that exists")
    name = "plumetrace_entry_" + re.sub(r"\W", "_", p.stem)
    spec = importlib.util.spec_from_file_location(name, p)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    entered = []
    controllers._RECORDERS.append(entered)
    try:
        spec.loader.exec_module(module)
    except Exception as e:  # the file's own error, named with the file
        del sys.modules[name]
        raise BadPath(f"--controller '{path}': importing it raised {type(e).__name__}: {e}") \
            from e
    finally:
        controllers._RECORDERS.remove(entered)
    entered = list(dict.fromkeys(entered))
    if entered:
        return entered
    classes = [c for c in vars(module).values()
               if isinstance(c, type) and issubclass(c, Controller) and c is not Controller
               and c.__module__ == name]
    if not classes:
        raise BadPath(f"--controller '{path}': defines no controller (register one with "
                      "plumetrace.register_controller(name, Class), or define a subclass of "
                      "plumetrace.controllers.Controller)")
    for c in classes:
        entry = getattr(c, "name", None) or _kebab(c.__name__)
        api.register_controller(entry, c)
        entered.append(entry)
    return entered


def benchmark(suite=None, controllers=(), tasks=(), only=False, runs=0, threads=0, out=None,
              store=None, fresh=False, shard=None, overrides=None, share_plumes=True,
              leaderboard=True, processes=True, progress=None, **kwargs):
    """Runs every chosen controller on every task of `suite` (a suite file; None: the built-in
    plumetrace-core) into a resumable results store and writes the leaderboard, as
    `plumetrace benchmark` does. `controllers`: names of registered controllers or .py files
    (load_controllers), added to the suite's (with `only`, the only ones); `tasks`: the tasks to
    run (default all); `runs`: runs per cell (0: the suite's); `threads`: 0 for all cores (with a
    controller written in Python, that many worker processes forked from this one, unless
    `processes` is False, as in plumetrace.sweep); `out`: the output folder (default
    out/SUITE-NAME); `store`: the results store (default OUT/results.sqlite, or
    OUT/part-I-of-N.sqlite for `shard` "I/N"); `fresh` discards the stored runs;
    `overrides`/keyword arguments set keys of every task (as --set); `progress`: None, or a
    function ``f(done, total, seconds)`` called every 0.25 s while runs are computed (an
    exception it raises stops the benchmark and is raised here).

    Returns the leaderboard (the dict written to leaderboard.json), or with `leaderboard=False`
    or a shard what was run (out, store, digest, counts). A stopped benchmark (Ctrl-C) keeps
    every finished run: calling again computes only what is missing."""
    from .. import _core
    from .._workers import can_fork
    from ..api import _config_value, _dotted, _flag, _whole, MAX_THREADS

    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be a function f(done, total, seconds) or None, got "
                        f"{type(progress).__name__}")
    names, files = [], {}
    for c in controllers:
        if str(c).endswith(".py"):
            for name in load_controllers(c):
                files[name] = os.fspath(c)
                names.append(name)
        else:
            names.append(str(c))
    settings = [(k, _config_value(k, v)) for k, v in _dotted({**(overrides or {}),
                                                             **kwargs}).items()]
    done = _core.benchmark(os.fspath(suite) if suite is not None else default_suite(), names,
                           bool(only), [str(t) for t in tasks],
                           _whole("runs", runs, 0, 2**31 - 1), settings,
                           _whole("threads", threads, 0, MAX_THREADS), bool(share_plumes),
                           os.fspath(out) if out is not None else "",
                           os.fspath(store) if store is not None else "", bool(fresh),
                           shard or "", files, _flag("processes", processes) and can_fork(),
                           progress)
    if not leaderboard or done["shard"]:
        return done
    from .leaderboard import write_leaderboard

    return write_leaderboard(done["out"])
