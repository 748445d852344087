"""The calibration study: which reading of what the paper leaves unsaid reproduces it.

    python3 -m plumetrace.calibrate STUDY.toml [--out DIR] [--trials N] [--threads N] [--quiet]

searches the unknowns the study file names (from an unknowns file such as
studies/lochmatter2008/unknowns.toml) with Optuna's TPE sampler, scoring only the
calibration claims; reruns the best candidates with a fresh seed to evaluate the held-out
claims; writes DIR/study.sqlite (resumable), DIR/validation.json, DIR/best.toml and
DIR/calibration.html. Formats and the score: docs/calibration.md.
"""

__all__ = ["CALIBRATION_CLAIMS", "HELD_OUT_CLAIMS", "StudyError", "load_study", "main"]


def __getattr__(name):
    # why: lazy, so that `python3 -m plumetrace.calibrate` reaches its signal handlers (status
    # 130 on Ctrl-C) after as few imports as possible
    if name in __all__:
        from . import study

        return getattr(study, name)
    raise AttributeError(f"module 'plumetrace.calibrate' has no attribute {name!r}")


def main(argv=None):
    """The command; returns its exit status."""
    from .cli import main as cli_main

    return cli_main(argv)
