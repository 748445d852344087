"""TeamPlumeEnv (plumetrace.team_env): PettingZoo's ParallelEnv API for a team on one plume,
checked without PettingZoo: dict keys, spaces, dtypes, agents that leave, termination and
truncation, exact replays, the built-in run reproduced, and refused input naming the agent."""

import math

import numpy as np
import pytest

from conftest import plumetrace_with_core

pt = plumetrace_with_core()
from plumetrace.team_env import TeamPlumeEnv  # noqa: E402

TEAM = {"team__count": 3, "supervisor__timeout": 30.0}


def away_from_the_middle(infos, diagonal):
    """Robot 0 drives upwind; robots 1 and 2 drive to the wall on their own side, straight
    across (robot 1) or at 45 degrees (robot 2, later). heading action a: odometry heading pi a
    from the start heading (pi, upwind); +y in the arena is odometry heading -pi / 2."""
    actions = {"robot_0": np.array([0.0], np.float32)}
    for agent, a in (("robot_1", 0.5), ("robot_2", 0.25 if diagonal else 0.5)):
        side = math.copysign(1.0, infos[agent]["pose"][1])
        actions[agent] = np.array([-a * side], np.float32)
    return actions


def test_a_team_episode_follows_the_parallel_api_and_agents_leave_as_they_end():
    env = TeamPlumeEnv(decision_interval=8, **TEAM)
    assert env.possible_agents == ["robot_0", "robot_1", "robot_2"]
    assert env.max_num_agents == 3 and env.num_agents == 0 and env.agents == []
    assert env.metadata["name"] and env.metadata["is_parallelizable"] is True
    for a in env.possible_agents:
        assert env.observation_space(a) is env.observation_space(a)
        assert env.action_space(a) is env.action_space(a)
        assert env.observation_space(a).shape == (7,)  # odor, wind (2), odometry (4)
    obs, infos = env.reset(seed=3)
    assert set(obs) == set(infos) == set(env.agents) == set(env.possible_agents)
    plan = away_from_the_middle(infos, diagonal=True)
    ended = {}  # agent -> step at which it left
    steps = 0
    while env.agents:
        live = list(env.agents)
        obs, rewards, terms, truncs, infos = env.step({a: plan[a] for a in live})
        steps += 1
        for d in (obs, rewards, terms, truncs, infos):
            assert list(d) == live
        for a in live:
            assert obs[a].dtype == np.float32 and obs[a] in env.observation_space(a), (a, obs[a])
            assert type(rewards[a]) is float and rewards[a] == 0.0
            assert type(terms[a]) is bool and type(truncs[a]) is bool
            done = terms[a] or truncs[a]
            assert ("result" in infos[a]) == done
            if done:
                ended[a] = steps
                assert infos[a]["result"]["outcome"] == infos[a]["outcome"]
        assert env.agents == [a for a in live if not (terms[a] or truncs[a])]
        assert env.num_agents == len(env.agents)
    # the robots driven across reached their walls (terminated), the straight one first; robot 0
    # drove upwind until supervisor.timeout (truncated)
    assert ended["robot_1"] < ended["robot_2"] < ended["robot_0"], ended
    assert infos["robot_0"]["outcome"] == "timeout" and truncs["robot_0"] and not terms["robot_0"]
    assert env.result("robot_1")["outcome"] == "wall"
    assert env.result("robot_2")["outcome"] == "wall"
    assert env.result("robot_0")["time_s"] == pytest.approx(30.0, abs=0.04)
    with pytest.raises(RuntimeError, match="reset"):
        env.step({})
    state = env.state()
    assert state.dtype == np.float32 and state.shape == (9,) and state in env.state_space
    assert env.render() is None
    env.close()
    env.close()  # twice is fine
    with pytest.raises(RuntimeError, match="closed"):
        env.reset()


def episode(env, seed=None, options=None, sample_seed=0):
    """Every observation and reward of an episode of sampled actions, as one array."""
    obs, _ = env.reset(seed=seed, options=options)
    for k, a in enumerate(env.possible_agents):
        env.action_space(a).seed(sample_seed + k)
    rows = [np.concatenate([obs[a] for a in env.agents])]
    while env.agents:
        obs, rewards, _, _, _ = env.step({a: env.action_space(a).sample() for a in env.agents})
        rows.append(np.concatenate([np.append(obs[a], rewards[a]) for a in obs]))
    return rows


def test_a_seed_replays_every_value_and_a_reset_without_one_plays_the_next_trial():
    def make():
        return TeamPlumeEnv(decision_interval=16, observation="concentration",
                            observe=("odor", "odor_fraction", "wind", "odometry", "time"),
                            stack=2, reward="shaped", team__count=2, supervisor__timeout=12.0,
                            wind__model="meander")
    env, again = make(), make()
    first = episode(env, seed=11)
    assert env.trial == 0
    second = episode(env)  # the next trial
    assert env.trial == 1 and env.episode_seed == 11
    replay = episode(again, seed=11)
    assert len(first) == len(replay) > 20
    for a, b in zip(first, replay):
        assert a.tobytes() == b.tobytes()  # bit for bit
    assert any(a.shape != b.shape or a.tobytes() != b.tobytes() for a, b in zip(first, second))
    picked = episode(again, options={"trial": 1})
    assert all(a.tobytes() == b.tobytes() for a, b in zip(second, picked))
    assert again.observation_names[:2] == ("odor[0]", "odor_fraction[0]")
    assert len(again.observation_names) == again.observation_space("robot_0").shape[0] == 18


def test_actions_that_give_a_controllers_commands_reproduce_the_built_in_run():
    # a Python controller turning odor into a heading, and the same rule as actions. Robot 0's
    # run (the one pt.run returns) meets its teammates: without contacts it would differ, so its
    # equality checks the team's step, contacts included
    def rule(k, odor):
        return 0.0 if odor else (0.5 if k % 2 else -0.5)

    class Rule:
        def __init__(self, k):
            self.k = k

        def step(self, obs, wind):
            return pt.controllers.Command.go(math.pi * rule(self.k, obs.odor))

    def built_in(**more):
        made = []

        def factory(scenario, rng):
            made.append(Rule(len(made)))
            return made[-1]

        out = pt.run(controller=factory, seed=5, trial=2, trace=False, **keys, **more)
        assert len(made) == 3
        return out

    keys = {"team__count": 3, "supervisor__timeout": 40.0, "wind__model": "meander",
            "supervisor__walls": "block"}
    env = TeamPlumeEnv(observe=("odor",), **keys)
    obs, _ = env.reset(seed=5, options={"trial": 2})
    while env.agents:
        obs, *_ = env.step({a: rule(int(a[-1]), obs[a][0] == 1.0) for a in env.agents})
    mine, theirs = env.result("robot_0"), built_in()
    shared = sorted(set(mine) & set(theirs) - {"algorithm"})
    assert {"outcome", "time_s", "d_t", "d_u", "steps", "odor_fraction"} <= set(shared)
    assert {k: mine[k] for k in shared} == {k: theirs[k] for k in shared}
    assert theirs["steps"] == 1250 and theirs["odor_fraction"] > 0.0
    assert built_in(team__contact="off")["d_t"] != mine["d_t"]


def test_a_shaped_reward_sums_to_the_share_of_the_distance_closed_and_reward_fn_replaces_it():
    seen = []

    def doubled(infos):
        seen.append(sorted(infos))
        return {a: 2.0 * info["reward"] + 1.0 for a, info in infos.items()}

    for reward_fn in (None, doubled):
        env = TeamPlumeEnv(decision_interval=8, reward="shaped", reward_fn=reward_fn,
                           action="discrete", discrete_headings=4, team__count=2,
                           supervisor__timeout=20.0)
        _, infos = env.reset(seed=2)
        start = {a: infos[a]["source_distance"] for a in env.agents}
        total = dict.fromkeys(env.agents, 0.0)
        steps = 0
        while env.agents:
            _, rewards, _, _, infos = env.step({a: 0 for a in env.agents})  # upwind
            steps += 1
            for a, r in rewards.items():
                total[a] += r
        for a, d0 in start.items():
            closed = (d0 - infos[a]["source_distance"]) / d0
            expected = closed if reward_fn is None else 2.0 * closed + steps
            assert closed > 0.1
            assert total[a] == pytest.approx(expected, abs=1e-9)
    assert seen[0] == ["robot_0", "robot_1"]


def test_bad_input_is_refused_naming_the_agent_and_the_argument():
    env = TeamPlumeEnv(decision_interval=8, **TEAM)
    with pytest.raises(RuntimeError, match="reset"):
        env.step({})
    _, infos = env.reset(seed=3)
    ok = {a: 0.0 for a in env.agents}

    def refused(kind, match, **change):
        with pytest.raises(kind, match=match):
            env.step({**ok, **change})

    refused(ValueError, "robot_7.*not an agent", robot_7=0.0)
    refused(ValueError, r"robot_1.*nan.*finite", robot_1=float("nan"))
    refused(ValueError, r"robot_2.*inf.*finite", robot_2=np.array([np.inf]))
    refused(ValueError, r"robot_0.*shape \(2,\)", robot_0=np.zeros(2))
    refused(TypeError, "robot_0.*bool", robot_0=True)
    refused(TypeError, "robot_1.*bool", robot_1=np.array([True]))
    refused(TypeError, "robot_2.*<U", robot_2=np.array(["0.5"]))
    refused(TypeError, "robot_2.*not a number", robot_2=None)
    refused(TypeError, "robot_2.*complex", robot_2=1j)
    with pytest.raises(ValueError, match=r"no action for \[robot_1\]"):
        env.step({"robot_0": 0.0, "robot_2": 0.0})
    with pytest.raises(TypeError, match="dict keyed by agent"):
        env.step([0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="robot_9.*not an agent"):
        env.observation_space("robot_9")
    with pytest.raises(ValueError, match="not an agent"):
        env.action_space(0)
    # nothing moved: the refused steps left the episode where it was (the first sensing, at
    # reset, is step 1; one decision is 8 more)
    assert env.step(ok)[4]["robot_0"]["time"] == pytest.approx(9 * 0.032)
    # a robot whose run has ended may not act
    plan = away_from_the_middle(infos, diagonal=False)
    while len(env.agents) == 3:
        env.step({a: plan[a] for a in env.agents})
    gone = [a for a in env.possible_agents if a not in env.agents][0]
    with pytest.raises(ValueError, match=f"{gone}'s run has ended"):
        env.step({a: 0.0 for a in env.possible_agents})
    discrete = TeamPlumeEnv(action="discrete", discrete_headings=4, team__count=2)
    discrete.reset(seed=1)
    for bad, kind in ((4, ValueError), (-1, ValueError), (1.0, TypeError), (np.int8(1), None)):
        if kind is None:
            discrete.step({"robot_0": bad, "robot_1": bad})  # any integer type
            continue
        with pytest.raises(kind, match="robot_1"):
            discrete.step({"robot_0": 0, "robot_1": bad})
    for options, kind, match in (
            ({"stack": 0}, ValueError, "stack"), ({"observe": ("smell",)}, ValueError, "smell"),
            ({"action": "discrete"}, ValueError, "discrete_headings"),
            ({"decision_interval": True}, TypeError, "decision_interval"),
            ({"reward_fn": 3}, TypeError, "reward_fn"), ({"seed": 1}, TypeError, "seed"),
            ({"team__count": 0}, Exception, "team.count")):
        with pytest.raises(kind, match=match):
            TeamPlumeEnv(**options)
    bad_fn = TeamPlumeEnv(team__count=2, reward_fn=lambda infos: {"robot_0": 1.0})
    bad_fn.reset(seed=1)
    with pytest.raises(ValueError, match="reward_fn.*robot_1"):
        bad_fn.step({"robot_0": 0.0, "robot_1": 0.0})


def test_a_team_of_one_and_a_mixed_team_have_each_robot_its_own_bounds():
    one = TeamPlumeEnv()
    assert one.possible_agents == ["robot_0"]
    obs, _ = one.reset(seed=1)
    assert obs["robot_0"] in one.observation_space("robot_0")
    # robot 1 drives twice as fast: its odometry may reach twice as far
    mixed = TeamPlumeEnv(team__count=2, overrides={"member.1.robot.wheel_speed": 0.212})
    high0 = mixed.observation_space("robot_0").high
    high1 = mixed.observation_space("robot_1").high
    assert high1[3] == pytest.approx(2.0 * high0[3], rel=1e-6)
