"""`python3 -m plumetrace.calibrate`: parsing, the run's order (search, validation, files) and
exit statuses (0 done, 2 bad input, 130 interrupted)."""

import argparse
import os
import sys
from pathlib import Path

from .study import StudyError, load_study

BAD_INPUT = 2
INTERRUPTED = 130


def parse(argv):
    p = argparse.ArgumentParser(
        prog="python3 -m plumetrace.calibrate",
        description="Search the declared unknowns on the calibration claims, validate the best "
        "candidates on every claim, write the study's report.")
    p.add_argument("study", help="study file (TOML, see docs/calibration.md)")
    p.add_argument("--out", default="out/calibration",
                   help="output folder: study.sqlite, validation.json, best.toml, "
                   "calibration.html (default: out/calibration)")
    p.add_argument("--trials", type=int, help="completed trials to reach (default: the file's)")
    p.add_argument("--threads", type=int, help="worker threads (default: the file's; 0 all cores)")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    return p.parse_args(argv)


def run(args):
    from . import report, search

    study = load_study(args.study, check_keys=search.check_settings)
    if args.trials is not None:
        if args.trials < 1:
            raise StudyError(f"--trials: bad range: must be at least 1 (got {args.trials})")
        study.trials = args.trials
    if args.threads is not None:
        if args.threads < 0:
            raise StudyError(f"--threads: bad range: must be >= 0 (got {args.threads})")
        study.threads = args.threads
    progress = not args.quiet and sys.stderr.isatty()
    out = Path(args.out)
    opt, evaluated = search.run_search(study, out, progress)
    validation = search.validate(study, opt, out, progress)
    best_path = out / "best.toml"
    best_path.write_text(search.best_toml(study, validation))
    page = report.write_report(study, opt, validation, out, evaluated)
    if not args.quiet:
        print(report.title_of(study, validation))
        print(f"report: {page}\nbest reading: {best_path}")
    return 0


def main(argv=None):
    args = parse(argv)
    try:
        return run(args)
    except StudyError as e:
        print(f"plumetrace.calibrate: error: {e}", file=sys.stderr)
        return BAD_INPUT
    except KeyboardInterrupt:
        print(f"plumetrace.calibrate: interrupted; the finished trials are in "
              f"{os.path.join(args.out, 'study.sqlite')}: run the same command again to continue",
              file=sys.stderr)
        return INTERRUPTED
