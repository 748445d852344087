"""A learning-style loop on the paper's plume, and the two plot helpers.

Run: PYTHONPATH=build/python /usr/bin/python3 examples/python_env_and_plots.py [OUT_DIR]
Writes OUT_DIR/last_frame.png (the environment's last frame), OUT_DIR/trajectory.png and
OUT_DIR/sweep.png (default: the current folder).
"""

import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot  # noqa: E402

import plumetrace as pt  # noqa: E402
from plumetrace import plots  # noqa: E402
from plumetrace.env import PlumeEnv  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def zigzag_policy(obs, time):
    """Upwind in odor; outside it, sweep the heading to and fro (a hand-made policy)."""
    odor = obs[0] > 0.5
    return 0.0 if odor else 1.2 * math.sin(time / 1.92)


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(".")
    out.mkdir(parents=True, exist_ok=True)

    # a decision every 4 steps of 0.032 s; frames drawn with matplotlib
    env = PlumeEnv(robot__start_x=8.0, decision_interval=4, render_mode="rgb_array")
    total = 0.0
    for episode in range(3):
        obs, info = env.reset(seed=1) if episode == 0 else env.reset()
        while True:
            obs, reward, terminated, truncated, info = env.step(zigzag_policy(obs, info["time"]))
            total += reward
            if terminated or truncated:
                break
        print(f"episode {episode} (trial {info['trial']}): {info['outcome']} "
              f"after {info['time']:.1f} s")
    print(f"total reward {total}")
    matplotlib.pyplot.imsave(out / "last_frame.png", env.render())
    env.close()

    run = pt.run(algorithm="surge-spiral", seed=1, trial=0, snapshot_interval=10.0)
    plots.trajectory(run).figure.savefig(out / "trajectory.png", dpi=100)
    rows = pt.sweep(ROOT / "tests" / "golden" / "sweep.toml", runs=4)
    plots.sweep_bars(rows, "wind_sensor.sigma_a").savefig(out / "sweep.png", dpi=100)
    print(f"wrote {out / 'last_frame.png'}, {out / 'trajectory.png'} and {out / 'sweep.png'}")


if __name__ == "__main__":
    main()
