"""Surge-cast (Lochmatter & Martinoli 2008) written in Python, run against the built-in one.

Run: PYTHONPATH=build/python /usr/bin/python3 examples/python_surge_cast.py
It is registered as "py-surge-cast" with keys of its own, py_surge_cast.d_cast and
py_surge_cast.d_lost (the built-in's defaults), and gives exactly the built-in surge-cast's
results for the same seeds and values (tested in python/tests/test_controllers.py).
"""

import math

import plumetrace as pt
from plumetrace.controllers import Controller, guess_plume_side


class SurgeCast(Controller):
    """Straight upwind in the plume; once lost, cast d_cast toward the guessed side, then
    2 d_cast the other way, then give up."""

    params = {
        "d_cast": pt.Param(0.27, min=0.0, min_open=True, help="cast length (m)"),
        "d_lost": pt.Param(0.614, min=0.0, min_open=True,
                           help="path length without odor before the plume is lost (m)"),
    }

    def __init__(self, params, rng):
        super().__init__(params, rng)
        self.d_cast, self.d_lost = params["d_cast"], params["d_lost"]
        self.state, self.losses = "surge", 0
        self.started = False
        self.heading = self.upwind = 0.0
        self.side = 1
        self.cast_start = 0.0
        self.last_odor = 0.0  # odometer at the last detection (the robot starts in the plume)

    def step(self, obs, wind):
        if obs.odor:
            self.last_odor = obs.odometer
        if not self.started:
            self.started = True
            self.heading = self.measure_upwind(wind, obs)
        cast_length = obs.odometer - self.cast_start
        if self.state == "surge":
            if obs.odometer - self.last_odor >= self.d_lost:
                self.losses += 1
                self.upwind = self.measure_upwind(wind, obs)
                self.side = guess_plume_side(self.heading, self.upwind, self.rng)
                self.cast_start = obs.odometer
                self.state = "cast1"
        elif obs.odor:
            self.heading = self.measure_upwind(wind, obs)
            self.state = "surge"
        elif self.state == "cast1" and cast_length >= self.d_cast:
            self.cast_start = obs.odometer
            self.state = "cast2"
        elif self.state == "cast2" and cast_length >= 2.0 * self.d_cast:
            return self.abandon()
        if self.state == "surge":
            return self.go(self.heading)
        if self.state == "cast1":
            return self.go(self.upwind + self.side * math.pi / 2.0)
        return self.go(self.upwind - self.side * math.pi / 2.0)


# one line: "py-surge-cast" becomes a value of controller.algorithm and its keys config keys
pt.register_controller("py-surge-cast", SurgeCast)


def main():
    for trial in range(3):
        mine = pt.run(algorithm="py-surge-cast", seed=7, trial=trial, trace=False,
                      py_surge_cast__d_cast=0.4)
        builtin = pt.run(algorithm="surge-cast", seed=7, trial=trial, trace=False,
                         surge_cast__d_cast=0.4)
        same = all(mine[k] == builtin[k] for k in ("outcome", "time_s", "d_t", "d_u", "losses"))
        print(f"trial {trial}: {mine['outcome']:8s} d_t {mine['d_t']:.3f} m, "
              f"identical to the built-in: {same}")


if __name__ == "__main__":
    main()
