"""The study file (STUDY.toml) and the unknowns file it names, read and checked.

They are read and checked in C++ (studies/lochmatter2008/calibration_study.hpp,
`plumetrace._core.read_calibration_study`), as every input file is read: a regular file opened
without blocking, keys bounded in depth, each mistake named. Here the result becomes the
dataclasses the search uses. Every mistake raises StudyError naming the file and the key; the
command exits with status 2. The formats are described in docs/calibration.md.
"""

import math
from dataclasses import dataclass, field
from pathlib import Path

CALIBRATION_CLAIMS = [1, 2, 10]
HELD_OUT_CLAIMS = [3, 4, 5, 6, 7, 8, 9, 11]
TARGETS = ["paper", "synthetic"]


class StudyError(ValueError):
    """A study or unknowns file that cannot be used; the message names the file and the key."""


@dataclass
class Evidence:
    """One evidenced value of an unknown."""

    value: object
    source: str = ""
    says: str = ""


@dataclass
class Unknown:
    """One quantity the paper leaves open: a config key and its candidate values or range."""

    name: str
    key: str
    title: str = ""
    printed: object = None
    choices: list = None
    low: float = None
    high: float = None
    log: bool = False
    integer: bool = False
    changes: str = ""
    evidence: list = field(default_factory=list)

    def is_choice(self):
        """Whether the candidates are a list (else a range)."""
        return self.choices is not None

    def evidence_for(self, value):
        """The evidence entries whose value equals `value` (numbers to a relative 1e-9)."""
        return [e for e in self.evidence if same_value(e.value, value)]


@dataclass
class Validation:
    """How the best candidates are checked: the top k at more runs with a fresh seed."""

    top: int = 3
    runs: int = 50
    seed: int = 0
    confirm_runs: int = 0  # a second validation at more runs, same seed (0: none)


@dataclass
class Study:
    """A calibration study, as its file says, with every path resolved."""

    path: Path
    unknowns_path: Path
    unknowns: list  # the searched unknowns, in the unknowns file's order
    all_unknowns: list
    sets_dir: Path
    sets: list
    runs: int = 10
    seed: int = 1
    trials: int = 500
    threads: int = 0
    startup_trials: int = 10
    target: str = "paper"
    truth: dict = field(default_factory=dict)  # synthetic target: unknown name -> value
    fixed: dict = field(default_factory=dict)  # dotted key -> value, applied to every candidate
    validation: Validation = field(default_factory=Validation)
    name: str = "calibration"


def same_value(a, b):
    """Whether two candidate values are the same (numbers to a relative 1e-9)."""
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b or a == b and type(a) is type(b)
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return math.isclose(float(a), float(b), rel_tol=1e-9, abs_tol=1e-12)
    return a == b


def _unknown(d):
    evidence = [Evidence(value, source, says) for value, source, says in d.pop("evidence")]
    return Unknown(**d, evidence=evidence)


def load_study(path, check_keys=None):
    """Reads and checks a study file and its unknowns file (in C++: every check but the
    simulator's). `check_keys(settings)` (optional) raises ValueError when a config key or value
    is not accepted by the simulator; it is called with each searched unknown's first candidate,
    the fixed settings and each truth value."""
    from .. import _core

    try:
        d = _core.read_calibration_study(str(path))
    except ValueError as e:  # ConfigError
        raise StudyError(str(e)) from None
    path = Path(path)
    study = Study(path=path, unknowns_path=Path(d["unknowns_path"]),
                  unknowns=[_unknown(u) for u in d["unknowns"]],
                  all_unknowns=[_unknown(u) for u in d["all_unknowns"]],
                  sets_dir=Path(d["sets_dir"]), sets=list(d["sets"]), runs=d["runs"],
                  seed=d["seed"], trials=d["trials"], threads=d["threads"],
                  startup_trials=d["startup_trials"], target=d["target"], truth=d["truth"],
                  fixed=d["fixed"], validation=Validation(**d["validation"]), name=d["name"])
    if check_keys is not None:
        where = f"study file '{path}'"
        by_name = {u.name: u for u in study.all_unknowns}
        for u in study.unknowns:
            first = u.choices[0] if u.is_choice() else u.low
            _check(check_keys, f"{where}: unknown '{u.name}' (key '{u.key}')", {u.key: first})
        if study.fixed:
            _check(check_keys, f"{where}: 'fixed'", study.fixed)
        for n, value in study.truth.items():
            _check(check_keys, f"{where}: 'truth.{n}'", {by_name[n].key: value})
    return study


def _check(check_keys, where, settings):
    try:
        check_keys(settings)
    except ValueError as e:
        raise StudyError(f"{where}: {e}") from None
