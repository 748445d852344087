"""`python3 -m plumetrace.calibrate`: parsing, the run's order (search, validation, files) and
exit statuses (0 done, 2 bad input, 3 I/O failure, 130 interrupted; docs/calibration.md)."""

import argparse
import os
import signal
import sys
from contextlib import contextmanager

from .._files import BadPath, FileIoError, folder_lock, output_folder, write_whole
from .study import StudyError, load_study

BAD_INPUT = 2
IO_FAILURE = 3
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


def _option(name, value, low, high, meaning=""):
    if not low <= value <= high:
        raise StudyError(f"{name}: bad range: must be {low}{meaning} to {high} (got {value})")
    return value


class StorageError(Exception):
    """The study's database could not be used; `status` is the exit status (3 for I/O)."""

    def __init__(self, message, status):
        super().__init__(message)
        self.status = status


@contextmanager
def _storage_errors(path):
    # why: Optuna reports its database's failures as SQLAlchemy's exceptions, whose text is a
    # traceback's worth of SQL; a full disk or a read-only file is an I/O failure (exit 3), a
    # file that is not a database bad input (exit 2), each named by the file
    try:
        yield
    except Exception as e:
        try:
            from sqlalchemy import exc
        except ImportError:  # pragma: no cover - Optuna needs SQLAlchemy
            raise e from None
        if not isinstance(e, exc.SQLAlchemyError):
            raise
        cause = str(getattr(e, "orig", None) or e).splitlines()[0]
        if cause in ("disk I/O error", "database or disk is full"):
            cause += " (is the disk full, or the file size limit reached?)"
        status = IO_FAILURE if isinstance(e, exc.OperationalError) else BAD_INPUT
        raise StorageError(f"cannot use the study database '{path}': {cause}", status) from None


def run(args):
    from .. import _core
    from . import report, search

    study = load_study(args.study, check_keys=search.check_settings)
    if args.trials is not None:
        study.trials = _option("--trials", args.trials, 1, _core.MAX_CALIBRATION_TRIALS)
    if args.threads is not None:
        study.threads = _option("--threads", args.threads, 0, _core.MAX_THREADS, " (all cores)")
    progress = not args.quiet and sys.stderr.isatty()
    out = output_folder(args.out, "--out")
    # why: two processes in one folder would race on its database and files; the second is
    # refused at once, naming the folder, before it touches anything (issue 22, G5)
    with folder_lock(out, "--out"), _storage_errors(out / "study.sqlite"):
        opt, evaluated = search.run_search(study, out, progress)
        validation = search.validate(study, opt, out, progress)
        best_path = write_whole(out / "best.toml", search.best_toml(study, validation))
        page = report.write_report(study, opt, validation, out, evaluated)
    if not args.quiet:
        print(report.title_of(study, validation))
        print(f"report: {page}\nbest reading: {best_path}")
    return 0


class _Stop:
    """SIGINT and SIGTERM while the command runs: the first raises KeyboardInterrupt where Python
    is (in C++ the evaluation sees it within 0.25 s and stops: plumetrace._core.evaluate_sets);
    a second ends the process at once with status 130, as the C++ command's second signal does."""

    def __init__(self):
        self.signalled = False

    def __call__(self, signum, frame):
        if self.signalled:
            os._exit(INTERRUPTED)
        self.signalled = True
        raise KeyboardInterrupt


@contextmanager
def _stop_on_signals(stop):
    # why: installed even where the shell left SIGINT ignored (a command started with &), as
    # the C++ command does
    previous = {s: signal.signal(s, stop) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, h in previous.items():
            signal.signal(s, h)


def _error(message):
    print(f"plumetrace.calibrate: error: {message}", file=sys.stderr)


def _status(args):
    # the command's exit status; each error reported in one line naming the file or option
    try:
        return run(args)
    except (StudyError, BadPath) as e:
        _error(e)
        return BAD_INPUT
    except StorageError as e:
        _error(e)
        return e.status
    except OSError as e:  # FileIoError, and any other the system raised
        _error(e if isinstance(e, FileIoError) else
               f"cannot use '{e.filename or args.out}': {e.strerror or e}")
        return IO_FAILURE
    except MemoryError:
        _error("out of memory; the finished trials are kept in "
               f"{os.path.join(args.out, 'study.sqlite')} (lower threads or runs)")
        return IO_FAILURE


def main(argv=None):
    args = parse(argv)
    stop = _Stop()
    interrupted = False
    with _stop_on_signals(stop):
        try:
            status = _status(args)
        except KeyboardInterrupt:
            interrupted = True
        except BaseException:
            # why: a signal may surface as another exception from the code it interrupted (an
            # import half done); the signal is what the user asked for
            if not stop.signalled:
                raise
        if interrupted or stop.signalled:
            print(f"plumetrace.calibrate: interrupted; the finished trials are in "
                  f"{os.path.join(args.out, 'study.sqlite')}: run the same command again to "
                  "continue", file=sys.stderr)
            return INTERRUPTED
        return status
