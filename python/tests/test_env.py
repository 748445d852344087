"""The Gymnasium-style environment: conventions, determinism, and equality with the runner."""

import math

import numpy as np
import pytest

from conftest import plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()
from plumetrace.env import PlumeEnv  # noqa: E402


def test_reset_and_step_follow_gymnasium_conventions():
    env = PlumeEnv()
    obs, info = env.reset(seed=3)
    assert env.observation_space.contains(obs) and obs.shape == (7,)
    assert obs[0] in (0.0, 1.0) and obs[1:5].tolist() == [0.0, 0.0, 0.0, 0.0]
    assert env.action_space.contains(env.action_space.sample())
    obs, reward, terminated, truncated, info = env.step(0.0)
    assert isinstance(reward, float) and not terminated and not truncated
    assert info["time"] == pytest.approx(0.032)
    assert obs[4] > 0.0  # it drove


def test_driving_upwind_from_the_start_reaches_the_wall_or_source():
    # heading 0 in the odometry frame is the robot's start heading: upwind
    env = PlumeEnv(robot__start_x=4.0)
    env.reset(seed=1)
    steps, done = 0, False
    while not done:
        obs, reward, terminated, truncated, info = env.step(np.array([0.0]))
        done = terminated or truncated
        steps += 1
    assert info["outcome"] in ("success", "wall")
    assert reward == float(info["outcome"] == "success")
    assert info["result"]["steps"] == steps
    # 3 m upwind at 0.106 m/s and 0.032 s per step: about 885 steps
    assert abs(info["pose"][0] - 1.0) < 0.3 or info["outcome"] == "wall"


def test_the_same_seed_and_trial_replay_exactly_and_trials_count_up():
    env = PlumeEnv()
    def episode(**reset):
        obs, info = env.reset(**reset)
        trace = [obs]
        for k in range(200):
            obs, *_ = env.step(math.sin(k / 20.0))
            trace.append(obs)
        return np.array(trace), info["trial"]
    a, trial_a = episode(seed=5)
    b, trial_b = episode()
    c, trial_c = episode(seed=5)
    assert (trial_a, trial_b, trial_c) == (0, 1, 0)
    assert np.array_equal(a, c) and not np.array_equal(a, b)


def test_surge_cast_driving_the_environment_gets_the_built_in_run():
    # the environment is the runner's loop split in two: an agent that decides like the
    # built-in surge-cast (examples/python_surge_cast.py, fed from the observation array and
    # sampling the wind on demand) reproduces the built-in run exactly
    import importlib.util
    from pathlib import Path
    from types import SimpleNamespace

    root = Path(__file__).resolve().parents[2]
    spec = importlib.util.spec_from_file_location("sc", root / "examples" / "python_surge_cast.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)

    for trial in range(3):
        env = PlumeEnv(wind_every_step=False, wind_sensor__sigma_a=0.3)
        obs, _ = env.reset(seed=4, options={"trial": trial})
        from plumetrace.controllers import controller_rng
        agent = example.SurgeCast(pt.Scenario()["py_surge_cast"], controller_rng(4, trial))
        wind = SimpleNamespace(measure_wind_body=env.measure_wind)
        while True:
            seen = SimpleNamespace(odor=bool(obs[0]), odometer=obs[4], time=0.0,
                                   odometry=SimpleNamespace(x=obs[1], y=obs[2], heading=obs[3]))
            obs, _, terminated, truncated, info = env.step(agent.step(seen, wind))
            if terminated or truncated:
                break
        builtin = pt.run(algorithm="surge-cast", seed=4, trial=trial, wind_sensor__sigma_a=0.3,
                         trace=False)
        for key in ("outcome", "time_s", "d_t", "d_u", "steps", "wind_samples", "odor_fraction"):
            assert info["result"][key] == builtin[key], (trial, key)
