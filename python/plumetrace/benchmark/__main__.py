"""python3 -m plumetrace.benchmark [SUITE] [options]: `plumetrace benchmark` with controllers
written in Python (the command hands itself to this module when a --controller is a .py file).
Exit status 0, 2 for bad input or a controller that raised (its traceback printed), 3 when a
file cannot be read or written, 130 when stopped."""

import argparse
import sys
import traceback
from pathlib import Path

from .._files import exit_status
from .._workers import RemoteTraceback

# the package's folder: an exception whose traceback passes through no file outside it was not
# raised by a controller
_PACKAGE = Path(__file__).resolve().parents[1]


def _parser():
    p = argparse.ArgumentParser(
        prog="plumetrace benchmark",
        description="run controllers on every task of a benchmark suite into a results store "
                    "and write the leaderboard (docs/benchmark.md)")
    p.add_argument("suite", nargs="?", help="suite file (default: the built-in suite)")
    p.add_argument("--controller", action="append", default=[],
                   help="a registered name, or a .py file that defines controllers (repeatable)")
    p.add_argument("--only", action="store_true", help="run only the --controller ones")
    p.add_argument("--task", action="append", default=[], help="run only this task (repeatable)")
    p.add_argument("--runs", type=int, default=0, help="runs per controller and task")
    p.add_argument("--threads", type=int, default=0,
                   help="worker processes with a controller written in Python, else threads "
                        "(default: all cores)")
    p.add_argument("--store", help="results store (default: OUT/results.sqlite)")
    p.add_argument("--out", help="output folder (default: out/NAME)")
    p.add_argument("--set", action="append", default=[], dest="sets",
                   help="override a key of every task: key=value (repeatable)")
    p.add_argument("--shard", help="compute only part I of N (I/N)")
    p.add_argument("--quiet", action="store_true", help="print less")
    p.add_argument("--fresh", action="store_true", help="discard every run the store holds")
    p.add_argument("--no-share-plumes", action="store_true",
                   help="simulate the plume anew for every run (same results, slower)")
    p.add_argument("--no-leaderboard", action="store_true",
                   help="write the store and the exports only")
    p.add_argument("--compare", nargs=2, metavar=("A", "B"), help="compare two results")
    p.add_argument("--allow-runs", action="store_true",
                   help="with --compare: accept the same tasks at other run counts")
    return p


def _sets(texts):
    out = {}
    for text in texts:
        key, sep, value = text.partition("=")
        if not sep or not key.strip():
            raise ValueError(f"--set '{text}': expected key.path=value")
        out[key.strip()] = value.strip()
    return out


class _ProgressBar:
    """The command's progress line on stderr, as `plumetrace benchmark` draws it (cli/progress.cpp):
    drawn only where stderr is a terminal."""

    WIDTH = 30

    def __init__(self, label, enabled):
        self.label, self.enabled, self.drawn = label, enabled, False

    def __call__(self, done, total, seconds):
        if not self.enabled or total == 0:
            return
        filled = int(done / total * self.WIDTH)
        rate = done / seconds if seconds > 0 else 0.0
        eta = _clock(round((total - done) / rate)) if rate > 0 else "--:--"
        sys.stderr.write(f"\r{self.label} [{'#' * filled}{'.' * (self.WIDTH - filled)}] "
                         f"{done}/{total} runs  {rate:.1f} runs/s  ETA {eta}  ")
        sys.stderr.flush()
        self.drawn = True

    def finish(self):
        if self.drawn:
            sys.stderr.write("\n")
        self.drawn = False


def _clock(seconds):
    minutes, s = divmod(seconds, 60)
    return f"{minutes // 60}:{minutes % 60:02d}:{s:02d}" if minutes >= 60 else f"{minutes}:{s:02d}"


def _controller_traceback(error):
    """The traceback of `error`, raised by benchmark(), as text where a controller raised it (in
    a worker process, or in a file outside this package), else None."""
    if isinstance(error.__cause__, RemoteTraceback):
        return error.__cause__.text
    for frame in traceback.extract_tb(error.__traceback__):
        if not Path(frame.filename).resolve().is_relative_to(_PACKAGE):
            return "".join(traceback.format_exception(error))
    return None


def main(argv=None):
    args = _parser().parse_args(argv)
    if args.compare:
        from .compare import main as compare

        return compare(list(args.compare) + (["--allow-runs"] if args.allow_runs else []))
    from .run import benchmark

    bar = _ProgressBar("benchmark", not args.quiet and sys.stderr.isatty())
    try:
        try:
            done = benchmark(args.suite, controllers=args.controller, tasks=args.task,
                             only=args.only, runs=args.runs, threads=args.threads, out=args.out,
                             store=args.store, fresh=args.fresh, shard=args.shard,
                             overrides=_sets(args.sets), share_plumes=not args.no_share_plumes,
                             leaderboard=False, progress=bar)
        except Exception as e:
            bar.finish()
            text = _controller_traceback(e)
            if text is None:
                raise
            sys.stderr.write(text)
            print(f"plumetrace: error: a controller raised {type(e).__name__}: {e} (traceback "
                  "above); the runs finished before it are in the store: run the same command "
                  "again once it is fixed", file=sys.stderr)
            return 2
        finally:
            bar.finish()
        print(f"{done['total']} runs ({done['computed']} computed now, {done['skipped']} from "
              f"the store) in {done['elapsed']:.1f} s; store {done['store']}")
        if done["shard"]:
            print(f"shard {done['shard']} of benchmark {done['suite']}; merge the parts' stores "
                  "with plumetrace merge")
            return 0
        print(f"suite {done['suite']} version {done['version']}, digest {done['digest']}")
        if args.no_leaderboard:
            print(f"exports in {done['out']}/")
            return 0
        from .leaderboard import write_leaderboard

        write_leaderboard(done["out"])
        print(f"leaderboard: {done['out']}/leaderboard.html (and .md, .csv, .json, figures/)")
        return 0
    except KeyboardInterrupt:
        print("plumetrace: interrupted: the runs finished are in the store; run the same "
              "command again to compute the rest", file=sys.stderr)
        return 130
    except (ValueError, OSError) as e:
        print(f"plumetrace: error: {e}", file=sys.stderr)
        return exit_status(e)


if __name__ == "__main__":
    sys.exit(main())
