"""Shared by the Python tests."""

import os

import pytest


def plumetrace_with_core():
    """The plumetrace package with its C++ module. A missing module fails the tests, unless the
    build left it out (PLUMETRACE_CORE_OPTIONAL=1, set by CMake), where they are skipped."""
    if os.environ.get("PLUMETRACE_CORE_OPTIONAL") == "1":
        pytest.importorskip("plumetrace._core")
    import plumetrace
    import plumetrace._core  # noqa: F401

    _register_a_zigzag(plumetrace)
    return plumetrace


def _register_a_zigzag(pt):
    """Every test runs with a controller of a user's own called "zigzag" registered, as a user's
    process may have it: no test may take "zigzag" for an unknown name, or a rule of the paper's
    algorithms for one of every controller. (test_controllers.py registers another zigzag in its
    place, as registering a name again does.)"""
    if "zigzag" in pt.algorithms():
        return
    from plumetrace.controllers import Controller

    class Zigzag(Controller):
        params = {"leg": pt.Param(1.0, min=0.1, max=10.0, help="path length of each leg (m)")}
        side, turn_at, heading = 1, 0.0, 0.0

        def step(self, obs, wind):
            if obs.odometer >= self.turn_at:
                self.side, self.turn_at = -self.side, obs.odometer + self.params.leg
                self.heading = self.measure_upwind(wind, obs) + self.side * 0.7
            return self.go(self.heading)

    pt.register_controller("zigzag", Zigzag)


class Shows:
    """A controller that stands still and whose snapshot() returns what it was given."""

    def __init__(self, shown):
        self.shown = shown

    def step(self, obs, wind):
        from plumetrace.controllers import Command

        return Command.stop()

    def snapshot(self):
        return self.shown


def overhead_bounds(rows, out):
    """Every overhead number plumetrace prints or draws for the sweep `rows` (SweepRows), as
    (where, value): rows.summary()'s interval, plumetrace.report's report.csv and report.md
    (written into `out`), and the points handed to the figures (the report's and
    plots.sweep_bars'). An overhead is d_t / d_u >= 1, so none of them may be below 1."""
    import csv
    import math
    import re

    import plumetrace as pt
    from plumetrace import plots
    from plumetrace.report import figures

    found = []
    for r in rows.summary():
        for key in ("overhead_lo", "overhead_hi"):
            if not math.isnan(r[key]):
                found.append((f"summary() point {r['point']} {key}", r[key]))
    drawn = []
    original = figures.draw_sweep_panels

    def recording(ax_rate, ax_oh, x_labels, groups, *args, **kwargs):
        drawn.extend(p for _, points in groups for p in points if p is not None)
        return original(ax_rate, ax_oh, x_labels, groups, *args, **kwargs)

    figures.draw_sweep_panels = recording
    try:
        pt.report(rows, out=out)
        if len(rows.info.get("axes") or []) <= 2:
            import matplotlib.pyplot as plt

            plt.close(plots.sweep_bars(rows))
    finally:
        figures.draw_sweep_panels = original
    for p in drawn:
        found += [("figure", v) for v in (p.oh_lo, p.oh_hi, p.oh_mean) if v is not None]
    with open(out / "report.csv", newline="") as f:
        for row in csv.DictReader(f):
            for key in ("overhead_lo", "overhead_hi", "overhead_mean", "overhead_median",
                        "overhead_q1", "overhead_q3"):
                if row[key]:
                    found.append((f"report.csv point {row['point']} {key}", float(row[key])))
    # "1.23 [1.05, 1.40]": a mean or median with its interval, wherever report.md prints one
    for m in re.finditer(r"(\d+\.\d+) \\?\[(\d+\.\d+), (\d+\.\d+)\\?\]",
                         (out / "report.md").read_text()):
        found += [(f"report.md {m.group(0)}", float(v)) for v in m.groups()]
    return found
