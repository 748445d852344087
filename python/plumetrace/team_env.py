"""A team of robots on one plume, every robot an agent of a learner: PettingZoo's ParallelEnv
API (dicts keyed by agent), without depending on PettingZoo (docs/vector.md, "Teams").

    from plumetrace.team_env import TeamPlumeEnv
    env = TeamPlumeEnv("scenarios/meander-strong.toml", team__count=3)
    observations, infos = env.reset(seed=1)
    while env.agents:
        actions = {agent: env.action_space(agent).sample() for agent in env.agents}
        observations, rewards, terminations, truncations, infos = env.step(actions)

The agents are the scenario's team (``team.count`` robots, "robot_0", "robot_1", ...), released
together on one plume under the scenario's contacts and messages rules. All robots decide at
once; a decision holds each robot's action for ``decision_interval`` simulation steps, stepped in
C++ with the GIL released, exactly as a team's run steps (environment; every running robot
senses; every one proposes; contacts resolved; every one commits and is checked). A robot whose
run ends (success, wall, gave up: terminated; supervisor.timeout: truncated) stops there while
the others go on; the step that ends it returns its last entries and then it leaves ``agents``;
the episode is over when ``agents`` is empty.

The options mean what they mean for ``plumetrace.vector.VectorPlumeEnv``: `observation`,
`observe` (names from ``plumetrace.vector.OBSERVED``), `stack`, `action` with
`discrete_headings`, `reward` and `decision_interval`; `reward_fn` is f(infos) -> {agent:
number}, called once per step with the step's infos (each holding ``"reward"``, the built-in
reward) and returning a number for every agent of the step.

Seeding: ``reset(seed=s)`` plays run (s, trial 0) of the scenario, each robot with the random
streams it has in ``plumetrace run --seed s``; each later ``reset()`` without a seed plays the
next trial (``options={"trial": k}`` picks one). Actions that give the commands the robots'
controllers would give reproduce the built-in run bit for bit.
"""

import json
import math
import numbers

import numpy as np

from . import _core
from .api import _load_json, _settings, _whole
from .controllers import _is_bool, _shown
from .env import Box, Discrete, _np_random
from .vector import _agent_options, _observation_names, _observe_flags

__all__ = ["TeamPlumeEnv"]


class TeamPlumeEnv:
    """The scenario's team on one plume, one agent per robot (see the module docstring and
    docs/vector.md, "Teams").

    `scenario`: a Scenario, a TOML path or None (the defaults); `overrides` (dict of dotted keys)
    and any other keyword argument (``team__count=3`` for ``team.count``) are config keys,
    checked here. The environment's own options: `decision_interval` (int >= 1), `observation`
    ("binary" or "concentration"), `observe` (a tuple of names from OBSERVED), `stack` (frames
    per observation, the newest first), `action` ("heading", "turn" or "discrete" with
    `discrete_headings` n; continuous actions in [-1, 1], clipped), `reward` ("success" or
    "shaped"), `reward_fn` (f(infos) -> {agent: number}).
    """

    metadata = {"name": "plumetrace_team_v0", "is_parallelizable": True, "render_modes": []}

    def __init__(self, scenario=None, *, decision_interval=1, observation="binary",
                 observe=("odor", "wind", "odometry"), stack=1, action="heading",
                 discrete_headings=None, reward="success", reward_fn=None, overrides=None,
                 **keys):
        if "seed" in keys:
            raise TypeError("TeamPlumeEnv takes no seed: reset(seed=...) seeds an episode")
        _agent_options(self, decision_interval, observation, observe, stack, action,
                       discrete_headings, reward, reward_fn)

        path, settings = _settings(scenario, None, overrides, keys)
        self.config = _load_json(_core.resolve_json(path, settings))  # checks every key now
        self._world = _core.TeamWorld(path, settings, self.decision_interval,
                                      _observe_flags(self), action,
                                      self.discrete_headings or 0, reward)
        n = self._world.size
        self.possible_agents = [f"robot_{k}" for k in range(n)]
        self.agents = []
        self._index = {agent: k for k, agent in enumerate(self.possible_agents)}
        self.observation_names = _observation_names(self)
        """The name of each value of an observation ([k]: k frames back)."""
        self.observation_spaces = {
            agent: Box(*self._world.bounds(k), dtype=np.float32)
            for k, agent in enumerate(self.possible_agents)}
        if self.discrete_headings is None:
            self.action_spaces = {
                agent: Box(np.array([-1.0], np.float32), np.array([1.0], np.float32),
                           dtype=np.float32) for agent in self.possible_agents}
        else:
            self.action_spaces = {agent: Discrete(self.discrete_headings)
                                   for agent in self.possible_agents}
        arena = self.config["arena"]
        low = np.tile(np.array([arena["x_min"], arena["y_min"], -math.pi], np.float32), n)
        high = np.tile(np.array([arena["x_max"], arena["y_max"], math.pi], np.float32), n)
        self.state_space = Box(low, high, dtype=np.float32)
        """Every robot's true pose (x, y in m, heading in rad), robot 0 first: state()."""
        self.render_mode = None
        self.closed = False
        self.episode_seed = None  # master seed of the current episode (None before a reset)
        self.trial = 0
        self._next_trial = 0
        self._np_random = None
        self._started = False

    @property
    def num_agents(self):
        """The agents whose run goes on."""
        return len(self.agents)

    @property
    def max_num_agents(self):
        """The team's robots."""
        return len(self.possible_agents)

    @property
    def np_random(self):
        """The generator that draws the seed of a first reset() without one."""
        if self._np_random is None:
            self._np_random, _ = _np_random()
        return self._np_random

    @property
    def unwrapped(self):
        return self

    def observation_space(self, agent):
        """The agent's observation space (the same object at every call)."""
        return self.observation_spaces[self._agent(agent, "observation_space")]

    def action_space(self, agent):
        """The agent's action space (the same object at every call)."""
        return self.action_spaces[self._agent(agent, "action_space")]

    def reset(self, seed=None, options=None):
        """Starts an episode, every robot an agent again; returns (observations, infos), dicts
        keyed by agent. `seed`: see the module docstring; `options`: {"trial": k}."""
        self._check_open()
        if seed is not None:
            seed = _whole("seed", seed, 0, 2**64 - 1)
            self._np_random, _ = _np_random(seed)
            self.episode_seed, self._next_trial = seed, 0
        elif self.episode_seed is None:
            self.episode_seed, self._next_trial = int(self.np_random.integers(2**63)), 0
        options = {} if options is None else options
        if not isinstance(options, dict) or set(options) - {"trial"}:
            raise ValueError(f"options may hold only 'trial', got {_shown(options)}")
        self.trial = _whole("trial", options.get("trial", self._next_trial), 0, 2**64 - 1)
        self._next_trial = self.trial + 1
        self._world.reset(self.episode_seed, self.trial)
        self._started = True
        self.agents = list(self.possible_agents)
        obs = self._world.observations()
        infos = self._infos(self.agents)
        return {a: obs[self._index[a]] for a in self.agents}, infos

    def step(self, actions):
        """One decision of every agent: `actions` is a dict holding an action for each agent in
        ``agents`` and no other. Returns (observations, rewards, terminations, truncations,
        infos), dicts keyed by the agents of the step; those terminated or truncated then leave
        ``agents``."""
        self._check_open()
        if not self._started:
            raise RuntimeError("call reset() before step()")
        if not self.agents:
            raise RuntimeError("every agent's run has ended: call reset()")
        values = self._actions(actions)
        obs, reward, terminated, truncated = self._world.step(values)
        live = self.agents
        infos = self._infos(live)
        rewards = {a: float(reward[self._index[a]]) for a in live}
        if self.reward_fn is not None:
            for a in live:
                infos[a]["reward"] = rewards[a]
            rewards = _rewards(self.reward_fn(infos), live)
        terminations = {a: bool(terminated[self._index[a]]) for a in live}
        truncations = {a: bool(truncated[self._index[a]]) for a in live}
        observations = {a: obs[self._index[a]] for a in live}
        self.agents = [a for a in live if not (terminations[a] or truncations[a])]
        return observations, rewards, terminations, truncations, infos

    def state(self):
        """Every robot's true pose now (x, y, heading; m, m, rad), robot 0 first, as float32:
        for a centralised critic, not for the agents."""
        self._check_open()
        if not self._started:
            raise RuntimeError("call reset() before state()")
        info = self._world.info()
        return np.column_stack([info["x"], info["y"], info["heading"]]).astype(
            np.float32).reshape(-1)

    def render(self):
        """No rendering: draw a single robot's episode with plumetrace.env.PlumeEnv."""
        return None

    def close(self):
        """Frees the team; may be called again."""
        self._world = None
        self.agents = []
        self.closed = True

    def result(self, agent):
        """The agent's run's metrics so far (a dict, as a run's)."""
        self._check_open()
        if not self._started:
            raise RuntimeError("call reset() before result()")
        return json.loads(self._world.result_json(self._index[self._agent(agent, "result")]))

    def __enter__(self):
        return self

    def __exit__(self, *args):
        self.close()
        return False

    def __repr__(self):
        return (f"TeamPlumeEnv({self.max_num_agents} robots, observe={self.observe}, "
                f"action={self.action!r})")

    def _check_open(self):
        if self.closed:
            raise RuntimeError("the TeamPlumeEnv is closed")

    def _agent(self, agent, where):
        if isinstance(agent, str) and agent in self._index:
            return agent
        raise ValueError(f"{where}: {_shown(agent)} is not an agent of this team; the agents are "
                         f"{_names(self.possible_agents)}")

    def _infos(self, agents):
        info = self._world.info()
        infos = {}
        for a in agents:
            k = self._index[a]
            infos[a] = {"time": float(info["time"][k]), "outcome": info["outcome"][k],
                        "pose": (float(info["x"][k]), float(info["y"][k]),
                                 float(info["heading"][k])),
                        "source_distance": float(info["source_distance"][k]),
                        "odometer": float(info["odometer"][k]),
                        "seed": self.episode_seed, "trial": self.trial}
            if not info["running"][k]:
                infos[a]["result"] = json.loads(self._world.result_json(k))
        return infos

    def _actions(self, actions):
        if not isinstance(actions, dict):
            raise TypeError(f"actions must be a dict keyed by agent, got {_shown(actions)}")
        for agent in actions:
            if agent not in self._index:
                raise ValueError(f"actions: {_shown(agent)} is not an agent of this team; the "
                                 f"agents are {_names(self.possible_agents)}")
            if agent not in self.agents:
                raise ValueError(f"actions: {agent}'s run has ended (it left agents); act only "
                                 f"for env.agents = {_names(self.agents)}")
        missing = [a for a in self.agents if a not in actions]
        if missing:
            raise ValueError(f"actions: no action for {_names(missing)}; every agent in "
                             f"env.agents acts at every step")
        values = np.zeros(len(self.possible_agents))
        for agent, action in actions.items():
            values[self._index[agent]] = self._action(agent, action)
        return values

    def _action(self, agent, action):
        n = self.discrete_headings
        want = (f"an int from 0 to {n - 1}" if n is not None else
                "a number in [-1, 1] or an array of one (clipped to [-1, 1])")

        def refused(kind, why):
            return kind(f"action of {agent}: {_shown(action)}: {why}; an action is {want}")

        if action is None or isinstance(action, (str, bytes)):
            raise refused(TypeError, "not a number")
        if _is_bool(action):
            raise refused(TypeError, "a bool is no action")
        value = action
        if not isinstance(action, numbers.Number):
            try:
                array = np.asarray(action)
            except (TypeError, ValueError, OverflowError):
                raise refused(TypeError, "not an array of numbers") from None
            if array.dtype.kind == "b":
                raise refused(TypeError, "an array of bools")
            if array.dtype.kind not in ("iu" if n is not None else "iuf"):
                raise refused(TypeError, f"an array of {array.dtype}")
            if array.shape not in ((), (1,)):
                raise refused(ValueError, f"shape {array.shape}, not (1,)")
            value = array.reshape(-1)[0].item()
        if not isinstance(value, numbers.Real) or (n is not None
                                                   and not isinstance(value, numbers.Integral)):
            raise refused(TypeError, f"a {type(value).__name__} is no "
                                     f"{'index' if n is not None else 'real number'}")
        if n is not None:
            if not 0 <= int(value) < n:
                raise refused(ValueError, f"out of 0 to {n - 1}")
            return float(value)
        try:
            value = float(value)
        except OverflowError:
            value = math.inf
        if not math.isfinite(value):
            raise refused(ValueError, "not a finite number")
        return value


def _names(agents):
    return "[" + ", ".join(agents) + "]" if len(agents) <= 8 else (
        f"[{agents[0]}, ..., {agents[-1]}] ({len(agents)})")


def _rewards(values, agents):
    if not isinstance(values, dict):
        raise TypeError(f"reward_fn must return a dict keyed by agent, got {_shown(values)}")
    if set(values) != set(agents):
        raise ValueError(f"reward_fn returned rewards for {_names(sorted(map(str, values)))}, "
                         f"not for the step's agents {_names(agents)}")
    out = {}
    for a in agents:
        v = values[a]
        if _is_bool(v) or not isinstance(v, numbers.Real) or not math.isfinite(float(v)):
            raise ValueError(f"reward_fn: the reward of {a} is {_shown(v)}, not a finite number")
        out[a] = float(v)
    return out
