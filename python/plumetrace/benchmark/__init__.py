"""Benchmarks (docs/benchmark.md): a versioned suite of plume-tracking tasks, every chosen
controller run on every task into a resumable results store, and a leaderboard.

    import plumetrace as pt
    board = pt.benchmark(runs=10)                      # the built-in suite and controllers
    board = pt.benchmark(controllers=["my_controller.py"], tasks=["laminar", "find"])
    python3 -m plumetrace.benchmark [SUITE] [--controller FILE.py] ...   # as the command

``plumetrace.benchmark.leaderboard`` writes leaderboard.html/.md/.csv/.json from an output
folder, ``plumetrace.benchmark.compare`` compares two results.
"""

import sys
import types

__all__ = ["benchmark", "default_suite", "load_controllers"]


def __getattr__(name):
    if name in __all__:
        from . import run

        return getattr(run, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class _CallableModule(types.ModuleType):
    """This package, callable: ``plumetrace.benchmark(...)`` runs a benchmark (run.benchmark)."""

    def __call__(self, *args, **kwargs):
        from .run import benchmark

        return benchmark(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
