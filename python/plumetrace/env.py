"""A plume-tracking environment following Gymnasium's conventions (no gymnasium needed).

    from plumetrace.env import PlumeEnv
    env = PlumeEnv()                              # the paper's setup; PlumeEnv(scenario, ...)
    obs, info = env.reset(seed=1)
    while True:
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        if terminated or truncated:
            break

Each step is one simulation step (sim.dt = 0.032 s): the plume moves, the robot senses, the
action is applied, the robot moves, the supervisor checks.

Observation (``observation_space``, a float64 array of 7):
    [odor (0 or 1), x, y, heading (odometry relative to the release pose: m, m, rad),
     odometer (m), wind_x, wind_y (one noisy wind sample in the robot frame, m/s; 0 when
     ``wind_every_step`` is False; ``env.measure_wind()`` takes a sample on demand)]
Action (``action_space``): a heading in [-pi, pi] (rad, odometry frame) to turn toward and
drive along (the built-in algorithms' "go"), as a float or an array of 1; or any
``plumetrace.controllers.Command`` (turn_to, curve, stop, abandon).
Reward: ``reward_fn(info)`` if given, else 1 when the robot reaches the source, 0 otherwise.
terminated: success, wall or gave up; truncated: the scenario's timeout.
info: time, outcome, the true pose (for analysis only), and at the end the run's metrics.
Episodes: ``reset(seed=s)`` sets the master seed; trials count up from 0 with each reset
(``options={"trial": k}`` picks one), so episode k meets the plume of trial k, as in sweeps.
"""

import json
import math

import numpy as np

from . import _core
from .api import _settings, _whole


class Box:
    """A box of real vectors, like gymnasium.spaces.Box: ``low``, ``high``, ``shape``,
    ``dtype``, ``sample()``, ``contains(x)``."""

    def __init__(self, low, high, seed=None):
        self.low = np.asarray(low, dtype=np.float64)
        self.high = np.asarray(high, dtype=np.float64)
        self.shape = self.low.shape
        self.dtype = np.float64
        self._rng = np.random.default_rng(seed)

    def sample(self):
        low = np.where(np.isfinite(self.low), self.low, -1.0)
        high = np.where(np.isfinite(self.high), self.high, 1.0)
        return self._rng.uniform(low, high).astype(np.float64)

    def contains(self, x):
        x = np.asarray(x, dtype=np.float64)
        return x.shape == self.shape and bool(np.all(x >= self.low) and np.all(x <= self.high))

    def __repr__(self):
        return f"Box({self.low}, {self.high})"


class PlumeEnv:
    """One robot on the paper's plume, stepped by an agent (see the module docstring)."""

    metadata = {"render_modes": []}

    def __init__(self, scenario=None, wind_every_step=True, reward_fn=None, seed=1, **overrides):
        self._path, self._settings = _settings(scenario, None, None, overrides)
        self.wind_every_step = wind_every_step
        self.reward_fn = reward_fn
        self.seed = _whole("seed", seed, 0, 2**64 - 1)
        self.trial = 0
        inf = math.inf
        self.observation_space = Box([0, -inf, -inf, -math.pi, 0, -inf, -inf],
                                     [1, inf, inf, math.pi, inf, inf, inf])
        self.action_space = Box([-math.pi], [math.pi])
        self._world = None
        self._next_trial = 0

    def reset(self, seed=None, options=None):
        if seed is not None:
            self.seed = _whole("seed", seed, 0, 2**64 - 1)
            self._next_trial = 0
        self.trial = _whole("trial", (options or {}).get("trial", self._next_trial), 0, 2**64 - 1)
        self._next_trial = self.trial + 1
        self._world = _core.World(self._path, self._settings, self.seed, self.trial)
        return self._observe(), self._info()

    def step(self, action):
        if self._world is None or self._world.done():
            raise RuntimeError("call reset() before step() and after an episode ends")
        self._world.act(_command(action))
        info = self._info()
        done = self._world.done()
        if done:
            info["result"] = json.loads(self._world.result_json())
        outcome = info["outcome"]
        reward = self.reward_fn(info) if self.reward_fn else float(outcome == "success")
        terminated = outcome in ("success", "wall", "gave_up")
        truncated = outcome == "timeout"
        obs = self._last if done else self._observe()
        return obs, reward, terminated, truncated, info

    def measure_wind(self):
        """One more noisy wind sample (m/s, robot frame) at the current step, as a controller
        takes one at a state switch; counts in the run's wind_samples."""
        return self._world.measure_wind_body()

    def close(self):
        self._world = None

    def _observe(self):
        o = self._world.observe()
        wind = self._world.measure_wind_body() if self.wind_every_step else (0.0, 0.0)
        p = o.odometry
        self._last = np.array([float(o.odor), p.x, p.y, p.heading, o.odometer, wind[0], wind[1]])
        return self._last.copy()

    def _info(self):
        x, y, heading = self._world.pose()
        return {"time": self._world.time(), "outcome": self._world.outcome(),
                "pose": (x, y, heading), "seed": self.seed, "trial": self.trial}


def _command(action):
    if isinstance(action, _core.Command):
        return action
    try:
        values = np.asarray(action, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError, OverflowError):
        values = np.empty(0)
    if values.size != 1:
        raise TypeError("an action is a heading (a number or an array of one) or a Command, got "
                        f"{type(action).__name__} {action!r}"[:300])
    return _core.Command.go(float(values[0]))
