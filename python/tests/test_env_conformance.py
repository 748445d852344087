"""PlumeEnv against Gymnasium's environment checker.

gymnasium cannot be installed on the machines that run these tests, so its rules are written out
here from gymnasium/utils/env_checker.py and passive_env_checker.py (check_env, in its order):
the spaces, check_seed_deprecation, check_reset_return_type, check_reset_seed_determinism,
check_reset_options, env_reset_passive_checker, env_step_passive_checker,
check_step_determinism, env_render_passive_checker for every declared render mode, and close.
They run whether or not gymnasium is present; where it is, gymnasium's own check_env runs too.
A fake gymnasium package (a few lines, in a temporary folder) checks that PlumeEnv takes the
gymnasium branch: it subclasses gymnasium.Env, uses gymnasium.spaces and is made by
gymnasium.make. It tests our code path, not gymnasium itself.
"""

import copy
import inspect
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from conftest import plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()
from plumetrace import env as envmod  # noqa: E402
from plumetrace.env import PlumeEnv  # noqa: E402

# the environment's shapes: Box and Discrete actions, one simulation step per decision
VARIANTS = {"default": {}, "discrete": {"discrete_headings": 8},
            "every_step": {"decision_interval": 1}}


@pytest.fixture(params=list(VARIANTS))
def env(request):
    e = PlumeEnv(**VARIANTS[request.param])
    yield e
    e.close()


def data_equivalence(a, b, exact=False):
    """env_checker.data_equivalence: same types, same keys, arrays of one shape and dtype that
    are all close (or equal, when exact)."""
    if type(a) is not type(b):
        return False
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(data_equivalence(a[k], b[k], exact) for k in a)
    if isinstance(a, (tuple, list)):
        return len(a) == len(b) and all(data_equivalence(x, y, exact) for x, y in zip(a, b))
    if isinstance(a, np.ndarray):
        if a.shape != b.shape or a.dtype != b.dtype:
            return False
        return bool(np.all(a == b)) if exact else np.allclose(a, b, rtol=1e-5, atol=1e-5)
    return a == b


def check_obs(obs, space):
    """passive_env_checker.check_obs (its warnings as failures): a NumPy array of the space's
    dtype, inside the space."""
    if isinstance(space, envmod.Box):
        assert isinstance(obs, np.ndarray) and obs.dtype == space.dtype, type(obs)
    assert obs in space


def check_space(space):
    """passive_env_checker.check_space, and what a space must offer: seed, sample, contains."""
    if envmod.GYMNASIUM:
        import gymnasium

        assert isinstance(space, gymnasium.spaces.Space)
    for name in ("seed", "sample", "contains", "shape", "dtype"):
        assert hasattr(space, name), name
    if isinstance(space, envmod.Box):
        assert space.low.shape == space.shape and space.high.shape == space.shape
        assert space.low.dtype == space.dtype and space.high.dtype == space.dtype
        assert np.all(space.low < space.high)  # not even equal: a warning in the checker
    else:
        assert isinstance(space, envmod.Discrete) and space.n > 0 and space.shape == ()
    assert space.sample() in space


def test_spaces(env):
    check_space(env.observation_space)
    check_space(env.action_space)
    assert env.observation_space.dtype == np.float32


def test_no_seed_function(env):
    # check_seed_deprecation: env.seed() is gone from Gymnasium; reset(seed=...) seeds
    assert not callable(getattr(env, "seed", None))


def test_reset_return_type(env):
    result = env.reset()
    assert isinstance(result, tuple) and len(result) == 2
    obs, info = result
    check_obs(obs, env.observation_space)
    assert isinstance(info, dict)


def test_reset_signature():
    # env_reset_passive_checker: reset takes seed and options, and seed defaults to None
    parameters = inspect.signature(PlumeEnv.reset).parameters
    assert parameters["seed"].default is None and parameters["options"].default is None


def test_reset_seed_determinism(env):
    obs_1, _ = env.reset(seed=123)
    assert obs_1 in env.observation_space
    assert env.unwrapped._np_random is not None
    rng_1 = copy.deepcopy(env.unwrapped._np_random)
    obs_2, _ = env.reset()
    obs_3, _ = env.reset(seed=123)
    rng_3 = copy.deepcopy(env.unwrapped._np_random)
    obs_4, _ = env.reset()
    for obs in (obs_2, obs_3, obs_4):
        assert obs in env.observation_space
    # the spec of a made environment says nondeterministic=False: these must hold, exactly
    assert data_equivalence(obs_1, obs_3, exact=True)
    assert data_equivalence(obs_2, obs_4, exact=True)
    assert rng_1.bit_generator.state == rng_3.bit_generator.state
    obs_5, _ = env.reset(seed=456)
    assert obs_5 in env.observation_space
    assert env.unwrapped._np_random.bit_generator.state != rng_1.bit_generator.state


def test_reset_options(env):
    obs, info = env.reset(options={})
    assert obs in env.observation_space


def test_step_return_types(env):
    # env_step_passive_checker, after env_reset_passive_checker
    env.reset()
    result = env.step(env.action_space.sample())
    assert isinstance(result, tuple) and len(result) == 5
    obs, reward, terminated, truncated, info = result
    assert isinstance(terminated, (bool, np.bool_)) and isinstance(truncated, (bool, np.bool_))
    check_obs(obs, env.observation_space)
    assert np.issubdtype(type(reward), np.floating) and np.isfinite(reward)
    assert isinstance(info, dict)


def test_step_determinism(env, seed=123):
    env.action_space.seed(seed)
    action = env.action_space.sample()
    env.reset(seed=seed)
    obs_0, rew_0, term_0, trunc_0, info_0 = env.step(action)
    rng = copy.deepcopy(env.unwrapped._np_random)
    env.reset(seed=seed)
    obs_1, rew_1, term_1, trunc_1, info_1 = env.step(action)
    assert env.unwrapped._np_random.bit_generator.state == rng.bit_generator.state
    assert data_equivalence(obs_0, obs_1, exact=True)
    assert data_equivalence(rew_0, rew_1, exact=True)
    assert data_equivalence(term_0, term_1, exact=True)
    assert trunc_0 is False and trunc_1 is False  # no truncation after one step
    assert data_equivalence(info_0, info_1, exact=True)


def test_render_metadata_and_every_declared_mode():
    # env_render_passive_checker, then each declared mode made anew, reset and rendered
    modes = PlumeEnv.metadata["render_modes"]
    assert isinstance(modes, (list, tuple)) and all(isinstance(m, str) for m in modes)
    assert set(modes) == {"human", "rgb_array"}
    for mode in modes:
        env = PlumeEnv(render_mode=mode)
        fps = env.metadata["render_fps"]
        assert np.issubdtype(type(fps), np.floating) and fps > 0
        assert fps == pytest.approx(1.0 / env.dt)  # real time
        env.reset()
        frame = env.render()
        if mode == "human":
            assert frame is None
        else:
            assert isinstance(frame, np.ndarray) and frame.dtype == np.uint8
            assert frame.ndim == 3 and frame.shape[2] == 3
        env.close()


def test_close_twice(env):
    env.reset()
    env.close()
    env.close()


@pytest.mark.parametrize("variant", list(VARIANTS))
def test_a_random_episode_stays_in_its_spaces(variant):
    # the checker's single steps, over a whole episode (a short timeout)
    env = PlumeEnv(supervisor__timeout=30.0, **VARIANTS[variant])
    env.action_space.seed(3)
    obs, _ = env.reset(seed=3)
    steps = 0
    while True:
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        check_obs(obs, env.observation_space)
        assert type(terminated) is bool and type(truncated) is bool and type(reward) is float
        steps += 1
        if terminated or truncated:
            break
    assert info["outcome"] in ("timeout", "wall") and steps > 10


# -- our spaces (without gymnasium): the API of gymnasium.spaces -------------------------------

def test_our_box_seeds_samples_and_contains_like_gymnasium():
    box = envmod._Box(np.array([-1.0, 0.0, -np.inf, 2.0], np.float32),
                      np.array([1.0, np.inf, np.inf, 2.5], np.float32))
    assert box.shape == (4,) and box.dtype == np.float32
    assert box.low.dtype == box.high.dtype == np.float32
    assert box.seed(5) == [5]
    a = np.array([box.sample() for _ in range(2000)])
    box.seed(5)
    b = np.array([box.sample() for _ in range(2000)])
    assert np.array_equal(a, b) and a.dtype == np.float32
    assert all(x in box for x in a)
    # uniform on [-1, 1]: mean 0 within 4 sigma (sigma = 1/sqrt(3 n)); exponential from 0: mean 1
    assert abs(a[:, 0].mean()) < 4 / np.sqrt(3 * 2000)
    assert abs(a[:, 1].mean() - 1.0) < 4 / np.sqrt(2000)
    assert abs(a[:, 2].mean()) < 4 / np.sqrt(2000) and a[:, 2].min() < -1.0
    assert a[:, 3].min() >= 2.0 and a[:, 3].max() <= 2.5
    # the same draws as gymnasium's Box, from the generator gymnasium.utils.seeding makes
    rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence(5)))
    first = np.empty(4)
    first[2] = rng.normal(size=1)[0]
    first[1] = rng.exponential(size=1)[0]
    first[[0, 3]] = rng.uniform(low=box.low[[0, 3]], high=box.high[[0, 3]], size=2)
    assert np.array_equal(first.astype(np.float32), a[0])
    assert not box.contains(np.zeros(4, np.float64))  # float64 does not cast safely to float32
    assert not box.contains(np.zeros(3, np.float32)) and not box.contains("x")
    assert box.contains([0.0, 0.0, 0.0, 2.0]) and not box.contains([2.0, 0.0, 0.0, 2.0])
    assert not box.is_bounded() and box.is_bounded("below") is False


def test_our_discrete_seeds_samples_and_contains_like_gymnasium():
    space = envmod._Discrete(5)
    assert space.shape == () and space.dtype == np.int64 and space.n == 5
    space.seed(9)
    a = [space.sample() for _ in range(500)]
    space.seed(9)
    assert a == [space.sample() for _ in range(500)]
    assert set(a) == {0, 1, 2, 3, 4} and all(type(x) is np.int64 for x in a)
    assert 4 in space and np.int32(0) in space and np.array(3) in space
    # (a bool is not an action here, where gymnasium's Discrete takes True as 1)
    assert 5 not in space and -1 not in space and 1.0 not in space and True not in space
    assert np.array([1]) not in space


def test_our_env_base_seeds_np_random_like_gymnasium():
    base = envmod._Env()
    base.reset(seed=42)
    expected = np.random.Generator(np.random.PCG64(np.random.SeedSequence(42)))
    assert base.np_random.integers(10**9) == expected.integers(10**9)
    assert base.np_random_seed == 42 and base.unwrapped is base
    with envmod._Env() as other:
        assert other.np_random is not None  # from fresh entropy
        other.np_random = np.random.default_rng(1)
        assert other.np_random_seed == -1  # a generator set directly: its seed is unknown


# -- gymnasium itself, where it is installed ---------------------------------------------------

@pytest.mark.skipif(not envmod.GYMNASIUM, reason="gymnasium is not installed")
def test_gymnasium_check_env_passes():
    import gymnasium
    from gymnasium.utils.env_checker import check_env

    env = gymnasium.make(envmod.ENV_ID)
    assert isinstance(env.unwrapped, PlumeEnv)
    check_env(env.unwrapped)


# -- the gymnasium branch, with a fake gymnasium -------------------------------------------------

FAKE_GYMNASIUM = '''
"""A stand-in for gymnasium: the few names plumetrace.env uses, for a test."""
import importlib

import numpy as np

from . import spaces

registry = {}


class Env:
    metadata = {"render_modes": []}
    render_mode = None
    spec = None
    _np_random = None

    @property
    def np_random(self):
        if self._np_random is None:
            self._np_random = np.random.default_rng()
        return self._np_random

    @property
    def unwrapped(self):
        return self

    def reset(self, *, seed=None, options=None):
        if seed is not None:
            self._np_random = np.random.default_rng(seed)

    def close(self):
        pass


class EnvSpec:
    def __init__(self, id, entry_point, kwargs):
        self.id, self.entry_point, self.kwargs = id, entry_point, kwargs


def register(id, entry_point, **kwargs):
    registry[id] = EnvSpec(id, entry_point, kwargs)


def make(id, **kwargs):
    spec = registry[id]
    module, name = spec.entry_point.split(":")
    env = getattr(importlib.import_module(module), name)(**{**spec.kwargs, **kwargs})
    env.unwrapped.spec = spec
    return env
'''

FAKE_SPACES = '''
import numpy as np


class Space:
    def seed(self, seed=None):
        self.np_random = np.random.default_rng(seed)
        return [seed]


class Box(Space):
    def __init__(self, low, high, shape=None, dtype=np.float32, seed=None):
        self.dtype = np.dtype(dtype)
        self.low, self.high = low.astype(self.dtype), high.astype(self.dtype)
        self.shape = self.low.shape
        self.seed(seed)

    def sample(self):
        low = np.where(np.isfinite(self.low), self.low, -1.0)
        high = np.where(np.isfinite(self.high), self.high, 1.0)
        return self.np_random.uniform(low, high).astype(self.dtype)

    def contains(self, x):
        return x.shape == self.shape and bool(np.all(x >= self.low) and np.all(x <= self.high))

    __contains__ = contains


class Discrete(Space):
    def __init__(self, n, seed=None, start=0):
        self.n, self.shape, self.dtype = n, (), np.dtype(np.int64)
        self.seed(seed)

    def sample(self):
        return self.np_random.integers(self.n)
'''

WITH_FAKE = textwrap.dedent('''
    import gymnasium
    import numpy as np

    from plumetrace import env as envmod
    from plumetrace.env import ENV_ID, PlumeEnv

    assert envmod.GYMNASIUM and gymnasium.__file__.startswith(FAKE), gymnasium.__file__
    assert issubclass(PlumeEnv, gymnasium.Env)
    assert envmod.Box is gymnasium.spaces.Box and envmod.Discrete is gymnasium.spaces.Discrete
    assert list(gymnasium.registry) == [ENV_ID]  # registered on import of plumetrace.env

    env = gymnasium.make(ENV_ID, render_mode="rgb_array", decision_interval=4)
    assert type(env) is PlumeEnv and env.spec.id == ENV_ID and env.decision_interval == 4
    assert type(env.observation_space) is gymnasium.spaces.Box
    assert type(env.action_space) is gymnasium.spaces.Box
    discrete = gymnasium.make(ENV_ID, discrete_headings=6)
    assert type(discrete.action_space) is gymnasium.spaces.Discrete
    obs, info = env.reset(seed=7)
    # reset(seed=...) went through gymnasium.Env.reset: the fake's np_random
    assert env.np_random.integers(10**9) == np.random.default_rng(7).integers(10**9)
    assert obs in env.observation_space and obs.dtype == np.float32
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    assert obs in env.observation_space and info["time"] > 4 * 0.032
    assert env.render().shape == (320, 960, 3)
    envmod.register_envs()  # again: nothing changes
    assert list(gymnasium.registry) == [ENV_ID]
    print("gymnasium branch ok")
''')

AS_PLUGIN = textwrap.dedent('''
    # what Gymnasium does with a "gymnasium.envs" entry point at import: call the function, which
    # must not import plumetrace's C++ module; make() then loads the environment
    import sys

    import gymnasium
    from plumetrace.registration import ENV_ID, register_envs

    register_envs()
    assert "plumetrace.env" not in sys.modules
    env = gymnasium.make(ENV_ID)
    assert type(env).__module__ == "plumetrace.env" and isinstance(env, gymnasium.Env)
    assert env.reset(seed=1)[1]["seed"] == 1
    print("plugin ok")
''')


@pytest.mark.parametrize("script", [WITH_FAKE, AS_PLUGIN], ids=["make", "entry_point"])
def test_with_a_fake_gymnasium_plumeenv_is_a_gymnasium_env_made_by_make(tmp_path, script):
    fake = tmp_path / "fake"
    (fake / "gymnasium").mkdir(parents=True)
    (fake / "gymnasium" / "__init__.py").write_text(FAKE_GYMNASIUM)
    (fake / "gymnasium" / "spaces.py").write_text(FAKE_SPACES)
    package = Path(pt.__file__).resolve().parents[1]
    done = subprocess.run(
        [sys.executable, "-c", f"FAKE = {str(fake)!r}\n" + script], capture_output=True,
        text=True, timeout=300, cwd=tmp_path,
        env={**os.environ, "PYTHONPATH": os.pathsep.join([str(fake), str(package)]),
             "MPLBACKEND": "Agg"})
    assert done.returncode == 0, done.stdout + done.stderr
    assert "ok" in done.stdout
