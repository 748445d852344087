"""A plume-tracking environment for reinforcement learning: a Gymnasium environment when gymnasium
is installed, the same API without it.

    from plumetrace.env import PlumeEnv
    env = PlumeEnv()                          # the paper's setup; PlumeEnv(scenario, ..., **keys)
    env.action_space.seed(1)
    obs, info = env.reset(seed=1)
    while True:
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        if terminated or truncated:
            break

    import gymnasium                          # where installed (registered by plumetrace.env)
    env = gymnasium.make("plumetrace/Lochmatter2008-v0", render_mode="rgb_array")

With gymnasium, PlumeEnv subclasses ``gymnasium.Env`` and its spaces are ``gymnasium.spaces``;
without it, ``plumetrace.env.Box`` and ``Discrete`` offer the same ``seed()``, ``sample()``,
``contains()``, ``shape``, ``dtype`` (and ``low``/``high``, ``n``). docs/gymnasium.md has the
details.

A decision (one ``step``) holds its action for ``decision_interval`` simulation steps of
``sim.dt`` (default 8 x 0.032 s = 0.256 s); each simulation step moves the plume, senses, applies
the action, moves the robot and checks the run, exactly as the runner does; 1 makes every
simulation step a decision.

Observation (``observation_space``, float32, 8 values):
    [odor (0 or 1, at the last sensing; with ``observation="concentration"``, the odor sensor's
     reading there instead, >= 0, in the odor model's units after the sensor model
     ``odor.model``: odor is perceived where it reaches ``odor.threshold``),
     x, y, heading (odometry relative to the release pose:
     m, m, rad in [-pi, pi]), odometer (m), wind_x, wind_y (one noisy wind sample in the robot
     frame, m/s, taken at the end of the decision, the last one again in the terminal frame of
     a run that ended within it; 0 when ``wind_every_step`` is False;
     ``env.measure_wind()`` takes one on demand), odor fraction (the share of this decision's
     sensings that perceived odor, 0 to 1)]
Action (``action_space``): a heading in [-pi, pi] (rad, odometry frame; 0 is the start heading,
upwind) to turn toward and drive along, as a float or an array of one; with
``discrete_headings=n``, ``Discrete(n)``: action i drives along heading 2 pi i / n. Any
``plumetrace.controllers.Command`` (turn_to, curve, stop, abandon, declare_source) is accepted
as well. Anything
else is refused before the world moves: a bool, None, text, a complex number or an array of
other than one real number raises TypeError, a heading that is not finite or an index out of
0 to n - 1 ValueError, each naming the action.
Reward: the sum over the decision's simulation steps of ``reward_fn(info)`` (info of that step),
by default 1.0 at the step the robot reaches the source and 0.0 otherwise: an episode's return
is 1 for a success and 0 otherwise, whatever the decision interval.
terminated: the run ended in a state of the task: success (within supervisor.success_radius of
the source, or a declaration within supervisor.declaration_radius), wall (the robot touched the
arena's wall), gave_up (a ``Command.abandon()``) or wrong_declaration (a
``Command.declare_source(x, y)`` farther from the source).
truncated: the time limit, supervisor.timeout (1200 s after release by default).
info: time (s since release), outcome, the true pose and source_distance (for analysis and
shaped rewards, not for the agent), odometry (x, y, heading) and odometer as in the
observation at full precision (float64), seed, trial; at the end the run's metrics as
``result``.
Episodes: ``reset(seed=s)`` seeds ``np_random`` and starts run (s, 0); each later ``reset()``
without a seed continues with trial 1, 2, ... of seed s (``options={"trial": k}`` picks one), so
episode k meets the plume of trial k, as run k of ``plumetrace run --seed s --trial k`` and of
sweeps. A first ``reset()`` without any seed draws one from ``np_random`` (fresh entropy);
``info["seed"]`` and ``info["trial"]`` replay any episode.
"""

import json
import math
import numbers
import warnings

import numpy as np

from . import _core
from .api import _load_json, _settings, _whole
from .controllers import _is_bool, _shown
from .registration import ENV_ID, register_envs

try:
    import gymnasium as _gym
except ModuleNotFoundError as e:
    if e.name != "gymnasium":
        raise
    _gym = None

GYMNASIUM = _gym is not None
"""True when gymnasium is installed: PlumeEnv is then a gymnasium.Env."""

__all__ = ["Box", "Discrete", "ENV_ID", "GYMNASIUM", "PlumeEnv", "register_envs"]


def _np_random(seed=None):
    # why: gymnasium.utils.seeding.np_random's generator, so that a seed draws the same numbers
    # with or without gymnasium
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or seed < 0):
        raise ValueError(f"seed must be an int >= 0 or None, got {seed!r}")
    sequence = np.random.SeedSequence(seed)
    return np.random.Generator(np.random.PCG64(sequence)), sequence.entropy


class _Space:
    """What gymnasium.spaces.Space offers: ``shape``, ``dtype``, ``seed()``, ``sample()``,
    ``contains()`` (and ``x in space``)."""

    def __init__(self, shape, dtype, seed=None):
        self._shape = shape
        self.dtype = np.dtype(dtype)
        self._np_random = None
        if seed is not None:
            self.seed(seed)

    @property
    def shape(self):
        return self._shape

    @property
    def np_random(self):
        """The generator of sample(), seeded from fresh entropy at first use if seed() was not
        called."""
        if self._np_random is None:
            self.seed()
        return self._np_random

    def seed(self, seed=None):
        """Seeds sample()'s generator; returns the seed used, as a list of one int."""
        self._np_random, used = _np_random(seed)
        return [used]

    def __contains__(self, x):
        return self.contains(x)


class _Box(_Space):
    """A box of real vectors, like gymnasium.spaces.Box (closed intervals, possibly infinite):
    ``Box(low, high, dtype=np.float32)`` with ``low`` and ``high`` arrays of one shape."""

    def __init__(self, low, high, dtype=np.float32, seed=None):
        low, high = np.asarray(low, dtype=np.float64), np.asarray(high, dtype=np.float64)
        if low.shape != high.shape or np.any(low > high):
            raise ValueError(f"Box: low {low} and high {high} must have one shape, low <= high")
        super().__init__(low.shape, dtype, seed)
        self.bounded_below = np.isfinite(low)
        self.bounded_above = np.isfinite(high)
        self.low = low.astype(self.dtype)
        self.high = high.astype(self.dtype)

    def is_bounded(self, manner="both"):
        below, above = bool(np.all(self.bounded_below)), bool(np.all(self.bounded_above))
        return {"both": below and above, "below": below, "above": above}[manner]

    def sample(self):
        """A random point: uniform on finite intervals, normal on infinite ones, exponential
        from a finite bound (gymnasium's draws, in its order)."""
        sample = np.empty(self.shape)
        unbounded = ~self.bounded_below & ~self.bounded_above
        upper = ~self.bounded_below & self.bounded_above
        lower = self.bounded_below & ~self.bounded_above
        both = self.bounded_below & self.bounded_above
        rng = self.np_random
        sample[unbounded] = rng.normal(size=unbounded[unbounded].shape)
        sample[lower] = rng.exponential(size=lower[lower].shape) + self.low[lower]
        sample[upper] = -rng.exponential(size=upper[upper].shape) + self.high[upper]
        sample[both] = rng.uniform(low=self.low[both], high=self.high[both],
                                   size=both[both].shape)
        return sample.astype(self.dtype)

    def contains(self, x):
        """Whether x is an array of this shape, of a dtype that casts safely to this one, within
        the bounds (a list or a number is converted first)."""
        if not isinstance(x, np.ndarray):
            try:
                x = np.asarray(x, dtype=self.dtype)
            except (ValueError, TypeError):
                return False
        return bool(np.can_cast(x.dtype, self.dtype) and x.shape == self.shape
                    and np.all(x >= self.low) and np.all(x <= self.high))

    def __eq__(self, other):
        return (isinstance(other, _Box) and self.shape == other.shape
                and np.array_equal(self.low, other.low) and np.array_equal(self.high, other.high))

    def __repr__(self):
        return f"Box({self.low}, {self.high}, {self.shape}, {self.dtype})"


class _Discrete(_Space):
    """The integers start, ..., start + n - 1, like gymnasium.spaces.Discrete."""

    def __init__(self, n, seed=None, start=0):
        n = _whole("n", n, 1, 2**63 - 1)
        super().__init__((), np.int64, seed)
        self.n = np.int64(n)
        self.start = np.int64(start)

    def sample(self):
        """A uniformly random member (an np.int64)."""
        return self.start + self.np_random.integers(self.n)

    def contains(self, x):
        """Whether x is an int (or an integer NumPy scalar or 0-d array) in range."""
        if isinstance(x, int) and not isinstance(x, bool):
            value = np.int64(x)
        elif isinstance(x, (np.generic, np.ndarray)) and (np.issubdtype(x.dtype, np.integer)
                                                          and x.shape == ()):
            value = np.int64(x)
        else:
            return False
        return bool(self.start <= value < self.start + self.n)

    def __eq__(self, other):
        return isinstance(other, _Discrete) and (self.n, self.start) == (other.n, other.start)

    def __repr__(self):
        start = "" if self.start == 0 else f", start={self.start}"
        return f"Discrete({self.n}{start})"


class _Env:
    """What gymnasium.Env offers an environment: ``np_random`` (seeded by ``reset(seed=...)``),
    ``metadata``, ``render_mode``, ``spec``, ``unwrapped``, ``close()``, ``with``."""

    metadata = {"render_modes": []}
    render_mode = None
    spec = None
    _np_random = None
    _np_random_seed = None

    @property
    def np_random(self):
        """The environment's generator (gymnasium's), seeded by reset(seed=...), else from fresh
        entropy at first use."""
        if self._np_random is None:
            self._np_random, self._np_random_seed = _np_random()
        return self._np_random

    @np_random.setter
    def np_random(self, generator):
        self._np_random, self._np_random_seed = generator, -1

    @property
    def np_random_seed(self):
        """The seed of np_random (-1 if it was set otherwise)."""
        if self._np_random_seed is None:
            self._np_random, self._np_random_seed = _np_random()
        return self._np_random_seed

    @property
    def unwrapped(self):
        return self

    def reset(self, *, seed=None, options=None):
        if seed is not None:
            self._np_random, self._np_random_seed = _np_random(seed)

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *args):
        self.close()
        return False


if GYMNASIUM:
    Env, Box, Discrete = _gym.Env, _gym.spaces.Box, _gym.spaces.Discrete
else:
    Env, Box, Discrete = _Env, _Box, _Discrete


class PlumeEnv(Env):
    """One robot on the paper's plume, stepped by an agent (see the module docstring).

    `scenario`: a Scenario, a TOML path or None (the defaults); `overrides` (dict of dotted keys)
    and any other keyword argument (``wind_sensor__sigma_a=0.3`` for ``wind_sensor.sigma_a``)
    are config keys, checked here. The rest are the environment's own options:
    `decision_interval`: simulation steps per decision (an int >= 1); `render_mode`: None,
    "rgb_array" or "human"; `discrete_headings`: None (a Box action, a heading in rad) or n (a
    Discrete(n) action); `wind_every_step`: take a wind sample with every observation;
    `reward_fn`: f(info) -> float, called every simulation step (default: 1.0 on success);
    `observation`: "binary" (value 0 is the odor, 0 or 1) or "concentration" (value 0 is the
    odor sensor's reading, a float >= 0); `normalized_actions`: a Box action in [-1, 1] (clipped
    there) that drives along heading pi a, as RL libraries expect and as
    plumetrace.vector.VectorPlumeEnv does.
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 1.0 / (0.032 * 8)}

    def __init__(self, scenario=None, decision_interval=8, render_mode=None,
                 discrete_headings=None, wind_every_step=True, reward_fn=None, overrides=None,
                 observation="binary", normalized_actions=False, **keys):
        if "seed" in keys:
            raise TypeError("PlumeEnv takes no seed: reset(seed=...) seeds an episode")
        path, settings = _settings(scenario, None, overrides, keys)
        self.config = _load_json(_core.resolve_json(path, settings))  # checks every key now
        self._path, self._settings = path, settings
        if self.config["team"]["count"] != 1:
            raise ValueError(f"team.count = {self.config['team']['count']}: PlumeEnv drives one "
                             "robot (team.count = 1)")
        if not isinstance(observation, str) or observation not in _OBSERVATIONS:
            raise ValueError(f"observation must be one of {list(_OBSERVATIONS)}, got "
                             f"{_shown(observation)}")
        self.observation = observation
        self._reads = ("concentration",) if observation == "concentration" else ()
        self.decision_interval = _whole("decision_interval", decision_interval, 1, 2**31 - 1)
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or one of "
                             f"{self.metadata['render_modes']}, got {render_mode!r}")
        self.render_mode = render_mode
        self.wind_every_step = bool(wind_every_step)
        self.reward_fn = reward_fn
        self.dt = self.config["sim"]["dt"] * self.decision_interval  # simulated s per decision
        self.metadata = {**self.metadata, "render_fps": 1.0 / self.dt}  # real time

        self.observation_space = Box(*_observation_bounds(self.config, observation),
                                     dtype=np.float32)
        if not isinstance(normalized_actions, bool):
            raise TypeError(f"normalized_actions must be True or False, got "
                            f"{_shown(normalized_actions)}")
        if normalized_actions and discrete_headings is not None:
            raise ValueError("normalized_actions goes with a Box action, not discrete_headings")
        self.normalized_actions = normalized_actions
        if discrete_headings is None:
            self.discrete_headings = None
            bound = 1.0 if normalized_actions else math.pi
            self.action_space = Box(np.array([-bound], np.float32),
                                    np.array([bound], np.float32), dtype=np.float32)
        else:
            self.discrete_headings = _whole("discrete_headings", discrete_headings, 1, 2**31 - 1)
            self.action_space = Discrete(self.discrete_headings)

        self.episode_seed = None  # master seed of the current episode (None before a reset)
        self.trial = 0
        self._next_trial = 0
        self._world = None
        self._last = None
        self._odor = False  # odor perceived at the last sensing
        self._odometry = None  # the last observation's odometry and odometer, in float64
        self._path_xy = []
        self._renderer = None

    def reset(self, *, seed=None, options=None):
        """Starts an episode; returns (observation, info). `seed`: see the module docstring;
        `options`: {"trial": k} picks the trial."""
        if seed is not None:
            seed = _whole("seed", seed, 0, 2**64 - 1)
        super().reset(seed=seed)
        if seed is not None:
            self.episode_seed, self._next_trial = seed, 0
        elif self.episode_seed is None:
            self.episode_seed, self._next_trial = int(self.np_random.integers(2**63)), 0
        options = options or {}
        self.trial = _whole("trial", options.get("trial", self._next_trial), 0, 2**64 - 1)
        self._next_trial = self.trial + 1
        self._world = _core.World(self._path, self._settings, self.episode_seed, self.trial,
                                  self._reads)
        self._wind = (0.0, 0.0)
        seen = self._world.observe()
        self._last = self._observation(seen, float(seen.odor))
        self._path_xy = [self._world.pose()[:2]]
        if self.render_mode == "human":
            self.render()
        return self._last.copy(), self._info(self._world.done())

    def step(self, action):
        """One decision: the action held for decision_interval simulation steps. Returns
        (observation, reward, terminated, truncated, info)."""
        if self._world is None or self._world.done():
            raise RuntimeError("call reset() before step() and after an episode ends")
        command = self._command(action)
        world = self._world
        reward, odor, sensed, seen = 0.0, 0, 0, None
        for _ in range(self.decision_interval):
            world.act(command)
            self._path_xy.append(world.pose()[:2])
            done = world.done()
            if self.reward_fn is not None:
                reward += float(self.reward_fn(self._info(done)))
            elif world.outcome() == "success":
                reward += 1.0
            if done:
                break
            seen = world.observe()
            odor += seen.odor
            sensed += 1
        # why: a run that ended at the decision's first step senses nothing more
        if seen is not None:
            self._last = self._observation(seen, odor / sensed)
        info = self._info(world.done())
        outcome = info["outcome"]
        terminated = outcome in ("success", "wall", "gave_up", "wrong_declaration")
        truncated = outcome == "timeout"
        if self.render_mode == "human":
            self.render()
        return self._last.copy(), reward, terminated, truncated, info

    def render(self):
        """"rgb_array": the arena, filaments, source and the robot's path as an H x W x 3 uint8
        frame; "human": the same drawn in a matplotlib figure (shown when the backend is
        interactive; with Agg it is only drawn), returning None."""
        if self.render_mode is None:
            warnings.warn("render() needs render_mode='rgb_array' or 'human' (PlumeEnv(...))",
                          stacklevel=2)
            return None
        if self._world is None:
            raise RuntimeError("call reset() before render()")
        if self._renderer is None:
            self._renderer = _Renderer(self.config, human=self.render_mode == "human")
        frame = self._renderer.draw(self._world, self._path_xy, self.episode_seed, self.trial,
                                    self._odor, 1.0 / self.metadata["render_fps"])
        return frame if self.render_mode == "rgb_array" else None

    def measure_wind(self):
        """One more noisy wind sample (m/s, robot frame) at the current step, as a controller
        takes one at a state switch; counts in the run's wind_samples."""
        if self._world is None:
            raise RuntimeError("call reset() before measure_wind()")
        return self._world.measure_wind_body()

    def close(self):
        """Ends the episode and closes the figure of "human" rendering; may be called again."""
        self._world = None
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    def _observation(self, seen, odor_fraction):
        if not self.wind_every_step:
            wind = (0.0, 0.0)
        elif self._world.done():
            # why: the terminal frame of a run that ended within the decision repeats the last
            # sample; a new one would count in the run's wind_samples after its end
            wind = self._wind
        else:
            wind = self._world.measure_wind_body()
        self._wind = wind
        p = seen.odometry
        self._odometry = (p.x, p.y, p.heading), seen.odometer
        self._odor = seen.odor
        sensed = seen.concentration if self.observation == "concentration" else float(seen.odor)
        return np.array([sensed, p.x, p.y, p.heading, seen.odometer, wind[0], wind[1],
                         odor_fraction], dtype=np.float32)

    def _info(self, done):
        world = self._world
        x, y, heading = world.pose()
        source = self.config["source"]
        info = {"time": world.time(), "outcome": world.outcome(), "pose": (x, y, heading),
                "source_distance": math.hypot(x - source["x"], y - source["y"]),
                "odometry": self._odometry[0], "odometer": self._odometry[1],
                "seed": self.episode_seed, "trial": self.trial}
        if done:
            info["result"] = json.loads(world.result_json())
        return info

    def _command(self, action):
        if isinstance(action, _core.Command):
            return action
        n = self.discrete_headings
        if n is None:
            heading = _action_number(action, None)
            if self.normalized_actions:
                # why: the vector environment's mapping (docs/vector.md), so one policy drives both
                heading = math.pi * min(1.0, max(-1.0, heading))
            return _core.Command.go(heading)
        return _core.Command.go(_core.wrap_angle(2.0 * math.pi * _action_number(action, n) / n))


_OBSERVATIONS = ("binary", "concentration")  # PlumeEnv(observation=...): what value 0 holds


def _observation_bounds(config, observation):
    # why: the odometry is the true pose relative to the release pose, so |x|, |y| and the
    # odometer never exceed the path length, and the centre never drives faster than
    # robot.wheel_speed; a run lasts at most supervisor.timeout plus a step (2 steps and a
    # relative 1e-6 spare for rounding). The wind sample has Gaussian noise: unbounded. A
    # concentration is >= 0 (every sensor model clips its reading there), with no upper bound.
    dt = config["sim"]["dt"]
    steps = math.ceil(config["supervisor"]["timeout"] / dt) + 2
    reach = config["robot"]["wheel_speed"] * dt * steps * (1.0 + 1e-6)
    inf = math.inf
    low = np.array([0.0, -reach, -reach, -math.pi, 0.0, -inf, -inf, 0.0])
    high = np.array([1.0 if observation == "binary" else inf, reach, reach, math.pi, reach, inf,
                     inf, 1.0])
    # why: float32 bounds, rounded as the observations are (rounding keeps x <= high)
    return low.astype(np.float32), high.astype(np.float32)


def _action_number(action, n):
    """The one number an action holds: a finite heading (rad) as a float, or with `n` (a
    Discrete(n) action space) an index from 0 to n - 1 as an int. A bool, None, text, a complex
    number or an array of other than one real number raises TypeError, a heading that is not
    finite or an index out of range ValueError, each naming the action."""
    want = (f"an int from 0 to {n - 1} (a heading of 2 pi i / {n})" if n is not None else
            "a heading (a finite number or an array of one, rad)")

    def refused(kind, why):
        return kind(f"action {_shown(action)}: {why}; an action is {want} or a Command")

    if action is None:
        raise refused(TypeError, "None is no action")
    if isinstance(action, (str, bytes)):
        raise refused(TypeError, "text is no action")
    if _is_bool(action):
        raise refused(TypeError, f"a bool is no {'heading' if n is None else 'index'}")
    value = action
    if not isinstance(action, numbers.Number):
        try:
            array = np.asarray(action)
        except (TypeError, ValueError, OverflowError):
            raise refused(TypeError, "not an array of numbers") from None
        if array.size != 1:
            raise refused(TypeError, f"{array.size} values (shape {array.shape}), not one")
        if array.dtype.kind not in "iuf":
            raise refused(TypeError, f"an array of {array.dtype} values, not of numbers")
        value = array.reshape(-1)[0].item()
    if not isinstance(value, numbers.Real):
        raise refused(TypeError, f"a {type(value).__name__} is no real number")
    if n is not None:
        if not isinstance(value, numbers.Integral):
            raise refused(TypeError, f"a {type(value).__name__} is no index")
        if not 0 <= int(value) < n:
            raise refused(ValueError, f"out of the range 0 to {n - 1}")
        return int(value)
    try:
        heading = float(value)
    except OverflowError:
        heading = math.inf
    if not math.isfinite(heading):
        raise refused(ValueError, "the heading must be a finite number")
    return heading


class _Renderer:
    """Draws an episode with matplotlib: a Figure of its own on the Agg canvas for frames, a
    pyplot figure for "human"."""

    WIDTH, HEIGHT, DPI = 960, 320, 100  # pixels of a frame

    def __init__(self, config, human):
        if human:
            import matplotlib.pyplot as plt

            self.fig = plt.figure(figsize=(self.WIDTH / self.DPI, self.HEIGHT / self.DPI),
                                  dpi=self.DPI)
        else:
            from matplotlib.backends.backend_agg import FigureCanvasAgg
            from matplotlib.figure import Figure

            self.fig = Figure(figsize=(self.WIDTH / self.DPI, self.HEIGHT / self.DPI), dpi=self.DPI)
            FigureCanvasAgg(self.fig)
        self.human = human
        from matplotlib.patches import Circle, Rectangle

        arena, source = config["arena"], config["source"]
        ax = self.fig.add_axes([0.06, 0.16, 0.92, 0.72])
        ax.set_xlim(arena["x_min"] - 0.2, arena["x_max"] + 0.2)
        ax.set_ylim(arena["y_min"] - 0.2, arena["y_max"] + 0.2)
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlabel("x (m), wind along +x", fontsize=8)
        ax.set_ylabel("y (m)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.add_patch(Rectangle((arena["x_min"], arena["y_min"]), arena["x_max"] - arena["x_min"],
                               arena["y_max"] - arena["y_min"], fill=False, lw=1.5, color="0.3"))
        self.filaments = ax.scatter([], [], s=[], c="tab:gray", alpha=0.3, lw=0)
        ax.add_patch(Circle((source["x"], source["y"]), source["radius"], color="tab:red"))
        ax.add_patch(Circle((source["x"], source["y"]), config["supervisor"]["success_radius"],
                            fill=False, ls="--", color="tab:red"))
        (self.path,) = ax.plot([], [], lw=1.4, color="tab:blue")
        self.robot = Circle((0.0, 0.0), config["robot"]["radius"], color="tab:blue", zorder=5)
        ax.add_patch(self.robot)
        (self.heading,) = ax.plot([], [], lw=1.5, color="k", zorder=6)
        self.title = ax.set_title("", fontsize=9)
        self.ax = ax
        self.radius = config["robot"]["radius"]
        # points per metre, for the filaments' marker areas (points^2), once the equal aspect
        # has shrunk the axes to fit
        ax.apply_aspect()
        x_lo, x_hi = ax.get_xlim()
        self.pt_per_m = ax.get_position().width * self.fig.get_figwidth() * 72.0 / (x_hi - x_lo)

    def draw(self, world, path_xy, seed, trial, odor, frame_time):
        x, y, w = world.filaments()
        self.filaments.set_offsets(np.column_stack([x, y]) if len(x) else np.empty((0, 2)))
        self.filaments.set_sizes((2.0 * w * self.pt_per_m) ** 2)  # a disc of radius w
        xy = np.asarray(path_xy)
        self.path.set_data(xy[:, 0], xy[:, 1])
        px, py, heading = world.pose()
        self.robot.center = (px, py)
        self.robot.set_color("tab:orange" if odor else "tab:blue")
        tip = 2.0 * self.radius
        self.heading.set_data([px, px + tip * math.cos(heading)],
                              [py, py + tip * math.sin(heading)])
        self.title.set_text(f"t = {world.time():.1f} s   {world.outcome()}   "
                            f"{'odor' if odor else 'no odor'}   seed {seed} trial {trial}")
        canvas = self.fig.canvas
        canvas.draw()
        if self.human:
            # why: with a GUI backend, show the figure and let it refresh at render_fps; a
            # non-interactive backend (Agg, headless) has nothing to show
            if getattr(canvas, "required_interactive_framework", None) is not None:
                import matplotlib.pyplot as plt

                plt.show(block=False)
                plt.pause(frame_time)
            return None
        return np.asarray(canvas.buffer_rgba())[:, :, :3].copy()

    def close(self):
        if self.human:
            import matplotlib.pyplot as plt

            plt.close(self.fig)


if GYMNASIUM:
    register_envs()
