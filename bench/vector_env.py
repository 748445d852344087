"""Agent-steps per second of plumetrace.vector.VectorPlumeEnv against PlumeEnv stepped one by one,
and memory per environment: a benchmark (docs/vector.md, figures in docs/performance.md).

    PYTHONPATH=python:build/python /usr/bin/python3 bench/vector_env.py [--envs 1024]
        [--steps 2000] [--threads 0] [--plumeenv-steps 20] [--json FILE]

Every configuration steps `--envs` environments at decision interval 1 with uniformly random
headings (a fresh batch of actions every 16 steps, drawn before the clock starts), after 50
steps of warm-up; an agent-step is one environment's decision. Episodes end and restart as they
do (next-step autoreset) inside the timed loop. PlumeEnv: the same number of environments, each
reset and stepped in a Python loop, the way a user without the vector environment would.
"""

import argparse
import json
import os
import platform
import subprocess
import sys
import time

import numpy as np

from plumetrace.env import PlumeEnv
from plumetrace.vector import VectorPlumeEnv


def rss_bytes():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    return 0


def actions(n, seed=0):
    rng = np.random.default_rng(seed)
    return [rng.uniform(-1, 1, (n, 1)).astype(np.float32) for _ in range(64)]


_MEMORY = """
import sys
sys.path[:0] = {path!r}
from plumetrace.vector import VectorPlumeEnv


def rss():
    for line in open("/proc/self/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024


before = rss()
env = VectorPlumeEnv({n}, threads=1, **{options!r})
env.reset(seed=1)
print(rss() - before)
"""


def memory_per_env(n, options):
    """The growth of a fresh process's resident memory from building and resetting n
    environments, per environment (in a child process, so that no memory freed earlier is
    reused)."""
    script = _MEMORY.format(path=sys.path, n=n, options=options)
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         check=True)
    return int(out.stdout.strip()) / n


def vector_rate(n, steps, threads, **options):
    memory = memory_per_env(n, options) * n
    env = VectorPlumeEnv(n, threads=threads, **options)
    start = time.perf_counter()
    env.reset(seed=1)
    reset_s = time.perf_counter() - start
    batches = actions(n)
    for k in range(50):
        env.step(batches[k // 16 % 64])
    start, cpu = time.perf_counter(), time.process_time()
    ended = 0
    for k in range(steps):
        _, _, terminated, truncated, _ = env.step(batches[k // 16 % 64])
        ended += int(terminated.sum() + truncated.sum())
    elapsed, cpu = time.perf_counter() - start, time.process_time() - cpu
    env.close()
    # why: per CPU-second too, which a machine shared with other work changes less than wall time
    return {"agent_steps_per_s": n * steps / elapsed, "agent_steps_per_cpu_s": n * steps / cpu,
            "reset_s": reset_s, "bytes_per_env": memory / n, "episodes_ended": ended}


def plumeenv_rate(n, steps):
    before = rss_bytes()
    envs = [PlumeEnv(decision_interval=1, normalized_actions=True) for _ in range(n)]
    start = time.perf_counter()
    for i, e in enumerate(envs):
        e.reset(seed=1 + i)
    reset_s = time.perf_counter() - start
    memory = rss_bytes() - before  # why: measured before any VectorPlumeEnv in this process
    batches = actions(n)
    start, cpu = time.perf_counter(), time.process_time()
    for k in range(steps):
        a = batches[k // 16 % 64]
        for i, e in enumerate(envs):
            _, _, terminated, truncated, _ = e.step(a[i])
            if terminated or truncated:
                e.reset()
    elapsed, cpu = time.perf_counter() - start, time.process_time() - cpu
    return {"agent_steps_per_s": n * steps / elapsed, "agent_steps_per_cpu_s": n * steps / cpu,
            "reset_s": reset_s, "bytes_per_env": memory / n}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--envs", type=int, default=1024)
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--threads", type=int, default=0, help="0: every core")
    parser.add_argument("--plumeenv-steps", type=int, default=20)
    parser.add_argument("--json", help="also write the figures here")
    args = parser.parse_args()
    n = args.envs
    load = os.getloadavg()[0]  # what else runs: figures on a shared machine are lower
    configs = [
        ("binary, K = n (one plume)", dict(group_size=n)),
        ("binary, K = 64", dict(group_size=64)),
        ("binary, K = 16", dict(group_size=16)),
        ("concentration, K = n (one plume)", dict(group_size=n, observation="concentration")),
        ("concentration, K = 64", dict(group_size=64, observation="concentration")),
        ("binary, K = 1 (a plume each)", dict(group_size=1)),
    ]
    # why: first, so that its memory is measured before any vector environment's
    single = plumeenv_rate(n, args.plumeenv_steps)
    print(f"PlumeEnv one by one: {single['agent_steps_per_s']:,.0f} agent-steps/s", flush=True)
    rows = []
    for name, options in configs:
        if n % options["group_size"]:
            continue
        steps = args.steps if options["group_size"] > 1 else max(1, args.steps // 10)
        rows.append((name, vector_rate(n, steps, args.threads, **options)))
        print(f"{name}: {rows[-1][1]['agent_steps_per_s']:,.0f} agent-steps/s", flush=True)
    print()
    print(f"{n} environments, decision interval 1, threads = {args.threads or os.cpu_count()} "
          f"({os.cpu_count()} cores, {platform.processor() or platform.machine()})")
    print()
    print(f"load average at the start: {load:.1f}")
    print()
    print("| configuration | agent-steps/s | per CPU-s | x PlumeEnv | reset (s) | memory per env "
          "(kB) |")
    print("|---|---|---|---|---|---|")
    for name, r in rows + [("PlumeEnv, one by one", single)]:
        print(f"| {name} | {r['agent_steps_per_s']:,.0f} | {r['agent_steps_per_cpu_s']:,.0f} | "
              f"{r['agent_steps_per_s'] / single['agent_steps_per_s']:.0f} | "
              f"{r['reset_s']:.2f} | {r['bytes_per_env'] / 1024:.1f} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"envs": n, "rows": dict(rows), "plumeenv": single}, f, indent=1)


if __name__ == "__main__":
    main()
