"""The calibration study: which reading of what the paper leaves unsaid reproduces it.

    python3 -m plumetrace.calibrate STUDY.toml [--out DIR] [--trials N] [--threads N] [--quiet]

searches the unknowns the study file names (from an unknowns file such as
studies/lochmatter2008/unknowns.toml) with Optuna's TPE sampler, scoring only the
calibration claims; reruns the best candidates with a fresh seed to evaluate the held-out
claims; writes DIR/study.sqlite (resumable), DIR/validation.json, DIR/best.toml and
DIR/calibration.html. Formats and the score: docs/calibration.md.
"""

from .study import CALIBRATION_CLAIMS, HELD_OUT_CLAIMS, StudyError, load_study

__all__ = ["CALIBRATION_CLAIMS", "HELD_OUT_CLAIMS", "StudyError", "load_study", "main"]


def main(argv=None):
    """The command; returns its exit status."""
    from .cli import main as cli_main

    return cli_main(argv)
