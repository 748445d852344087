"""Times a sweep of a controller written in Python on 1 and on N worker processes.

Usage: PYTHONPATH=build/python /usr/bin/python3 scripts/bench_python_controllers.py
           [--runs 40] [--workers 2] [--repeats 3] [--scenario scenarios/meander-weak.toml]

The example surge-cast in Python (examples/python_surge_cast.py) runs `runs` trials of its
default point, with threads=1 (one process), threads=N (N worker processes) and threads=N with
processes=False (N C++ threads of one process, every decision under its GIL), in turn, `repeats`
times; each line gives the median wall time, the CPU time of this process and its workers, and
whether the rows equal those of one process bit for bit. Load on the machine shows in the wall
times (docs/performance.md, "Python controllers on every core").
"""

import argparse
import os
import resource
import runpy
import statistics
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def cpu_seconds():
    """CPU time (user + system) of this process and of its children that have been reaped."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def same_rows(a, b):
    for key in a.keys():
        x, y = np.asarray(a[key]), np.asarray(b[key])
        same = list(x) == list(y) if x.dtype == object else x.tobytes() == y.tobytes()
        if not same or x.dtype != y.dtype:
            return False
    return a.keys() == b.keys()


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--runs", type=int, default=40)
    p.add_argument("--workers", type=int, default=os.cpu_count())
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--scenario", help="a scenario file (default: the paper's laminar setup)")
    args = p.parse_args()

    import plumetrace as pt

    runpy.run_path(str(ROOT / "examples" / "python_surge_cast.py"), run_name="bench")
    base = pt.Scenario(args.scenario) if args.scenario else None
    ways = {"1 process": dict(threads=1),
            f"{args.workers} worker processes": dict(threads=args.workers),
            f"{args.workers} threads, one process": dict(threads=args.workers, processes=False)}
    times = {name: [] for name in ways}
    reference = None
    for _ in range(args.repeats):
        for name, how in ways.items():
            cpu, start = cpu_seconds(), time.perf_counter()
            rows = pt.sweep({"controller.algorithm": ["py-surge-cast"]}, runs=args.runs,
                            base=base, **how)
            times[name].append((time.perf_counter() - start, cpu_seconds() - cpu))
            reference = rows if reference is None else reference
            assert same_rows(reference, rows), f"{name}: rows differ from one process's"
    one = statistics.median(w for w, _ in times["1 process"])
    print(f"{args.runs} runs of py-surge-cast, {args.scenario or 'laminar (the defaults)'}, "
          f"median of {args.repeats}; load average {os.getloadavg()[0]:.2f}")
    for name, values in times.items():
        wall = statistics.median(w for w, _ in values)
        cpu = statistics.median(c for _, c in values)
        print(f"  {name:28s} {wall:6.2f} s wall ({args.runs / wall:5.1f} runs/s, "
              f"x{one / wall:4.2f}), {cpu:6.2f} s CPU, rows equal")


if __name__ == "__main__":
    main()
