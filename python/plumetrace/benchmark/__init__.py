"""The benchmark's leaderboard and the comparison of two results (docs/benchmark.md).

    python3 -m plumetrace.benchmark.leaderboard OUT          OUT/leaderboard.{html,md,csv,json}
    python3 -m plumetrace.benchmark.compare A.json B.json    which differences are beyond noise

From Python: ``write_leaderboard(OUT)`` returns what leaderboard.json holds, and
``compare_files(A, B)`` the comparison. data.py reads and checks a benchmark's results, stats.py
computes the figures, figures.py draws, leaderboard.py and compare.py write and print. Pure
Python (numpy, matplotlib); no C++ module.
"""

from __future__ import annotations

import sys
import types

__all__ = ["BenchmarkError", "compare_files", "write_leaderboard"]


def __getattr__(name):
    # why: lazy, so that python3 -m plumetrace.benchmark.leaderboard (or .compare) runs its
    # module fresh instead of finding it imported by this package
    if name == "write_leaderboard":
        from .leaderboard import write_leaderboard

        return write_leaderboard
    if name == "compare_files":
        from .compare import compare_files

        return compare_files
    if name == "BenchmarkError":
        from .data import BenchmarkError

        return BenchmarkError
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class _CallableModule(types.ModuleType):
    """This package, callable: ``plumetrace.benchmark(...)`` runs a benchmark
    (plumetrace.api.benchmark), though importing this package makes it the attribute
    ``benchmark`` of plumetrace."""

    def __call__(self, *args, **kwargs):
        from .. import api

        return api.benchmark(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
