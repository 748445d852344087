"""Trains a learned plume-tracking policy with an evolution strategy on the vector environment
(docs/vector.md, "A learned baseline").

    python3 -m plumetrace.learn.es --out out/learned          # the shipped policy's training
    python3 -m plumetrace.learn.es --help

or from Python::

    from plumetrace.learn import es
    policy, curve = es.train(es.suite_tasks(["laminar"]), generations=50)

The strategy is OpenAI's (Salimans et al. 2017, "Evolution strategies as a scalable alternative
to reinforcement learning"): each generation perturbs the weights theta by `pairs` antithetic
Gaussian draws (theta +- sigma eps), scores every member by its return, turns the scores into
centred ranks, estimates the gradient as sum((rank+ - rank-) eps) / (2 pairs sigma), subtracts
weight decay and takes an Adam step. The whole population runs in one VectorPlumeEnv per task:
environment j of a group runs member j (the last member is theta itself, for the curve), and
every member of a group meets the same plume, start and sensor noise (the same seed), so members
differ only by their weights. NumPy only: no other package, and the same seed trains the same
weights whatever the thread count.
"""

import csv
import math
import os
import time
from collections import namedtuple
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from .policy import OBSERVE, Memory, Policy, forward, features

__all__ = ["CURVE_COLUMNS", "TRAIN_TASKS", "Task", "evaluate", "main", "plot_curve", "read_curve",
           "suite_tasks", "train"]

Task = namedtuple("Task", "name scenario overrides")
Task.__doc__ = """A training task: `name`, `scenario` (a scenario file) and `overrides` (a dict
of dotted keys on top of it)."""

TRAIN_TASKS = ("laminar", "meander-weak", "meander-strong", "find")
"""The benchmark suite's tasks the shipped policy was trained on (its single-robot tasks that
need neither a declaration nor a slow sensor)."""

CURVE_COLUMNS = ("generation", "return", "success", "population_return", "population_success",
                 "wall_s")
"""The learning curve's columns: the generation; theta's mean return over the generation's
episodes and the share of them it finished at the source; the same over the whole population;
the wall time since training began (s)."""


def suite_tasks(names=TRAIN_TASKS, suite=None):
    """The tasks `names` of a benchmark suite file (default: the built-in suite) as Tasks, with
    each task's scenario and its [task.set] keys; ValueError naming an unknown one."""
    from .._files import read_toml
    from ..benchmark.run import default_suite

    path = Path(default_suite() if suite is None else suite)
    doc = read_toml(path, "suite file")
    found = {t.get("name"): t for t in doc.get("task", [])}
    if isinstance(names, str):
        names = [names]
    tasks = []
    for name in names:
        if name not in found:
            raise ValueError(f"tasks: '{name}' is not a task of {path.name} (its tasks: "
                             f"{', '.join(str(n) for n in found)})")
        t = found[name]
        tasks.append(Task(name, str(path.parent / t["scenario"]), _dotted(t.get("set", {}))))
    return tasks


def _dotted(table, prefix=""):
    out = {}
    for key, value in table.items():
        if isinstance(value, dict):
            out.update(_dotted(value, f"{prefix}{key}."))
        else:
            out[f"{prefix}{key}"] = value
    return out


def _tasks(tasks):
    if isinstance(tasks, (str, Task)):
        tasks = [tasks]
    try:
        tasks = list(tasks)
    except TypeError:
        raise TypeError(f"tasks must be a list of task names or Tasks, got {tasks!r}") from None
    if not tasks:
        raise ValueError("tasks: at least one task")
    out = []
    for t in tasks:
        if isinstance(t, str):
            out.extend(suite_tasks([t]))
        elif isinstance(t, Task):
            out.append(t)
        else:
            raise TypeError(f"tasks: {t!r} is neither a task name nor a Task")
    return out


def _scenario(task, window):
    from ..api import Scenario

    scenario = Scenario(task.scenario)
    scenario.update({**task.overrides, "supervisor.timeout": window})
    return scenario


def _vector_env(scenario, policy, num_envs, group_size, threads):
    from ..vector import VectorPlumeEnv

    return VectorPlumeEnv(num_envs, scenario, group_size=group_size,
                          decision_interval=policy.decision_interval, observe=OBSERVE,
                          action=policy.action, reward="shaped", threads=threads)


def _decisions(scenario, policy, window):
    # enough decisions for every first episode to end (at the source or at the timeout `window`)
    return int(math.ceil(window / (scenario["sim.dt"] * policy.decision_interval))) + 2


def _rollout(env, policy, thetas, seeds, decisions):
    """Runs `env` (num_envs environments, environment i with weights thetas[i]) from seeds
    `seeds` for `decisions` decisions; returns each environment's summed reward and whether its
    first episode reached the source."""
    from ..vector import OUTCOMES

    success_code = OUTCOMES.index("success")
    obs, _ = env.reset(seed=[int(s) for s in seeds])
    n = env.num_envs
    memory = Memory(n)
    total = np.zeros(n)
    first = np.full(n, -1, dtype=np.int64)
    ended = np.zeros(n, dtype=bool)
    for _ in range(decisions):
        a = forward(thetas, features(policy, memory, obs), policy.hidden)
        # an environment that ended at the last step starts its next episode at this one
        memory.restart(ended)
        obs, reward, terminated, truncated, info = env.step(a)
        total += reward
        ended = terminated | truncated
        now = ended & (first < 0)
        first[now] = info["outcome"][now]
    return total, first == success_code


def evaluate(policy, tasks=TRAIN_TASKS, *, seed=0, episodes=8, window=300.0, threads=2):
    """`policy`'s mean return and success rate on `tasks` (names of the built-in suite's tasks,
    or Tasks): `episodes` environments per task (environment i with seed `seed` + i, each on its
    own plume) run for the decisions a first episode of at most `window` s needs (the timeout
    is `window`); the return sums the shaped reward of every episode begun in that time, the
    success rate counts first episodes. Returns {"return": ..., "success": ..., "tasks": {name:
    (return, success)}}."""
    from ..api import _finite_number, _whole

    if not isinstance(policy, Policy):
        raise TypeError(f"policy must be a plumetrace.learn.Policy, got {type(policy).__name__}")
    tasks = _tasks(tasks)
    seed = _whole("seed", seed, 0, 2**62)
    episodes = _whole("episodes", episodes, 1, 4096)
    window = _finite_number("window", window, 0.0, strict=True)
    threads = _whole("threads", threads, 0, 1024)
    per_task = {}
    for task in tasks:
        scenario = _scenario(task, window)
        env = _vector_env(scenario, policy, episodes, 1, threads)
        thetas = np.broadcast_to(policy.theta, (episodes, policy.theta.size))
        total, success = _rollout(env, policy, thetas, seed + np.arange(episodes),
                                  _decisions(scenario, policy, window))
        env.close()
        per_task[task.name] = (float(total.mean()), float(success.mean()))
    return {"return": float(np.mean([r for r, _ in per_task.values()])),
            "success": float(np.mean([s for _, s in per_task.values()])), "tasks": per_task}


def _centred_ranks(x):
    ranks = np.empty(len(x))
    ranks[np.argsort(x, kind="stable")] = np.arange(len(x))
    return ranks / (len(x) - 1) - 0.5


def train(tasks=TRAIN_TASKS, *, generations=150, pairs=8, groups=1, window=300.0, sigma=0.05,
          learning_rate=0.05, weight_decay=0.005, policy=None, seed=1, threads=2, log=None,
          progress=None):
    """Trains a policy with the evolution strategy (module docstring) and returns (policy,
    curve): the policy at the last generation's theta, and the learning curve (a list of dicts
    with CURVE_COLUMNS, one per generation).

    `tasks`: names of the built-in suite's tasks (suite_tasks) or Tasks. Every generation runs
    every member on `groups` new plumes of each task (drawn from `seed`) for the decisions a
    first episode of at most `window` s needs (the timeout is `window` s); a member's fitness is
    the shaped reward summed over that time, averaged over tasks and plumes, so a member that
    arrives sooner starts again and earns more. `pairs`: antithetic pairs (the population is
    2 pairs + 1: theta); `sigma`: the perturbations' standard deviation; `learning_rate`:
    Adam's step at the first generation (it falls linearly to a fifth of it at the last);
    `weight_decay`: the L2 coefficient pulling theta to 0; `policy`: where to start (its
    decision interval, action mode and sizes are kept; default a Policy() with random weights
    from `seed`); `threads`: threads for the tasks side by side and the vector environments'
    C++ threads (never change a result); `log`: a CSV file (in a folder that exists) the curve
    is written to after each generation; `progress`: f(row) called after each
    generation. Raises TypeError or ValueError naming the argument."""
    from .._files import write_whole
    from ..api import _finite_number, _whole

    tasks = _tasks(tasks)
    generations = _whole("generations", generations, 1, 10**7)
    pairs = _whole("pairs", pairs, 1, 4096)
    groups = _whole("groups", groups, 1, 4096)
    window = _finite_number("window", window, 0.0, strict=True)
    sigma = _finite_number("sigma", sigma, 0.0, strict=True)
    learning_rate = _finite_number("learning_rate", learning_rate, 0.0, strict=True)
    weight_decay = _finite_number("weight_decay", weight_decay, 0.0)
    seed = _whole("seed", seed, 0, 2**62)
    threads = _whole("threads", threads, 0, 1024)
    if policy is not None and not isinstance(policy, Policy):
        raise TypeError(f"policy must be a plumetrace.learn.Policy or None, got "
                        f"{type(policy).__name__}")
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be callable, got {type(progress).__name__}")
    rng = np.random.default_rng(seed)
    if policy is None:
        policy = Policy()
        policy = policy.with_theta(policy.initial(rng))
    members = 2 * pairs + 1
    scenarios = [_scenario(t, window) for t in tasks]
    # why: the tasks' environments step side by side in Python threads (a step releases the
    # GIL), each with its share of the C++ threads, so a group per task still uses every core
    workers = max(1, min(threads or (os.cpu_count() or 1), len(tasks)))
    inner = max(1, (threads or (os.cpu_count() or 1)) // workers)
    envs = [_vector_env(s, policy, groups * members, members, inner) for s in scenarios]
    pool = ThreadPoolExecutor(workers) if workers > 1 else None
    decisions = [_decisions(s, policy, window) for s in scenarios]
    theta = policy.theta.copy()
    adam_m, adam_v = np.zeros_like(theta), np.zeros_like(theta)
    beta1, beta2 = 0.9, 0.999
    curve = []
    start = time.perf_counter()
    try:
        for generation in range(generations):
            eps = rng.standard_normal((pairs, theta.size))
            population = np.vstack([theta + sigma * eps, theta - sigma * eps, theta])
            thetas = np.tile(population, (groups, 1))
            returns = np.zeros(members)
            successes = np.zeros(members)
            # every member of a group: the same seed (plume, start, noise)
            jobs = [(env, policy, thetas, np.repeat(rng.integers(0, 2**62, groups), members), n)
                    for env, n in zip(envs, decisions)]
            done = (pool.map(_rollout, *zip(*jobs)) if pool is not None else
                    [_rollout(*job) for job in jobs])
            for total, success in done:
                returns += total.reshape(groups, members).mean(axis=0)
                successes += success.reshape(groups, members).mean(axis=0)
            returns /= len(envs)
            successes /= len(envs)
            ranks = _centred_ranks(returns[:-1])
            grad = (ranks[:pairs] - ranks[pairs:2 * pairs]) @ eps / (2 * pairs * sigma)
            grad -= weight_decay * theta
            # Adam, ascending
            t = generation + 1
            adam_m = beta1 * adam_m + (1 - beta1) * grad
            adam_v = beta2 * adam_v + (1 - beta2) * grad * grad
            # why: the step falls linearly to a fifth by the last generation, so that the last
            # theta, the one returned, is not one noisy step away from a good one
            rate = learning_rate * (1.0 - 0.8 * generation / max(1, generations - 1))
            step = rate * math.sqrt(1 - beta2**t) / (1 - beta1**t)
            theta = theta + step * adam_m / (np.sqrt(adam_v) + 1e-8)
            row = {"generation": generation, "return": float(returns[-1]),
                   "success": float(successes[-1]),
                   "population_return": float(returns[:-1].mean()),
                   "population_success": float(successes[:-1].mean()),
                   "wall_s": time.perf_counter() - start}
            curve.append(row)
            if log is not None:
                write_whole(log, _curve_csv(curve))
            if progress is not None:
                progress(row)
    finally:
        if pool is not None:
            pool.shutdown()
        for env in envs:
            env.close()
    info = {"trainer": "plumetrace.learn.es", "tasks": [t.name for t in tasks],
            "generations": generations, "pairs": pairs, "groups": groups, "window": window,
            "sigma": sigma, "learning_rate": learning_rate, "weight_decay": weight_decay,
            "seed": seed, "wall_s": round(curve[-1]["wall_s"], 1)}
    return policy.with_theta(theta, info), curve


def _curve_csv(curve):
    lines = [",".join(CURVE_COLUMNS)]
    for row in curve:
        lines.append(",".join(f"{row[k]:.6g}" if isinstance(row[k], float) else str(row[k])
                              for k in CURVE_COLUMNS))
    return "\n".join(lines) + "\n"


def read_curve(path):
    """A learning curve's CSV (as train() writes it) as a list of dicts of floats."""
    from .._files import read_input

    text = read_input(path, "learning curve").decode("utf-8")
    return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(text.splitlines())]


def plot_curve(curve, path, title=None, smooth=10):
    """Draws the learning curve (a list of CURVE_COLUMNS dicts, or a CSV of them) to `path` (PNG):
    theta's return and success rate per generation, with a moving average of `smooth`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if isinstance(curve, (str, os.PathLike)):
        curve = read_curve(curve)
    g = np.array([r["generation"] for r in curve])
    wall = np.array([r["wall_s"] for r in curve]) / 60.0

    def mean(values):
        k = max(1, min(smooth, len(values)))
        return np.convolve(values, np.ones(k) / k, mode="valid"), g[k - 1:]

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for ax, key, label in ((axes[0], "return", "return in the window (shaped reward)"),
                           (axes[1], "success", "success rate (first episode in the window)")):
        for column, colour, name in ((key, "C0", "theta"), (f"population_{key}", "C1",
                                                            "population mean")):
            values = np.array([r[column] for r in curve])
            ax.plot(g, values, color=colour, alpha=0.25, lw=0.8)
            m, x = mean(values)
            ax.plot(x, m, color=colour, lw=2, label=f"{name} ({smooth}-generation mean)")
        ax.set_xlabel("generation")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[1].set_ylim(-0.02, 1.02)
    axes[0].legend(loc="lower right", fontsize=8)
    top = axes[0].secondary_xaxis("top", functions=(
        lambda x: np.interp(x, g, wall), lambda w: np.interp(w, wall, g)))
    top.set_xlabel("wall time (min)")
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    """The command line (python3 -m plumetrace.learn.es --help)."""
    import argparse

    from .._files import exit_status, output_folder

    p = argparse.ArgumentParser(
        prog="python3 -m plumetrace.learn.es",
        description="train a plume-tracking policy with an evolution strategy on the vector "
                    "environment; writes OUT/policy.json, OUT/curve.csv and OUT/curve.png")
    p.add_argument("--out", default="out/learned", help="output folder (default out/learned)")
    p.add_argument("--task", action="append", help="a task of the built-in benchmark suite "
                   f"(repeatable; default: {', '.join(TRAIN_TASKS)})")
    p.add_argument("--generations", type=int, default=150)
    p.add_argument("--pairs", type=int, default=8, help="antithetic pairs per generation")
    p.add_argument("--groups", type=int, default=1, help="plumes per task per generation")
    p.add_argument("--window", type=float, default=300.0,
                   help="seconds of each member's run per plume (and the timeout)")
    p.add_argument("--sigma", type=float, default=0.05)
    p.add_argument("--learning-rate", type=float, default=0.05)
    p.add_argument("--weight-decay", type=float, default=0.005)
    p.add_argument("--decision-interval", type=int, default=8)
    p.add_argument("--action", default="turn", choices=("turn", "heading"))
    p.add_argument("--hidden", type=int, default=8)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--quiet", action="store_true")
    args = p.parse_args(argv)
    try:
        out = output_folder(args.out, "--out")
        start = Policy(decision_interval=args.decision_interval, action=args.action,
                       hidden=args.hidden)
        start = start.with_theta(start.initial(np.random.default_rng(args.seed)))

        def show(row):
            if not args.quiet:
                print(f"generation {row['generation']:4d}  return {row['return']:7.3f}  "
                      f"success {row['success']:.2f}  population {row['population_return']:7.3f}"
                      f"  {row['wall_s']:7.1f} s", flush=True)

        policy, curve = train(args.task or TRAIN_TASKS, generations=args.generations,
                              pairs=args.pairs, groups=args.groups, window=args.window,
                              sigma=args.sigma, learning_rate=args.learning_rate,
                              weight_decay=args.weight_decay, policy=start, seed=args.seed,
                              threads=args.threads, log=out / "curve.csv", progress=show)
        policy.save(out / "policy.json")
        plot_curve(curve, out / "curve.png",
                   title=f"ES on {', '.join(policy.info['tasks'])}: {len(curve)} generations, "
                         f"{curve[-1]['wall_s'] / 60:.1f} min")
        print(f"wrote {out / 'policy.json'}, {out / 'curve.csv'}, {out / 'curve.png'} "
              f"({curve[-1]['wall_s']:.0f} s)")
    except (TypeError, ValueError, OSError) as e:
        print(f"python3 -m plumetrace.learn.es: {e}")
        return exit_status(e) if isinstance(e, OSError) else 2
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
