"""The study file (STUDY.toml) and the unknowns file it names, read and checked.

Every mistake raises StudyError naming the file and the key; the command exits with status 2.
The formats are described in docs/calibration.md.
"""

import math
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path



def study_set_names(folder: Path) -> list:
    """The experiment sets of the study in `folder`, in order, from its study.toml (the one list
    of the paper's sets A-I: studies/lochmatter2008/study.toml); none without one."""
    path = folder / "study.toml"
    if not path.is_file():
        return []
    try:
        doc = tomllib.loads(path.read_text())
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        raise StudyError(f"{path}: cannot read the study file: {e}") from e
    sets = doc.get("sets", [])
    if not isinstance(sets, list) or any(not isinstance(s, str) for s in sets):
        raise StudyError(f"{path}: 'sets' must be a list of sweep files")
    return [Path(s).stem for s in sets]
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


def _read_toml(path, what):
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except FileNotFoundError:
        raise StudyError(f"{what} '{path}': no such file") from None
    except tomllib.TOMLDecodeError as e:
        raise StudyError(f"{what} '{path}': not valid TOML: {e}") from None


def _flatten(table, prefix=""):
    # nested tables and dotted keys alike become {"plume.amount": 1.0}
    out = {}
    for k, v in table.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(_flatten(v, key + "."))
        else:
            out[key] = v
    return out


def _number(where, value, integer=False):
    ok = isinstance(value, int) if integer else isinstance(value, (int, float))
    if isinstance(value, bool) or not ok:
        kind = "an integer" if integer else "a number"
        raise StudyError(f"{where}: must be {kind} (got {value!r})")
    return value


UNKNOWN_FIELDS = {"name", "key", "title", "printed", "choices", "low", "high", "log", "int",
                  "changes", "evidence"}


def read_unknowns(path):
    """The [[unknown]] entries of an unknowns file. Fields beyond the documented ones are
    ignored (the file is shared with the fidelity documents); missing or malformed ones are
    errors naming the entry."""
    doc = _read_toml(path, "unknowns file")
    entries = doc.get("unknown")
    if not isinstance(entries, list) or not entries:
        raise StudyError(f"unknowns file '{path}': no [[unknown]] entries")
    unknowns, names = [], set()
    for i, e in enumerate(entries):
        where = f"unknowns file '{path}', unknown {e.get('name', i + 1)!s}"
        if not isinstance(e, dict):
            raise StudyError(f"{where}: not a table")
        for req in ("name", "key"):
            if not isinstance(e.get(req), str) or not e[req]:
                raise StudyError(f"{where}: '{req}' is missing (a non-empty string)")
        if e["name"] in names:
            raise StudyError(f"{where}: name '{e['name']}' is used twice")
        names.add(e["name"])
        u = Unknown(name=e["name"], key=e["key"], title=str(e.get("title", "")),
                    printed=e.get("printed"), changes=str(e.get("changes", "")))
        if "choices" in e:
            if not isinstance(e["choices"], list) or not e["choices"]:
                raise StudyError(f"{where}: 'choices' must be a non-empty list")
            for c in e["choices"]:
                if isinstance(c, (dict, list)):
                    raise StudyError(f"{where}: 'choices' holds {c!r}; give numbers or strings")
            u.choices = list(e["choices"])
        elif "low" in e or "high" in e:
            u.integer = bool(e.get("int", False))
            u.log = bool(e.get("log", False))
            u.low = _number(f"{where}: 'low'", e.get("low"), u.integer)
            u.high = _number(f"{where}: 'high'", e.get("high"), u.integer)
            if not u.low < u.high:
                raise StudyError(f"{where}: bad range: low ({u.low}) must be below high "
                                 f"({u.high})")
            if u.log and u.low <= 0:
                raise StudyError(f"{where}: bad range: log = true needs low > 0 (got {u.low})")
        else:
            raise StudyError(f"{where}: give either 'choices' or 'low' and 'high'")
        for ev in e.get("evidence", []) or []:
            if not isinstance(ev, dict) or "value" not in ev:
                raise StudyError(f"{where}: every [[unknown.evidence]] needs a 'value'")
            u.evidence.append(Evidence(ev["value"], str(ev.get("source", "")),
                                       str(ev.get("says", ""))))
        unknowns.append(u)
    return unknowns


STUDY_KEYS = {"name", "unknowns", "search", "sets_dir", "sets", "runs", "seed", "trials",
              "threads", "startup_trials", "target", "truth", "fixed", "validation",
              "evidenced_only"}
VALIDATION_KEYS = {"top", "runs", "seed"}


def _positive(where, value):
    _number(where, value, integer=True)
    if value < 1:
        raise StudyError(f"{where}: bad range: must be at least 1 (got {value})")
    return value


def load_study(path, check_keys=None):
    """Reads and checks a study file. `check_keys(unknown, value)` (optional) raises when a
    config key or value is not accepted by the simulator; it is called with each searched
    unknown's first candidate and each fixed setting."""
    path = Path(path)
    doc = _read_toml(path, "study file")
    where = f"study file '{path}'"
    for k in doc:
        if k not in STUDY_KEYS:
            raise StudyError(f"{where}: unknown key '{k}' (keys: {', '.join(sorted(STUDY_KEYS))})")
    if "unknowns" not in doc or not isinstance(doc["unknowns"], str):
        raise StudyError(f"{where}: 'unknowns' is missing: the path of the unknowns file")
    base = path.parent
    unknowns_path = (base / doc["unknowns"]).resolve()
    all_unknowns = read_unknowns(unknowns_path)
    by_name = {u.name: u for u in all_unknowns}

    search = doc.get("search", [u.name for u in all_unknowns])
    if not isinstance(search, list) or not search:
        raise StudyError(f"{where}: 'search' must be a non-empty list of unknown names")
    for n in search:
        if n not in by_name:
            raise StudyError(f"{where}: 'search' names unknown '{n}', which '{unknowns_path}' "
                             f"does not declare (it has: {', '.join(by_name)})")
    searched = [u for u in all_unknowns if u.name in search]
    evidenced_only = doc.get("evidenced_only", False)
    if not isinstance(evidenced_only, bool):
        raise StudyError(f"{where}: 'evidenced_only' must be true or false")
    if evidenced_only:
        # why: the default reading may hold only values with evidence (docs/fidelity.md), so
        # this search offers each unknown its evidenced values alone
        restricted = []
        for u in searched:
            values = []
            for e in u.evidence:
                if not any(same_value(e.value, v) for v in values):
                    values.append(e.value)
            if not values:
                raise StudyError(f"{where}: 'evidenced_only': unknown '{u.name}' has no "
                                 f"[[unknown.evidence]] entry in '{unknowns_path}'")
            restricted.append(replace(u, choices=values, low=None, high=None))
        searched = restricted
    keys = [u.key for u in searched]
    for k in set(keys):
        if keys.count(k) > 1:
            raise StudyError(f"{where}: two searched unknowns set the same key '{k}'")

    sets_dir = (base / doc["sets_dir"]).resolve() if "sets_dir" in doc else unknowns_path.parent
    # the study whose sweep files these are: sets/ beside its study.toml, or the folder itself
    set_names = []
    for folder in (sets_dir.parent, sets_dir):
        if (folder / "study.toml").resolve() != path.resolve():
            set_names = set_names or study_set_names(folder)
    sets = doc.get("sets", set_names)
    if not isinstance(sets, list) or not sets or any(
            not isinstance(s, str) or (set_names and s not in set_names) for s in sets):
        raise StudyError(f"{where}: 'sets' must be a list of set names among "
                         f"{', '.join(set_names) or 'the sweep files of sets_dir'} (got {sets!r})")

    for name in sets:
        if not (sets_dir / f"{name}.toml").is_file():
            raise StudyError(f"{where}: 'sets_dir': no sweep file {name}.toml in '{sets_dir}'")

    study = Study(path=path, unknowns_path=unknowns_path, unknowns=searched,
                  all_unknowns=all_unknowns, sets_dir=sets_dir, sets=list(sets))
    if "name" in doc:
        if not isinstance(doc["name"], str) or not doc["name"]:
            raise StudyError(f"{where}: 'name' must be a non-empty string")
        study.name = doc["name"]
    study.runs = _positive(f"{where}: 'runs'", doc.get("runs", study.runs))
    study.trials = _positive(f"{where}: 'trials'", doc.get("trials", study.trials))
    study.startup_trials = _positive(f"{where}: 'startup_trials'",
                                     doc.get("startup_trials", study.startup_trials))
    study.seed = _positive(f"{where}: 'seed'", doc.get("seed", study.seed))
    study.threads = _number(f"{where}: 'threads'", doc.get("threads", 0), integer=True)
    if study.threads < 0:
        raise StudyError(f"{where}: 'threads': bad range: must be >= 0 (0: all cores)")

    study.target = doc.get("target", "paper")
    if study.target not in TARGETS:
        raise StudyError(f"{where}: 'target' must be one of {', '.join(TARGETS)} "
                         f"(got {study.target!r})")
    truth = doc.get("truth", {})
    if not isinstance(truth, dict):
        raise StudyError(f"{where}: 'truth' must be a table of unknown names and values")
    if study.target == "synthetic":
        if not truth:
            raise StudyError(f"{where}: target = \"synthetic\" needs a [truth] table")
        for n in truth:
            if n not in search:
                raise StudyError(f"{where}: 'truth' names '{n}', which is not searched")
    elif truth:
        raise StudyError(f"{where}: 'truth' is only for target = \"synthetic\"")
    study.truth = dict(truth)

    fixed = doc.get("fixed", {})
    if not isinstance(fixed, dict):
        raise StudyError(f"{where}: 'fixed' must be a table of config keys and values")
    study.fixed = _flatten(fixed)
    for k in study.fixed:
        if k in keys:
            raise StudyError(f"{where}: 'fixed.{k}' is also a searched unknown")

    val = doc.get("validation", {})
    if not isinstance(val, dict):
        raise StudyError(f"{where}: 'validation' must be a table")
    for k in val:
        if k not in VALIDATION_KEYS:
            raise StudyError(f"{where}: unknown key 'validation.{k}' (keys: "
                             f"{', '.join(sorted(VALIDATION_KEYS))})")
    v = Validation()
    v.top = _positive(f"{where}: 'validation.top'", val.get("top", v.top))
    v.runs = _positive(f"{where}: 'validation.runs'", val.get("runs", v.runs))
    v.seed = _positive(f"{where}: 'validation.seed'", val.get("seed", study.seed + 1000003))
    if v.seed == study.seed:
        raise StudyError(f"{where}: 'validation.seed' must differ from 'seed' (a fresh seed)")
    study.validation = v

    if check_keys is not None:
        for u in searched:
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
