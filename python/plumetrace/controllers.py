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

It answers with a ``Command``: ``go(heading)`` (turn on the spot, then drive straight),
``turn_to(heading)``, ``curve(curvature)`` (arc at the wheel-speed limit), ``stop()`` or
``abandon()`` (give up; the run fails). Headings are in the odometry frame; a heading or
curvature that is not finite raises ValueError where the command is made, and anything but a
Command returned from ``step`` raises TypeError.

Pass a factory ``f(scenario_dict, rng)`` to ``plumetrace.run(controller=...)`` or
``plumetrace.sweep(controller=...)``: it is called once per run with the resolved scenario and
the run's own controller random stream (``rng.uniform()``, ``rng.normal()``, ``rng.sign()``).
"""

from . import _core

Command = _core.Command
upwind_heading = _core.upwind_heading
guess_plume_side = _core.guess_plume_side
wrap_angle = _core.wrap_angle
controller_rng = _core.controller_rng  # controller_rng(seed, trial): the stream runs hand out


class Controller:
    """Optional base class: the motion primitives and the wind measurement as methods."""

    state = "python"
    losses = 0

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
    def measure_upwind(wind, observation):
        """One wind sample turned into the upwind heading (rad, odometry frame)."""
        return upwind_heading(wind.measure_wind_body(), observation.odometry.heading)
