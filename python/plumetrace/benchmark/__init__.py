"""Benchmarks (docs/benchmark.md): a versioned suite of plume-tracking tasks, every chosen
controller run on every task into a resumable results store, and a leaderboard.

    import plumetrace as pt
    board = pt.benchmark(runs=10)                   # the built-in suite and controllers
    board = pt.benchmark(controllers=["my_controller.py"], tasks=["laminar", "find"])
    python3 -m plumetrace.benchmark [SUITE] [--controller FILE.py] ...   # as the command
    python3 -m plumetrace.benchmark.leaderboard OUT          OUT/leaderboard.{html,md,csv,json}
    python3 -m plumetrace.benchmark.compare A.json B.json    which differences are beyond noise

``benchmark(...)`` (run.py) runs it; ``write_leaderboard(OUT)`` returns what leaderboard.json
holds, and ``compare_files(A, B)`` the comparison. data.py reads and checks a benchmark's
results, stats.py computes the figures, figures.py draws, leaderboard.py and compare.py write
and print; they are pure Python (numpy, matplotlib).
"""

from __future__ import annotations

import sys
import types

__all__ = ["BenchmarkError", "benchmark", "compare_files", "default_suite", "load_controllers",
           "write_leaderboard"]

# where each public name lives; why lazy: python3 -m plumetrace.benchmark.leaderboard (or
# .compare) runs its module fresh instead of finding it imported by this package
_HOMES = {"BenchmarkError": "data", "benchmark": "run", "compare_files": "compare",
          "default_suite": "run", "load_controllers": "run", "write_leaderboard": "leaderboard"}


def __getattr__(name):
    if name in _HOMES:
        import importlib

        return getattr(importlib.import_module(f".{_HOMES[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class _CallableModule(types.ModuleType):
    """This package, callable: ``plumetrace.benchmark(...)`` runs a benchmark
    (run.benchmark)."""

    def __call__(self, *args, **kwargs):
        from .run import benchmark

        return benchmark(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
