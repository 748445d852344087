"""The environment: its options, decisions, seeding, rendering, and equality with the runner."""

import math

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from conftest import plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()
from plumetrace.controllers import Command  # noqa: E402
from plumetrace.env import PlumeEnv  # noqa: E402


def test_reset_and_step_follow_gymnasium_conventions():
    env = PlumeEnv()
    obs, info = env.reset(seed=3)
    assert obs.dtype == np.float32 and obs.shape == (8,) and env.observation_space.contains(obs)
    assert obs[0] in (0.0, 1.0) and obs[1:5].tolist() == [0.0, 0.0, 0.0, 0.0]
    assert obs[7] == obs[0]  # one sensing so far
    assert env.action_space.contains(env.action_space.sample())
    obs, reward, terminated, truncated, step_info = env.step(0.0)
    assert type(reward) is float and terminated is False and truncated is False
    # a decision is 8 simulation steps of 0.032 s
    assert env.dt == pytest.approx(8 * 0.032)
    assert step_info["time"] - info["time"] == pytest.approx(env.dt)
    assert obs[4] > 0.0  # it drove


def test_options_of_the_environment_are_not_config_keys():
    # render_mode and the other options used to reach the scenario as unknown config keys
    env = PlumeEnv(render_mode="rgb_array", decision_interval=2, discrete_headings=4,
                   wind_every_step=False, reward_fn=lambda info: 0.0, wind_sensor__sigma_a=0.3)
    obs, _ = env.reset(seed=1)
    assert env.config["wind_sensor"]["sigma_a"] == 0.3 and obs[5] == obs[6] == 0.0
    assert env.render().shape[2] == 3
    # config keys are checked when the environment is made, not at its first reset
    with pytest.raises(pt.ConfigError, match="wind.vxx"):
        PlumeEnv(wind__vxx=1.0)
    with pytest.raises(pt.ConfigError, match="render_modes"):
        PlumeEnv(overrides={"render_modes": 1})
    with pytest.raises(ValueError, match="render_mode"):
        PlumeEnv(render_mode="rgb")
    with pytest.raises(ValueError, match="decision_interval"):
        PlumeEnv(decision_interval=0)
    with pytest.raises(TypeError, match="decision_interval"):
        PlumeEnv(decision_interval=2.5)
    with pytest.raises(ValueError, match="discrete_headings"):
        PlumeEnv(discrete_headings=0)
    with pytest.raises(TypeError, match=r"reset\(seed=...\)"):
        PlumeEnv(seed=1)


def test_driving_upwind_from_the_start_reaches_the_wall_or_source():
    # heading 0 in the odometry frame is the robot's start heading: upwind
    env = PlumeEnv(robot__start_x=4.0)
    env.reset(seed=1)
    decisions, done, total = 0, False, 0.0
    while not done:
        obs, reward, terminated, truncated, info = env.step(np.array([0.0]))
        done = terminated or truncated
        decisions += 1
        total += reward
    assert info["outcome"] in ("success", "wall") and terminated and not truncated
    assert total == float(info["outcome"] == "success")
    # the last decision may end within its 8 steps
    assert 8 * (decisions - 1) < info["result"]["steps"] <= 8 * decisions
    # 3 m upwind at 0.106 m/s and 0.032 s per step: about 885 steps
    assert abs(info["pose"][0] - 1.0) < 0.3 or info["outcome"] == "wall"
    assert info["source_distance"] == pytest.approx(math.hypot(info["pose"][0] - 1.0,
                                                               info["pose"][1]))


def test_the_same_seed_and_trial_replay_exactly_and_trials_count_up():
    env = PlumeEnv()

    def episode(**reset):
        obs, info = env.reset(**reset)
        trace = [obs]
        for k in range(40):
            obs, *_ = env.step(math.sin(k / 3.0))
            trace.append(obs)
        return np.array(trace), info["trial"]
    a, trial_a = episode(seed=5)
    b, trial_b = episode()
    c, trial_c = episode(seed=5)
    d, trial_d = episode(options={"trial": 1})
    assert (trial_a, trial_b, trial_c, trial_d) == (0, 1, 0, 1)
    assert np.array_equal(a, c) and np.array_equal(b, d) and not np.array_equal(a, b)


def test_reset_seeds_np_random_as_gymnasium_and_an_unseeded_reset_draws_a_replayable_seed():
    env = PlumeEnv()
    env.reset(seed=5)
    expected = np.random.Generator(np.random.PCG64(np.random.SeedSequence(5)))
    assert env.np_random.bit_generator.state == expected.bit_generator.state
    env.reset()  # the next trial: np_random is left alone
    assert env.np_random.bit_generator.state == expected.bit_generator.state

    # no seed at all: a fresh one from entropy, in info, that replays the episode
    first, info = PlumeEnv().reset()
    other, other_info = PlumeEnv().reset()
    assert info["seed"] != other_info["seed"] and info["trial"] == 0
    again, _ = PlumeEnv().reset(seed=info["seed"])
    assert np.array_equal(first[:5], again[:5])
    with pytest.raises(ValueError, match="seed"):
        env.reset(seed=-1)
    with pytest.raises(TypeError, match="seed"):
        env.reset(seed=1.5)


def test_a_seeded_random_policy_replays_exactly():
    def episode(space_seed, decisions=150):
        env = PlumeEnv()
        env.action_space.seed(space_seed)
        obs, _ = env.reset(seed=11)
        trace, actions = [obs], []
        for _ in range(decisions):
            action = env.action_space.sample()
            obs, reward, terminated, truncated, info = env.step(action)
            trace.append(obs)
            actions.append(action)
            assert env.observation_space.contains(obs)
            if terminated or truncated:
                break
        return np.array(trace), np.array(actions)
    a, actions_a = episode(7)
    b, actions_b = episode(7)
    c, actions_c = episode(8)
    assert np.array_equal(actions_a, actions_b) and np.array_equal(a, b)
    assert not np.array_equal(actions_a, actions_c) and not np.array_equal(a, c)


@pytest.mark.parametrize("k", [2, 5, 8])
def test_a_decision_of_k_steps_is_k_single_steps_of_the_same_action(k):
    # with a per-step reward: the rewards add up, and the episode's return does not depend on k
    def reward_fn(info):
        return -info["source_distance"] * 0.001 + 10.0 * (info["outcome"] == "success")

    one = PlumeEnv(decision_interval=1, wind_every_step=False, reward_fn=reward_fn,
                   robot__start_x=4.0)
    many = PlumeEnv(decision_interval=k, wind_every_step=False, reward_fn=reward_fn,
                    robot__start_x=4.0)
    obs_1, _ = one.reset(seed=2, options={"trial": 3})
    obs_k, _ = many.reset(seed=2, options={"trial": 3})
    assert np.array_equal(obs_1, obs_k)
    returns, odor_fractions = [0.0, 0.0], set()
    for decision in range(10000):
        action = 0.6 * math.sin(decision / 7.0)  # a wavy path upwind, into the plume
        odors, sum_1 = [], 0.0
        for _ in range(k):
            obs_1, r_1, term_1, trunc_1, info_1 = one.step(action)
            sum_1 += r_1
            odors.append(obs_1[0])
            if term_1 or trunc_1:
                break
        obs_k, r_k, term_k, trunc_k, info_k = many.step(action)
        assert np.array_equal(obs_1[:7], obs_k[:7]), decision
        assert obs_k[7] == np.float32(np.mean(odors)) or term_k
        assert r_k == pytest.approx(sum_1, rel=1e-12, abs=1e-12)
        assert (term_1, trunc_1) == (term_k, trunc_k)
        assert {key: info_1[key] for key in ("time", "outcome", "pose")} == \
            {key: info_k[key] for key in ("time", "outcome", "pose")}
        returns[0] += sum_1
        returns[1] += r_k
        odor_fractions.add(float(obs_k[7]))
        if term_k or trunc_k:
            break
    assert info_1["result"] == info_k["result"]  # every metric of the run
    assert info_k["outcome"] in ("success", "wall") and returns[0] == pytest.approx(returns[1])
    # the path met the plume's edge: decisions with some, but not all, of their steps in odor
    assert any(0.0 < f < 1.0 for f in odor_fractions)


def test_discrete_headings_drive_along_equally_spaced_headings():
    env = PlumeEnv(discrete_headings=4)
    assert env.action_space.n == 4 and env.action_space.shape == ()
    env.reset(seed=1)
    for action, heading in [(1, math.pi / 2), (3, -math.pi / 2), (0, 0.0)]:
        for _ in range(6):  # 1.5 s: time to turn by pi on the spot (2.4 rad/s)
            obs, *_ = env.step(action)
        assert obs[3] == pytest.approx(heading, abs=1e-6)
    for _ in range(6):
        obs, *_ = env.step(np.int64(2))
    assert abs(obs[3]) == pytest.approx(math.pi, abs=1e-6)
    before = obs[4]
    obs, *_ = env.step(Command.stop())  # a Command is still an action
    assert obs[4] == before
    for bad in (1.0, True, "1", [1, 2]):
        with pytest.raises(TypeError, match="action"):
            env.step(bad)
    for bad in (4, -1):
        with pytest.raises(ValueError, match="out of the range 0 to 3"):
            env.step(bad)


def test_observations_reach_their_bounds_only_within_them():
    # a long straight drive in a long arena: the odometer nears its bound (the path length a
    # run can have) and stays inside it, as does every observation of a random walk
    env = PlumeEnv(arena__x_max=100.0, robot__start_x=99.0, supervisor__timeout=60.0,
                   decision_interval=16)
    obs, _ = env.reset(seed=1)
    done = False
    while not done:
        obs, _, terminated, truncated, info = env.step(0.0)
        assert env.observation_space.contains(obs)
        done = terminated or truncated
    assert truncated and obs[4] > 0.99 * env.observation_space.high[4]
    # heading 0 of the odometry frame is the start heading: the drive is along +x there
    assert obs[1] > 0.99 * env.observation_space.high[1]


def test_rgb_array_frames_show_the_robot_where_it_is():
    def frames(action, decisions=30):
        env = PlumeEnv(render_mode="rgb_array")
        env.reset(seed=4)
        first = env.render()
        for _ in range(decisions):
            env.step(action)
        return first, env.render(), env.render()
    first, moved, again = frames(0.0)
    assert moved.shape == (320, 960, 3) and moved.dtype == np.uint8
    assert np.array_equal(moved, again)  # drawing does not change the state
    _, stopped, _ = frames(Command.stop())
    _, stopped_again, _ = frames(Command.stop())
    # the same plume (same seed and trial): only the robot differs between the two runs
    assert np.array_equal(stopped, stopped_again)
    # the arena's rows (below the title, which names the odor state, and above the x labels)
    diff = np.any(moved != stopped, axis=2)[int(0.13 * 320):int(0.83 * 320)]
    assert diff.any()
    # the robot starts at x = 15.5 of 16 m and drove 0.8 m upwind: the change is in the
    # right-hand part of the arena (columns by x)
    columns = np.flatnonzero(diff.any(axis=0))
    assert columns.min() > 0.7 * 960 and columns.max() < 0.99 * 960
    assert not np.array_equal(first, moved)  # and the plume moved on


def test_human_rendering_draws_a_figure_and_returns_none_headless():
    import matplotlib.pyplot as plt

    before = set(plt.get_fignums())
    env = PlumeEnv(render_mode="human")
    env.reset(seed=1)  # renders, as Gymnasium's human mode does at reset and step
    figures = set(plt.get_fignums()) - before
    assert len(figures) == 1
    fig = plt.figure(figures.pop())
    robot_path = fig.axes[0].get_lines()[0]
    env.step(0.0)
    assert env.render() is None
    assert len(robot_path.get_xdata()) == 1 + 8  # the release point and 8 steps
    assert len(fig.axes[0].collections[0].get_offsets()) == 1600  # the filaments
    env.close()
    env.close()  # closing twice is allowed
    assert set(plt.get_fignums()) == before


def test_render_without_a_mode_warns_and_returns_none():
    env = PlumeEnv()
    env.reset(seed=1)
    with pytest.warns(UserWarning, match="render_mode"):
        assert env.render() is None


def test_surge_cast_driving_the_environment_gets_the_built_in_run():
    # the environment is the runner's loop split in two: an agent that decides like the
    # built-in surge-cast (examples/python_surge_cast.py, fed from the observation array and
    # sampling the wind on demand) reproduces the built-in run exactly, one decision per step
    import importlib.util
    from pathlib import Path
    from types import SimpleNamespace

    root = Path(__file__).resolve().parents[2]
    spec = importlib.util.spec_from_file_location("sc", root / "examples" / "python_surge_cast.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)

    for trial in range(3):
        env = PlumeEnv(decision_interval=1, wind_every_step=False, wind_sensor__sigma_a=0.3)
        obs, info = env.reset(seed=4, options={"trial": trial})
        from plumetrace.controllers import controller_rng
        agent = example.SurgeCast(pt.Scenario()["py_surge_cast"], controller_rng(4, trial))
        wind = SimpleNamespace(measure_wind_body=env.measure_wind)
        while True:
            # the odometry at full precision (the observation rounds it to float32)
            x, y, heading = info["odometry"]
            seen = SimpleNamespace(odor=bool(obs[0]), odometer=info["odometer"], time=0.0,
                                   odometry=SimpleNamespace(x=x, y=y, heading=heading))
            obs, _, terminated, truncated, info = env.step(agent.step(seen, wind))
            if terminated or truncated:
                break
        builtin = pt.run(algorithm="surge-cast", seed=4, trial=trial, wind_sensor__sigma_a=0.3,
                         trace=False)
        for key in ("outcome", "time_s", "d_t", "d_u", "steps", "wind_samples", "odor_fraction"):
            assert info["result"][key] == builtin[key], (trial, key)


# -- G16: an action of no heading's type is refused, naming it, before the world moves ---------

_NO_HEADING = [
    (True, TypeError, "a bool is no heading"), (np.bool_(False), TypeError, "a bool is no"),
    (None, TypeError, "None is no action"), ("0.5", TypeError, "text is no action"),
    (b"1", TypeError, "text is no action"), (1 + 2j, TypeError, "complex is no real number"),
    (np.complex64(1), TypeError, "no real number"), ([1.0, 2.0], TypeError, "2 values"),
    (np.zeros((2, 1)), TypeError, "2 values"), ([], TypeError, "0 values"),
    (np.array([True]), TypeError, "array of bool values"), ([None], TypeError, "object values"),
    (["a"], TypeError, "<U1 values"), ([[1], [2, 3]], TypeError, "not an array of numbers"),
    (math.nan, ValueError, "finite"), (-math.inf, ValueError, "finite"),
    (np.float32("nan"), ValueError, "finite"), (10**400, ValueError, "finite"),
    (object(), TypeError, "object values"),
]


@pytest.mark.parametrize("action, error, says", _NO_HEADING,
                         ids=[f"{type(a).__name__}-{i}" for i, (a, _, _) in enumerate(_NO_HEADING)])
def test_actions_that_are_no_heading_are_refused_naming_their_type(action, error, says):
    env = PlumeEnv(sim__warmup=0.0, supervisor__timeout=2.0)
    env.reset(seed=1)
    before = env._world.time()
    with pytest.raises(error) as caught:
        env.step(action)
    assert type(caught.value) is error
    assert str(caught.value).startswith("action ") and says in str(caught.value)
    assert env._world.time() == before  # refused before the world moved
    env.step(0.25)  # and the episode goes on


@pytest.mark.parametrize("action, error, says", [
    (True, TypeError, "a bool is no index"), (np.bool_(True), TypeError, "a bool is no index"),
    (None, TypeError, "None is no action"), (2.0, TypeError, "a float is no index"),
    (np.float64(1), TypeError, "no index"), (1 + 0j, TypeError, "no real number"),
    (4, ValueError, "out of the range 0 to 3"), (-1, ValueError, "out of the range"),
    (2**70, ValueError, "out of the range"), (np.uint64(2**63), ValueError, "out of the range"),
    (np.array([1, 2]), TypeError, "2 values"), ("2", TypeError, "text is no action"),
])
def test_discrete_actions_other_than_an_index_in_range_are_refused(action, error, says):
    env = PlumeEnv(sim__warmup=0.0, supervisor__timeout=2.0, discrete_headings=4)
    env.reset(seed=1)
    with pytest.raises(error) as caught:
        env.step(action)
    assert type(caught.value) is error and says in str(caught.value)
    for good in (0, np.int64(3), np.uint8(1), np.array([2]), np.array(1)):
        env.step(good)


def test_meander_keys_beyond_the_stability_bound_raise_naming_them():
    # issue 22, G1: each key inside its range, together they made the wind, and so the
    # observations, NaN; the environment refuses them as the command does
    with pytest.raises(pt.ConfigError, match="meander.gain.*unstable"):
        PlumeEnv(wind__model="meander", meander__gain=10, meander__bandwidth=100,
                 meander__damping=10)


def test_the_meander_keys_old_names_still_work_and_warn_naming_the_new_ones(capfd):
    # until the next version: wind.meander_gain is meander.gain, said on stderr (issue 24)
    s = pt.Scenario(wind__model="meander", wind__meander_gain=0.05, wind__meander_nx=9)
    assert (s["meander.gain"], s["meander.nx"]) == (0.05, 9)
    assert "meander_gain" not in s.to_toml()
    err = capfd.readouterr().err
    assert "wind.meander_gain is deprecated: write meander.gain" in err
    assert "wind.meander_nx is deprecated: write meander.nx" in err
    # an old name reads too, with the same words as a DeprecationWarning
    with pytest.warns(DeprecationWarning, match="wind.meander_gain is deprecated: write meander.gain"):
        assert s["wind.meander_gain"] == 0.05


# -- issue 24: what the environment observes, where it starts, declaring -----------------------

def _episode(env, seed, actions):
    """The observations (and the last info) of an episode under a list of actions."""
    obs, info = env.reset(seed=seed)
    seen = [obs]
    for action in actions:
        obs, _, terminated, truncated, info = env.step(action)
        seen.append(obs)
        if terminated or truncated:
            break
    return np.array(seen), info


def test_a_concentration_observation_is_the_reading_the_binary_one_thresholds():
    binary = PlumeEnv(decision_interval=1, wind_every_step=False)
    env = PlumeEnv(decision_interval=1, wind_every_step=False, observation="concentration")
    space = env.observation_space
    assert env.observation == "concentration" and binary.observation == "binary"
    assert space.low[0] == 0.0 and space.high[0] == np.inf and binary.observation_space.high[0] == 1
    assert np.array_equal(space.low[1:], binary.observation_space.low[1:])
    assert np.array_equal(space.high[1:], binary.observation_space.high[1:])
    # the same actions take the same path; only value 0 differs: the reading, not its test
    actions = [0.0] * 300 + [1.5] * 100 + [-1.0] * 200
    c, _ = _episode(env, 4, actions)
    b, _ = _episode(binary, 4, actions)
    assert c.shape == b.shape and np.array_equal(c[:, 1:], b[:, 1:])
    assert all(o in space for o in c) and np.all(np.isfinite(c))
    threshold = env.config["odor"]["threshold"]
    clear = np.abs(c[:, 0] - threshold) > 1e-4 * threshold  # float32 rounding at the threshold
    assert clear.sum() > 0.99 * len(c) and set(b[:, 0]) == {0.0, 1.0}
    assert np.array_equal(b[clear, 0] == 1.0, c[clear, 0] >= threshold)


def test_a_first_order_sensor_observed_through_the_environment_lags_the_ideal_one():
    actions = [0.0] * 400
    ideal, _ = _episode(PlumeEnv(decision_interval=1, observation="concentration"), 4, actions)
    env = PlumeEnv(decision_interval=1, observation="concentration", odor__model="first-order",
                   first_order__noise=20.0)
    lagged, _ = _episode(env, 4, actions)
    assert np.all(np.isfinite(lagged)) and all(o in env.observation_space for o in lagged)
    assert np.array_equal(lagged[:, 1:5], ideal[:, 1:5])  # the same path
    # a first-order response smooths the filaments' spikes: a smaller spread of the reading
    assert np.std(np.diff(lagged[:, 0])) < 0.5 * np.std(np.diff(ideal[:, 0]))
    # the binary odor is its threshold test: value 7 of a one-step decision is that 0 or 1
    threshold = env.config["odor"]["threshold"]
    clear = np.abs(lagged[1:, 0] - threshold) > 1e-4 * threshold
    assert np.array_equal((lagged[1:, 7] == 1.0)[clear], (lagged[1:, 0] >= threshold)[clear])


def test_an_episode_starts_where_the_run_of_its_seed_and_trial_is_released():
    env = PlumeEnv(start__region="rectangle", start__heading="random")
    starts = set()
    for trial in range(3):
        _, info = env.reset(seed=6, options={"trial": trial})
        run = pt.run(seed=6, trial=trial, start__region="rectangle", start__heading="random",
                     supervisor__timeout=0.1)
        t = run["trajectory"]
        assert info["pose"] == (t["x"][0], t["y"][0], t["heading"][0])
        x, y, _ = info["pose"]
        assert 11.0 <= x <= 15.5 and -1.5 <= y <= 1.5  # 10 to 14.5 m downwind of the source
        starts.add(info["pose"])
    assert len(starts) == 3


def test_the_environment_declares_the_source_with_a_command():
    for offset, outcome in ((0.2, "success"), (1.0, "wrong_declaration")):
        env = PlumeEnv(supervisor__success="declare")
        env.reset(seed=1)
        # the source is 14.5 m straight ahead of the release pose (odometry frame)
        obs, reward, terminated, truncated, info = env.step(Command.declare_source(14.5 + offset,
                                                                                   0.0))
        assert terminated and not truncated and info["outcome"] == outcome
        assert reward == (1.0 if outcome == "success" else 0.0)
        assert info["result"]["declaration_error"] == pytest.approx(offset)


def test_observation_options_and_teams_the_environment_cannot_drive_are_refused():
    for bad in ("concentraton", "Binary", 1, None):
        with pytest.raises(ValueError, match=f"observation must be one of .*{bad!r}"):
            PlumeEnv(observation=bad)
    with pytest.raises(ValueError, match="team.count = 2: PlumeEnv drives one robot"):
        PlumeEnv(team__count=2)
