"""Many plume-tracking environments stepped together in C++: a Gymnasium vector environment when
gymnasium is installed, the same API without it (docs/vector.md).

    from plumetrace.vector import VectorPlumeEnv
    envs = VectorPlumeEnv(1024, group_size=64)       # 16 plumes, 64 agents on each
    obs, info = envs.reset(seed=1)                    # obs: (1024, 7) float32
    for _ in range(1000):
        obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())

Every environment is one robot on the scenario's plume, driven by actions; groups of
``group_size`` environments share one running plume (robots do not disturb the plume, so each
sees exactly what it would see alone); ``group_size=1`` gives every environment its own plume.
All stepping happens in C++ threads with the GIL released: one call steps every environment.

Episodes (Gymnasium 1.x's next-step autoreset, ``metadata["autoreset_mode"]``): the step after
an episode ends ignores that environment's action and returns the first observation of its next
episode, with reward 0 and terminated and truncated False. A new episode starts on the group's
plume as it is then, from a start drawn as the scenario's ``start`` keys say.

Seeding: ``reset(seed=s)`` gives environment i the seed s + i (a list gives each its own); its
episode e draws its robot's random streams as run (seed, e) of ``plumetrace run`` does, and
group g's plume is the plume of run (seed of environment g K, 0). With ``renew_plumes=True``
(``group_size=1``) every episode has a fresh plume and environment i's episode e is exactly run
(s + i, e), as ``PlumeEnv`` plays it. The same seed and actions replay every value exactly,
whatever the thread count.
"""

import numbers
import os

import numpy as np

from . import _core
from .api import _settings, _whole
from .controllers import _is_bool, _shown
from .env import GYMNASIUM, Box, Discrete, _np_random

if GYMNASIUM:
    from gymnasium.spaces import MultiDiscrete
    from gymnasium.vector import VectorEnv as _VectorBase

    try:
        from gymnasium.vector import AutoresetMode as _AutoresetMode

        _NEXT_STEP = _AutoresetMode.NEXT_STEP
    except ImportError:  # gymnasium 1.0 knew only the next-step mode
        _NEXT_STEP = "NextStep"
else:
    _VectorBase = object
    _NEXT_STEP = "NextStep"
    MultiDiscrete = None  # defined below

__all__ = ["GYMNASIUM", "OBSERVED", "OUTCOMES", "MAX_ENVS", "VectorPlumeEnv"]

OBSERVED = ("odor", "odor_fraction", "wind", "odometry", "time")
"""The values an observation may hold, in the order a frame holds them (docs/vector.md)."""

OUTCOMES = ("running", "success", "wall", "timeout", "gave_up", "wrong_declaration")
"""The names of the codes in ``info["outcome"]``."""

MAX_ENVS = _core.MAX_VECTOR_ENVS
"""The most environments one VectorPlumeEnv holds (docs/vector.md, "Memory")."""

_WIDTH = {"odor": 1, "odor_fraction": 1, "wind": 2, "odometry": 4, "time": 1}
_NAMES = {"odor": ["odor"], "odor_fraction": ["odor_fraction"], "wind": ["wind_x", "wind_y"],
          "odometry": ["x", "y", "heading", "odometer"], "time": ["time"]}


if MultiDiscrete is None:
    from .env import _Space

    class MultiDiscrete(_Space):
        """Vectors of integers, value i from 0 to nvec[i] - 1, like gymnasium.spaces.MultiDiscrete."""

        def __init__(self, nvec, dtype=np.int64, seed=None):
            self.nvec = np.asarray(nvec, dtype=dtype)
            if np.any(self.nvec < 1):
                raise ValueError(f"MultiDiscrete: nvec {self.nvec} must be >= 1")
            super().__init__(self.nvec.shape, dtype, seed)
            self.start = np.zeros_like(self.nvec)

        def sample(self):
            return (self.np_random.random(self.nvec.shape) * self.nvec).astype(self.dtype)

        def contains(self, x):
            if not isinstance(x, np.ndarray):
                try:
                    x = np.asarray(x)
                except (ValueError, TypeError):
                    return False
            return bool(x.shape == self.shape and x.dtype.kind in "iu"
                        and np.all(x >= 0) and np.all(x < self.nvec))

        def __eq__(self, other):
            return isinstance(other, MultiDiscrete) and np.array_equal(self.nvec, other.nvec)

        def __repr__(self):
            return f"MultiDiscrete({self.nvec})"


class VectorPlumeEnv(_VectorBase):
    """`num_envs` one-robot plume-tracking environments in one C++ object (see the module
    docstring and docs/vector.md).

    `scenario`: a Scenario, a TOML path or None (the defaults); `overrides` (dict of dotted keys)
    and any other keyword argument (``wind__model="meander"`` for ``wind.model``) are config
    keys, checked here. The environment's own options:
    `group_size`: environments per plume, dividing `num_envs` (1: a plume each);
    `renew_plumes`: a fresh plume for every episode (group_size 1 only; slower: a warm-up each);
    `decision_interval`: simulation steps an action is held (int >= 1);
    `observation`: "binary" (value "odor" is 0 or 1) or "concentration" (the odor sensor's
    reading); `observe`: the values of a frame, a tuple of names from OBSERVED;
    `stack`: frames per observation, the newest first (the first frame of an episode fills all);
    `action`: "heading" (a in [-1, 1]: go along heading pi a, odometry frame), "turn" (go along
    the current heading plus pi a) or "discrete" (with `discrete_headings` n: index i goes along
    heading 2 pi i / n); continuous actions are clipped to [-1, 1];
    `reward`: "success" (1 at the step the robot reaches the source) or "shaped" (plus the
    decision's decrease of the distance to the source over the distance at release: an
    episode's shaping sums to at most 1); `reward_fn`: f(info) -> array of num_envs floats,
    called once per step with the step's info and ``info["reward"]`` (the built-in reward),
    replacing it; `threads`: C++ threads (0: every core), which never change a result.
    """

    metadata = {"autoreset_mode": _NEXT_STEP, "render_modes": []}

    def __init__(self, num_envs=16, scenario=None, *, group_size=1, renew_plumes=False,
                 decision_interval=1, observation="binary",
                 observe=("odor", "wind", "odometry"), stack=1, action="heading",
                 discrete_headings=None, reward="success", reward_fn=None, threads=0,
                 overrides=None, **keys):
        for name in ("seed", "num_env", "n_envs"):
            if name in keys:
                raise TypeError(f"VectorPlumeEnv takes no {name}: "
                                + ("reset(seed=...) seeds the environments" if name == "seed"
                                   else "the number of environments is num_envs"))
        self.num_envs = _whole("num_envs", num_envs, 1, MAX_ENVS)
        self.group_size = _whole("group_size", group_size, 1, MAX_ENVS)
        if self.num_envs % self.group_size:
            raise ValueError(f"group_size = {self.group_size} must divide num_envs = "
                             f"{self.num_envs}")
        if not isinstance(renew_plumes, bool):
            raise TypeError(f"renew_plumes must be True or False, got {_shown(renew_plumes)}")
        self.renew_plumes = renew_plumes
        _agent_options(self, decision_interval, observation, observe, stack, action,
                       discrete_headings, reward, reward_fn)
        threads = _whole("threads", threads, 0, _core.MAX_THREADS)
        self.threads = threads or (os.cpu_count() or 1)

        path, settings = _settings(scenario, None, overrides, keys)
        self._world = _core.VectorWorld(path, settings, self.num_envs, self.group_size,
                                        renew_plumes, self.decision_interval,
                                        _observe_flags(self), action,
                                        self.discrete_headings or 0, reward, self.threads)
        self.render_mode = None
        self.spec = None
        self.closed = False
        self._started = False
        self._np_random = None
        self._np_random_seed = None
        low, high = self._world.bounds()
        self.observation_names = _observation_names(self)
        """The name of each value of an observation ([k]: k frames back)."""
        self.single_observation_space = Box(low, high, dtype=np.float32)
        self.observation_space = Box(np.tile(low, (self.num_envs, 1)),
                                     np.tile(high, (self.num_envs, 1)), dtype=np.float32)
        if self.discrete_headings is None:
            self.single_action_space = Box(np.array([-1.0], np.float32),
                                           np.array([1.0], np.float32), dtype=np.float32)
            self.action_space = Box(-np.ones((self.num_envs, 1), np.float32),
                                    np.ones((self.num_envs, 1), np.float32), dtype=np.float32)
        else:
            self.single_action_space = Discrete(self.discrete_headings)
            self.action_space = MultiDiscrete(np.full(self.num_envs, self.discrete_headings))

    # what gymnasium.vector.VectorEnv gives its subclasses, for when it is not installed
    @property
    def np_random(self):
        """The generator that draws the seeds of a first reset() without one."""
        if self._np_random is None:
            self._np_random, self._np_random_seed = _np_random()
        return self._np_random

    @np_random.setter
    def np_random(self, generator):
        self._np_random, self._np_random_seed = generator, -1

    @property
    def np_random_seed(self):
        if self._np_random_seed is None:
            self._np_random, self._np_random_seed = _np_random()
        return self._np_random_seed

    @property
    def unwrapped(self):
        return self

    def __enter__(self):
        return self

    def __exit__(self, *args):
        self.close()
        return False

    def __del__(self):
        pass  # why: gymnasium's VectorEnv.__del__ calls close(), which needs nothing here

    def __repr__(self):
        return (f"VectorPlumeEnv({self.num_envs}, group_size={self.group_size}, "
                f"observe={self.observe}, action={self.action!r})")

    def reset(self, *, seed=None, options=None):
        """Starts episodes; returns (observations, info). `seed`: an int (environment i gets
        seed + i), a list of num_envs ints, or None (the first reset draws one from np_random;
        a later one starts every environment's next episode on new plumes). `options`:
        ``{"reset_mask": array of num_envs bools}`` starts a new episode on the running plume for
        the flagged environments only (after a first reset)."""
        self._check_open()
        options = {} if options is None else options
        if not isinstance(options, dict) or set(options) - {"reset_mask"}:
            raise ValueError(f"options may hold only 'reset_mask', got {_shown(options)}")
        if "reset_mask" in options:
            if seed is not None:
                raise ValueError("reset(seed=..., options={'reset_mask': ...}): a masked reset "
                                 "keeps the seeds")
            if not self._started:
                raise RuntimeError("reset_mask: call reset() without it first")
            mask = _mask(options["reset_mask"], self.num_envs)
            self._world.reset_some(mask.view(np.uint8))
        elif seed is None and self._started:
            self._world.reset_next()
        else:
            if seed is None:
                seed = int(self.np_random.integers(2**63))
            else:
                self._np_random, self._np_random_seed = _np_random(
                    seed if isinstance(seed, int) and not isinstance(seed, bool) else None)
            self._world.reset(_seeds(seed, self.num_envs))
            self._started = True
        return self._world.observations(), self._world.info()

    def step(self, actions):
        """One decision of every environment; returns (observations, rewards, terminations,
        truncations, info), NumPy arrays of num_envs rows (info: a dict of such arrays)."""
        self._check_open()
        if not self._started:
            raise RuntimeError("call reset() before step()")
        obs, reward, terminated, truncated, info = self._world.step(self._actions(actions))
        if self.reward_fn is not None:
            info["reward"] = reward
            reward = _rewards(self.reward_fn(info), self.num_envs)
        return obs, reward, terminated, truncated, info

    def render(self):
        """No rendering: draw single episodes with plumetrace.env.PlumeEnv."""
        return None

    def close(self, **kwargs):
        """Frees the environments; may be called again."""
        self._world = None
        self.closed = True

    def result(self, i):
        """Environment i's current episode's metrics so far (a dict, as a run's)."""
        import json
        self._check_open()
        i = _whole("i", i, 0, self.num_envs - 1)
        return json.loads(self._world.result_json(i))

    def _check_open(self):
        if self.closed:
            raise RuntimeError("the VectorPlumeEnv is closed")

    def _actions(self, actions):
        n, discrete = self.num_envs, self.discrete_headings is not None
        want = (f"an array of {n} ints from 0 to {self.discrete_headings - 1}" if discrete else
                f"an array of shape ({n}, 1) or ({n},) of numbers in [-1, 1]")
        if actions is None or isinstance(actions, (str, bytes)) or _is_bool(actions):
            raise TypeError(f"actions: {_shown(actions)} is no array; actions are {want}")
        try:
            array = np.asarray(actions)
        except (TypeError, ValueError, OverflowError):
            raise TypeError(f"actions: not an array of numbers; actions are {want}") from None
        if array.dtype.kind == "b":
            raise TypeError(f"actions: an array of bools; actions are {want}")
        if array.dtype.kind not in ("iu" if discrete else "iuf"):
            raise TypeError(f"actions: an array of {array.dtype}; actions are {want}")
        if array.shape not in ((n,), (n, 1)):
            raise ValueError(f"actions: shape {array.shape}; actions are {want}")
        values = array.reshape(n).astype(np.float64)
        bad = ~np.isfinite(values)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(f"actions[{i}] = {array.reshape(n)[i]}: not a finite number; "
                             f"actions are {want}")
        if discrete and ((values < 0) | (values >= self.discrete_headings)).any():
            i = int(np.flatnonzero((values < 0) | (values >= self.discrete_headings))[0])
            raise ValueError(f"actions[{i}] = {array.reshape(n)[i]}: out of 0 to "
                             f"{self.discrete_headings - 1}")
        return np.ascontiguousarray(values)


def _agent_options(env, decision_interval, observation, observe, stack, action,
                   discrete_headings, reward, reward_fn):
    """Checks the options that VectorPlumeEnv and TeamPlumeEnv share (docs/vector.md) and sets
    them on `env`: decision_interval, observation, observe, stack, action, discrete_headings,
    reward, reward_fn. Raises TypeError or ValueError naming the option."""
    env.decision_interval = _whole("decision_interval", decision_interval, 1, 2**31 - 1)
    if not isinstance(observation, str) or observation not in ("binary", "concentration"):
        raise ValueError(f"observation must be 'binary' or 'concentration', got "
                         f"{_shown(observation)}")
    env.observation = observation
    env.observe = _observed(observe)
    env.stack = _whole("stack", stack, 1, 1024)
    if not isinstance(action, str) or action not in ("heading", "turn", "discrete"):
        raise ValueError(f"action must be 'heading', 'turn' or 'discrete', got {_shown(action)}")
    if (action == "discrete") != (discrete_headings is not None):
        raise ValueError("action='discrete' goes with discrete_headings=n (and only it), "
                         f"got action={action!r}, discrete_headings={_shown(discrete_headings)}")
    env.action = action
    env.discrete_headings = (None if discrete_headings is None else
                             _whole("discrete_headings", discrete_headings, 1, 2**31 - 1))
    if not isinstance(reward, str) or reward not in ("success", "shaped"):
        raise ValueError(f"reward must be 'success' or 'shaped', got {_shown(reward)}")
    if reward_fn is not None and not callable(reward_fn):
        raise TypeError(f"reward_fn must be callable, got {_shown(reward_fn)}")
    env.reward, env.reward_fn = reward, reward_fn


def _observe_flags(env):
    """What the C++ ObservationSpec takes, from the checked options."""
    flags = {name: name in env.observe for name in _WIDTH}
    flags.update(concentration=env.observation == "concentration", stack=env.stack)
    return flags


def _observation_names(env):
    return tuple(f"{name}[{k}]" if env.stack > 1 else name
                 for k in range(env.stack) for part in env.observe for name in _NAMES[part])


def _observed(observe):
    if isinstance(observe, str):
        observe = (observe,)
    try:
        names = tuple(observe)
    except TypeError:
        raise TypeError(f"observe must be a tuple of names from {OBSERVED}, got "
                        f"{_shown(observe)}") from None
    for name in names:
        if not isinstance(name, str) or name not in OBSERVED:
            raise ValueError(f"observe: {_shown(name)} is not one of {OBSERVED}")
    if len(set(names)) != len(names):
        raise ValueError(f"observe: {names} names a value twice")
    if not names:
        raise ValueError(f"observe: at least one of {OBSERVED}")
    return tuple(name for name in OBSERVED if name in names)


def _seeds(seed, n):
    if isinstance(seed, numbers.Integral) and not isinstance(seed, (bool, np.bool_)):
        first = _whole("seed", int(seed), 0, 2**64 - 1)
        return ((np.arange(n, dtype=np.uint64) + np.uint64(first % 2**64))
                if first + n <= 2**64 else
                np.array([(first + i) % 2**64 for i in range(n)], dtype=np.uint64))
    if isinstance(seed, (str, bytes)) or not hasattr(seed, "__len__"):
        raise TypeError(f"seed must be an int, a list of {n} ints or None, got {_shown(seed)}")
    if len(seed) != n:
        raise ValueError(f"seed: {len(seed)} seeds for {n} environments")
    return np.array([_whole(f"seed[{i}]", s, 0, 2**64 - 1) for i, s in enumerate(seed)],
                    dtype=np.uint64)


def _mask(mask, n):
    array = np.asarray(mask)
    if array.dtype.kind != "b" or array.shape != (n,):
        raise ValueError(f"reset_mask must be an array of {n} bools, got {_shown(mask)}")
    return np.ascontiguousarray(array)


def _rewards(values, n):
    try:
        array = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"reward_fn returned {_shown(values)}, not {n} numbers") from None
    if array.shape != (n,) or not np.all(np.isfinite(array)):
        raise ValueError(f"reward_fn must return {n} finite numbers, got shape {array.shape}"
                         + ("" if array.shape != (n,) else " with a value that is not finite"))
    return array


