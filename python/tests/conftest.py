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
