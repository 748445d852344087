"""plumetrace.vector.VectorPlumeEnv: Gymnasium's vector conventions (spaces, dtypes, next-step
autoreset, seeding), exact replays (against itself at any thread count, and against PlumeEnv
with renewed plumes), agents that share a plume without disturbing each other, observations,
rewards and bad input. gymnasium is not installed here: its vector API is written out; a fake
gymnasium package checks the gymnasium branch."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from conftest import plumetrace_with_core

pt = plumetrace_with_core()
from plumetrace import vector  # noqa: E402
from plumetrace.env import Box, Discrete, PlumeEnv  # noqa: E402
from plumetrace.vector import VectorPlumeEnv  # noqa: E402

# short episodes: a truncation after 2 s (63 steps)
SHORT = {"supervisor__timeout": 2.0}


def actions(n, steps, seed=0, discrete=None):
    rng = np.random.default_rng(seed)
    if discrete:
        return rng.integers(discrete, size=(steps, n))
    return rng.uniform(-1.0, 1.0, size=(steps, n, 1)).astype(np.float32)


def play(env, seed, acts):
    """Every output of reset(seed) and the steps, as a list of arrays."""
    obs, info = env.reset(seed=seed)
    out = [obs] + [info[k] for k in sorted(info)]
    for a in acts:
        obs, reward, terminated, truncated, info = env.step(a)
        out += [obs, reward, terminated, truncated] + [info[k] for k in sorted(info)]
    return out


def test_spaces_dtypes_and_batched_outputs_follow_gymnasium_vector_conventions():
    env = VectorPlumeEnv(6, group_size=3, observe=("odor", "odor_fraction", "wind", "odometry",
                                                   "time"), **SHORT)
    assert env.num_envs == 6 and env.metadata["autoreset_mode"] in ("NextStep",
                                                                     vector._NEXT_STEP)
    single, batched = env.single_observation_space, env.observation_space
    assert isinstance(single, Box) and single.shape == (9,) and single.dtype == np.float32
    assert batched.shape == (6, 9) and np.array_equal(batched.low[3], single.low)
    # finite bounds wherever the value is bounded: all but the wind sample
    finite = np.isfinite(single.low) & np.isfinite(single.high)
    assert list(np.flatnonzero(~finite)) == [2, 3]
    assert env.single_action_space == Box(np.float32([-1]), np.float32([1]), dtype=np.float32)
    assert env.action_space.shape == (6, 1)
    assert len(env.observation_names) == 9 and env.observation_names[-1] == "time"
    obs, info = env.reset(seed=5)
    assert obs.dtype == np.float32 and obs.shape == (6, 9) and obs in batched
    assert set(info) == {"outcome", "time", "x", "y", "heading", "source_distance", "odometer",
                         "seed", "trial"}
    assert all(v.shape == (6,) for v in info.values())
    assert list(info["seed"]) == [5, 6, 7, 8, 9, 10] and not info["trial"].any()
    env.action_space.seed(1)
    for _ in range(80):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert obs in batched and obs.dtype == np.float32
        assert reward.dtype == np.float64 and reward.shape == (6,)
        assert terminated.dtype == bool and truncated.dtype == bool
        assert not (terminated & truncated).any()
    assert info["trial"].min() >= 1  # every episode ended by the 2 s timeout at the latest
    env.close()
    env.close()  # twice: nothing happens
    with pytest.raises(RuntimeError, match="closed"):
        env.step(np.zeros((6, 1)))


@pytest.mark.parametrize("n, steps, options", [
    (8, 90, dict(group_size=2, wind__model="meander")),
    # why: the agents are split among the threads in chunks of 16 whatever the groups: one plume
    # of 40 agents, and 17 plumes renewed at each episode (past the first autoreset), each
    # decision 3 steps
    (40, 90, dict(group_size=40, decision_interval=3, observation="concentration")),
    (17, 25, dict(renew_plumes=True, decision_interval=3)),
])
def test_the_same_seed_and_actions_replay_every_value_whatever_the_thread_count(n, steps, options):
    acts = actions(n, steps)
    runs = [play(VectorPlumeEnv(n, threads=t, **options, **SHORT), 11, acts)
            for t in (1, 2, 3, 1)]
    for other in runs[1:]:
        assert len(other) == len(runs[0])
        assert all(np.array_equal(a, b) for a, b in zip(runs[0], other))
    # another seed, another plume and other starts
    assert not np.array_equal(play(VectorPlumeEnv(n, **options, **SHORT), 12, acts[:1])[0],
                              runs[0][0])


def test_with_renewed_plumes_environment_i_plays_plumeenv_episodes_of_seed_s_plus_i():
    # why: the strongest check of the C++ stepping: PlumeEnv drives World one step at a time in
    # Python; the same actions give the same bits, across an autoreset into the next trial
    d, n, steps = 4, 2, 40
    vec = VectorPlumeEnv(n, renew_plumes=True, decision_interval=d,
                         observe=("odor", "odor_fraction", "wind", "odometry"), **SHORT)
    acts = actions(n, steps, seed=3)
    obs, _ = vec.reset(seed=20)
    rows = [obs]
    flags = []
    for a in acts:
        obs, reward, terminated, truncated, info = vec.step(a)
        rows.append(obs)
        flags.append((reward, terminated, truncated, info["trial"]))
    for i in range(n):
        single = PlumeEnv(decision_interval=d, normalized_actions=True, **SHORT)
        o, _ = single.reset(seed=20 + i)
        # PlumeEnv: odor, x, y, heading, odometer, wind_x, wind_y, odor fraction
        order = [0, 7, 5, 6, 1, 2, 3, 4]
        assert np.array_equal(o[order], rows[0][i])
        ended, trials = False, 0
        for t, a in enumerate(acts):
            reward, terminated, truncated, trial = (f[i] for f in flags[t])
            if ended:
                o, _ = single.reset()  # the next trial, as the autoreset step
                trials += 1
                assert reward == 0 and not terminated and not truncated and trial == trials
            else:
                o, r, term, trunc, _ = single.step(a[i])
                assert (r, term, trunc) == (reward, terminated, truncated)
            assert np.array_equal(o[order], rows[t + 1][i]), (i, t)
            ended = not ended and (terminated or truncated)
        assert trials >= 1  # the comparison went through an autoreset


def test_agents_on_one_plume_do_not_disturb_each_other():
    steps = 60
    acts = actions(4, steps, seed=1)
    shared = play(VectorPlumeEnv(4, group_size=4, observe=("odor", "wind", "odometry", "time")),
                  30, acts)
    other = acts.copy()
    other[:, 1:] = -other[:, 1:]  # the others drive elsewhere
    moved = play(VectorPlumeEnv(4, group_size=4, observe=("odor", "wind", "odometry", "time")),
                 30, other)
    alone = play(VectorPlumeEnv(1, observe=("odor", "wind", "odometry", "time")), 30,
                 acts[:, :1])
    # robot 0 of the group is run (30, 0) in its plume, whatever the others do, and alone
    for a, b, c in zip(shared, moved, alone):
        assert np.array_equal(a[:1], b[:1]) and np.array_equal(a[:1], c[:1])
    assert not all(np.array_equal(a[1:], b[1:]) for a, b in zip(shared, moved))


def test_next_step_autoreset_ignores_the_action_and_starts_the_next_trial():
    env = VectorPlumeEnv(3, observe=("odor", "odometry", "time"), **SHORT)
    env.reset(seed=2)
    first_time = env.reset(seed=2)[0][:, -1].copy()
    done = np.zeros(3, bool)
    for _ in range(200):
        obs, reward, terminated, truncated, info = env.step(np.zeros((3, 1)))
        if (terminated | truncated).any():
            done = terminated | truncated
            break
    assert done.any()
    twin = VectorPlumeEnv(3, observe=("odor", "odometry", "time"), **SHORT)
    play(twin, 2, [np.zeros((3, 1))] * (_ + 1))
    obs, reward, terminated, truncated, info = env.step(np.full((3, 1), 0.5))
    obs2, *_ = twin.step(np.full((3, 1), -0.5))
    assert np.array_equal(obs[done], obs2[done])  # the action of an ended episode is ignored
    assert (reward[done] == 0).all() and not terminated[done].any()
    assert not truncated[done].any() and (info["trial"][done] == 1).all()
    # a new episode starts its clock and odometry at 0 (time: one step since release)
    assert np.allclose(obs[done][:, -1], first_time[done])
    assert (obs[done][:, 1:5] == 0).all()


def test_a_masked_reset_restarts_only_the_flagged_environments():
    acts = actions(4, 30, seed=4)
    a = VectorPlumeEnv(4, group_size=2)
    b = VectorPlumeEnv(4, group_size=2)
    for env in (a, b):
        env.reset(seed=8)
        for x in acts[:10]:
            env.step(x)
    mask = np.array([False, True, False, False])
    obs, info = a.reset(options={"reset_mask": mask})
    assert list(info["trial"]) == [0, 1, 0, 0] and (obs[1, 3:] == 0).all()
    for x in acts[10:]:
        oa, *_ = a.step(x)
        ob, *_ = b.step(x)
    assert np.array_equal(oa[[0, 2, 3]], ob[[0, 2, 3]])
    # an unseeded reset starts every environment's next trial on new plumes
    _, info = a.reset()
    assert list(info["trial"]) == [1, 2, 1, 1]
    with pytest.raises(ValueError, match="reset_mask"):
        a.reset(options={"reset_mask": [1, 0, 0, 0]})
    with pytest.raises(ValueError, match="keeps the seeds"):
        a.reset(seed=1, options={"reset_mask": mask})


def test_stacked_frames_are_the_last_observations_newest_first():
    env = VectorPlumeEnv(2, stack=3, observe=("odor", "odometry"), **SHORT)
    obs, _ = env.reset(seed=3)
    assert obs.shape == (2, 15) and np.array_equal(obs[:, :5], obs[:, 5:10])
    assert env.observation_names[5] == "odor[1]"
    frames = [obs[:, :5]]
    for a in actions(2, 8, seed=5):
        obs, *_ = env.step(a)
        frames.append(obs[:, :5])
        assert np.array_equal(obs[:, 5:10], frames[-2]) and np.array_equal(obs[:, 10:],
                                                                            frames[-3 if len(frames) > 2 else -2])


def test_shaped_rewards_add_up_to_the_share_of_the_distance_closed():
    env = VectorPlumeEnv(4, reward="shaped", decision_interval=8, **SHORT)
    _, info = env.reset(seed=9)
    start = info["source_distance"].copy()
    total = np.zeros(4)
    ended = np.zeros(4, bool)
    for a in actions(4, 20, seed=6):
        _, reward, terminated, truncated, info = env.step(a)
        total += np.where(ended, 0.0, reward)
        end = ~ended & (terminated | truncated)
        final = np.where(end, info["source_distance"], np.nan)
        for i in np.flatnonzero(end):
            success = terminated[i] and info["outcome"][i] == vector.OUTCOMES.index("success")
            assert total[i] == pytest.approx((start[i] - final[i]) / start[i] + success,
                                             abs=1e-9)
        ended |= end
    assert ended.all()


def test_a_reward_function_gets_the_batch_and_replaces_the_reward():
    seen = []

    def closer(info):
        seen.append(set(info))
        return -info["source_distance"]

    env = VectorPlumeEnv(3, reward_fn=closer)
    env.reset(seed=1)
    _, reward, *_ , info = env.step(np.zeros((3, 1)))
    assert np.array_equal(reward, -info["source_distance"]) and "reward" in seen[0]
    bad = VectorPlumeEnv(3, reward_fn=lambda info: np.zeros(2))
    bad.reset(seed=1)
    with pytest.raises(ValueError, match="reward_fn must return 3"):
        bad.step(np.zeros((3, 1)))


def test_discrete_and_turn_actions_drive_along_their_headings():
    env = VectorPlumeEnv(4, action="discrete", discrete_headings=4, observe=("odometry",),
                         decision_interval=100)
    assert env.single_action_space == Discrete(4) and env.action_space.shape == (4,)
    env.reset(seed=1)
    obs, *_ = env.step(np.arange(4))
    heading = np.arctan2(obs[:, 1], obs[:, 0])  # where each went from the release point
    assert np.allclose(np.cos(heading - np.pi / 2 * np.arange(4)), 1.0, atol=0.05)
    turn = VectorPlumeEnv(2, action="turn", observe=("odometry",), decision_interval=40)
    turn.reset(seed=1)
    turn.step(np.array([0.5, -0.5]))
    obs, *_ = turn.step(np.array([0.5, -0.5]))  # a quarter turn twice: backward
    assert np.allclose(np.abs(obs[:, 2]), np.pi, atol=0.05)


def test_concentration_observations_are_the_readings_the_binary_ones_threshold():
    kw = dict(observe=("odor",), decision_interval=1)
    binary, conc = VectorPlumeEnv(16, group_size=16, **kw), VectorPlumeEnv(
        16, group_size=16, observation="concentration", **kw)
    threshold = binary.observation_space  # noqa: F841 (bounds checked below)
    assert conc.single_observation_space.high[0] == np.inf
    a, b = binary.reset(seed=4)[0], conc.reset(seed=4)[0]
    levels = []
    for x in actions(16, 40, seed=2):
        levels.append((a[:, 0], b[:, 0]))
        a, b = binary.step(x)[0], conc.step(x)[0]
    odor, reading = np.concatenate([p for p, _ in levels]), np.concatenate([q for _, q in levels])
    assert odor.any() and not odor.all()
    # odor is perceived exactly where the reading reaches the threshold (odor.threshold = 100)
    assert (reading[odor == 1] >= 100 * (1 - 1e-6)).all() and (reading[odor == 0] < 100).all()


@pytest.mark.parametrize("kwargs, error, says", [
    ({"num_envs": 0}, ValueError, "num_envs"),
    ({"num_envs": vector.MAX_ENVS + 1}, ValueError, "num_envs"),
    ({"num_envs": True}, TypeError, "num_envs"),
    ({"num_envs": 6, "group_size": 4}, ValueError, "group_size = 4 must divide num_envs = 6"),
    ({"num_envs": 4, "group_size": 2, "renew_plumes": True}, ValueError, "renew_plumes"),
    ({"observe": ("odor", "smell")}, ValueError, "observe: 'smell'"),
    ({"observe": ()}, ValueError, "at least one"),
    ({"stack": 0}, ValueError, "stack"),
    ({"action": "discrete"}, ValueError, "discrete_headings"),
    ({"reward": "dense"}, ValueError, "reward"),
    ({"team__count": 2}, ValueError, "team.count = 2"),
    ({"seed": 3}, TypeError, "reset\\(seed"),
    ({"wind__vx": "fast"}, Exception, "wind.vx"),
])
def test_bad_options_are_refused_naming_them(kwargs, error, says):
    with pytest.raises(error, match=says):
        VectorPlumeEnv(**kwargs)


@pytest.mark.parametrize("acts, error, says", [
    (np.zeros((3, 2)), ValueError, "shape \\(3, 2\\)"),
    (np.zeros(4), ValueError, "shape \\(4,\\)"),
    (np.array([0.0, np.nan, 0.0]), ValueError, "actions\\[1\\] = nan"),
    (np.array([0.0, 0.0, np.inf]), ValueError, "actions\\[2\\]"),
    (np.array([True, False, True]), TypeError, "bools"),
    (True, TypeError, "no array"),
    (None, TypeError, "no array"),
    ("left", TypeError, "no array"),
    (np.array([1j, 0, 0]), TypeError, "complex"),
    ([[0.0], ["x"], [0.0]], TypeError, "actions"),
])
def test_bad_actions_are_refused_before_anything_moves(acts, error, says):
    env = VectorPlumeEnv(3)
    obs, _ = env.reset(seed=1)
    with pytest.raises(error, match=says):
        env.step(acts)
    # nothing moved: the next good step is the first
    twin = VectorPlumeEnv(3)
    twin.reset(seed=1)
    assert np.array_equal(env.step(np.zeros(3))[0], twin.step(np.zeros(3))[0])


def test_bad_discrete_actions_and_seeds_are_refused():
    env = VectorPlumeEnv(2, action="discrete", discrete_headings=3)
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.zeros(2, int))
    env.reset(seed=1)
    with pytest.raises(ValueError, match="actions\\[1\\] = 3: out of 0 to 2"):
        env.step(np.array([0, 3]))
    with pytest.raises(TypeError, match="float64"):
        env.step(np.array([0.0, 1.0]))
    with pytest.raises(ValueError, match="seed"):
        env.reset(seed=-1)
    with pytest.raises(ValueError, match="2 seeds for"):
        VectorPlumeEnv(3).reset(seed=[1, 2])


FAKE_VECTOR = """
import enum


class AutoresetMode(enum.Enum):
    NEXT_STEP = "NextStep"
    SAME_STEP = "SameStep"


class VectorEnv:
    def __del__(self):
        self.close()
"""

FAKE_MULTIDISCRETE = """


class MultiDiscrete(Space):
    def __init__(self, nvec):
        self.nvec = np.asarray(nvec)
        self.shape = self.nvec.shape
"""


def test_with_a_fake_gymnasium_the_vector_env_is_a_gymnasium_vector_env(tmp_path):
    # the fake gymnasium of the PlumeEnv conformance tests, with a vector module
    from test_env_conformance import FAKE_GYMNASIUM, FAKE_SPACES

    (tmp_path / "gymnasium").mkdir()
    (tmp_path / "gymnasium" / "__init__.py").write_text(FAKE_GYMNASIUM + "\nfrom . import vector\n")
    (tmp_path / "gymnasium" / "spaces.py").write_text(FAKE_SPACES + FAKE_MULTIDISCRETE)
    (tmp_path / "gymnasium" / "vector.py").write_text(FAKE_VECTOR)
    script = textwrap.dedent("""
        import gymnasium, numpy as np
        from plumetrace.vector import VectorPlumeEnv
        env = VectorPlumeEnv(4, group_size=2)
        assert isinstance(env, gymnasium.vector.VectorEnv)
        assert env.metadata["autoreset_mode"] is gymnasium.vector.AutoresetMode.NEXT_STEP
        assert type(env.single_observation_space) is gymnasium.spaces.Box
        assert type(VectorPlumeEnv(2, action="discrete", discrete_headings=3).action_space) \\
            is gymnasium.spaces.MultiDiscrete
        obs, info = env.reset(seed=1)
        assert obs.shape == (4, 7)
        env.step(np.zeros((4, 1)))
        print("vector ok")
    """)
    package = Path(pt.__file__).resolve().parents[1]
    path = [str(tmp_path), str(package)] + [
        os.path.abspath(p) for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=120, cwd=tmp_path,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join(path)})
    assert done.returncode == 0 and "vector ok" in done.stdout, done.stdout + done.stderr


@pytest.mark.skipif(not vector.GYMNASIUM, reason="gymnasium is not installed")
def test_gymnasium_accepts_the_vector_env():
    import gymnasium

    env = VectorPlumeEnv(4)
    assert isinstance(env, gymnasium.vector.VectorEnv)
    wrapped = gymnasium.wrappers.vector.RecordEpisodeStatistics(env)
    wrapped.reset(seed=1)
    for _ in range(5):
        wrapped.step(wrapped.action_space.sample())


def test_scenario_keys_work_a_start_in_odor_meets_odor_on_the_running_plume():
    # a new episode is released into the group's plume as it is and senses it at once, so a
    # start drawn in odor (start.condition = "in_odor") is in odor at its first observation
    scenario = Path(pt.__file__).resolve().parents[2] / "scenarios" / "switch-many.toml"
    if not scenario.exists():  # an installed package: the scenario ships with the repository
        pytest.skip("scenarios/ is not at hand")
    env = VectorPlumeEnv(8, str(scenario), group_size=4, observe=("odor", "odometry"),
                         supervisor__timeout=1.0)
    obs, info = env.reset(seed=3)
    starts, trial = [], info["trial"]
    for a in actions(8, 70, seed=9):
        obs, _, _, _, info = env.step(a)
        new = info["trial"] != trial  # the first observation of a new episode
        trial = info["trial"]
        assert (obs[new, 1:5] == 0).all()  # released: its odometry starts there
        starts += list(obs[new, 0])
    assert len(starts) >= 8 and all(v == 1 for v in starts)
    assert info["trial"].min() >= 1
