"""A benchmark's results as the leaderboard reads them: OUT/benchmark.json (the manifest) and
OUT/runs.csv (one row per robot and run), checked, and grouped into runs of (task, controller,
trial).

The formats: docs/benchmark.md, "Leaderboard". A team task has one row per robot; its run
succeeds when any robot succeeds, and its time, overhead and declaration are those of the
earliest robot (by time_s) that succeeded or declared. Pure Python (no C++ module).
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from .._files import MAX_RESULTS_BYTES, BadPath, FileIoError, read_input

__all__ = ["BenchmarkError", "MANIFEST_NAME", "OUTCOMES", "Run", "Results", "load_results",
           "read_json"]

MANIFEST_NAME = "benchmark.json"
MANIFEST_FORMAT = 1
#: A run's outcomes as runs.csv spells them (include/plumetrace/sim/result.hpp, outcome_name).
OUTCOMES = ("success", "wall", "timeout", "gave_up", "wrong_declaration")
SUCCESS_RULES = ("reach", "declare")
# the columns of runs.csv the leaderboard reads (the others, axis columns included, are ignored)
RUN_COLUMNS = ("sweep", "controller.algorithm", "trial", "agent", "outcome", "success", "time_s",
               "overhead", "declaration_error")


class BenchmarkError(ValueError):
    """A missing or malformed benchmark file, or two results that cannot be compared: bad input,
    exit status 2. The message names the file (and the key or line)."""


@dataclass
class Run:
    """One run of a controller on a task (all its robots): what the leaderboard counts."""

    trial: int
    success: bool
    time: float  # s, the earliest successful robot's time_s; NaN without success
    overhead: float  # that robot's d_t/d_u; NaN without success or where undefined
    declared: bool  # a robot declared a source position
    declaration_error: float  # m, the earliest declaring robot's; NaN without a declaration
    outcomes: dict  # outcome -> number of robots that ended so


@dataclass
class Results:
    """The manifest and the complete runs of every cell (task, controller)."""

    manifest: dict
    path: Path  # the manifest's
    runs: dict  # (task, controller) -> {trial: Run}, trials 0..runs-1 only
    partial: dict = field(default_factory=dict)  # (task, controller) -> runs lacking a robot
    beyond: int = 0  # rows of trials >= runs, not counted

    @property
    def suite(self) -> dict:
        return self.manifest["suite"]

    @property
    def tasks(self) -> list:
        return self.suite["tasks"]

    @property
    def controllers(self) -> list:
        return self.manifest["controllers"]


def read_json(path: Path, what: str):
    """The parsed JSON file `path`; BenchmarkError naming `what` and the file when it is missing
    or not JSON, FileIoError (exit 3) when the system cannot read an existing file."""
    try:
        data = read_input(path, what, MAX_RESULTS_BYTES)
    except BadPath as e:
        _raise_unreadable(path, e)
    try:
        return json.loads(data.decode("utf-8"))
    except UnicodeDecodeError as e:
        raise BenchmarkError(f"{what} '{path}': not UTF-8 text ({e.reason} at byte {e.start})"
                             ) from None
    except json.JSONDecodeError as e:
        raise BenchmarkError(f"{what} '{path}': not valid JSON: {e.msg} at line {e.lineno}, "
                             f"column {e.colno}") from None


def _raise_unreadable(path: Path, error: BadPath):
    # why: a file that is there but cannot be read (rights) is an I/O failure (exit 3), as in
    # docs/reliability.md; a missing file or a folder is bad input (exit 2), as for the C++ reader
    if os.path.isfile(path) and not os.access(path, os.R_OK):
        raise FileIoError(str(error)) from None
    raise BenchmarkError(str(error)) from None


class _Check:
    """Checks the shape of the manifest; each failure names the file and the key."""

    def __init__(self, path: Path):
        self.path = path

    def fail(self, key: str, msg: str):
        raise BenchmarkError(f"{self.path}: {key}: {msg}")

    def get(self, obj: dict, key: str, where: str, kind, optional: bool = False):
        at = f"{where}.{key}" if where else key
        if key not in obj:
            if optional:
                return None
            self.fail(at, "missing")
        v = obj[key]
        if v is None and optional:
            return None
        ok = {int: lambda x: isinstance(x, int) and not isinstance(x, bool),
              float: lambda x: isinstance(x, (int, float)) and not isinstance(x, bool),
              str: lambda x: isinstance(x, str),
              bool: lambda x: isinstance(x, bool),
              list: lambda x: isinstance(x, list),
              dict: lambda x: isinstance(x, dict)}[kind]
        if not ok(v):
            names = {int: "a whole number", float: "a number", str: "a string",
                     bool: "true or false", list: "an array", dict: "an object"}
            self.fail(at, f"expected {names[kind]}, got {json.dumps(v)[:40]}")
        return v


def _named_entries(c: _Check, entries: list, where: str, what: str):
    """(index, entry) of a list of objects with distinct names, checked as it is iterated."""
    names = set()
    for i, entry in enumerate(entries):
        if not isinstance(entry, dict):
            c.fail(f"{where}[{i}]", "expected an object")
        name = c.get(entry, "name", f"{where}[{i}]", str)
        if name in names:
            c.fail(f"{where}[{i}].name", f"{what} '{name}' is listed twice")
        names.add(name)
        yield i, entry


def check_manifest(manifest, path: Path) -> dict:
    """The manifest, checked as far as the leaderboard reads it; BenchmarkError names the file
    and the key of anything missing, mistyped or repeated."""
    c = _Check(path)
    if not isinstance(manifest, dict):
        c.fail("(top)", "expected a JSON object")
    if manifest.get("plumetrace_benchmark") != MANIFEST_FORMAT:
        raise BenchmarkError(f"{path}: not a plumetrace benchmark manifest of format "
                             f"{MANIFEST_FORMAT} (\"plumetrace_benchmark\" is "
                             f"{json.dumps(manifest.get('plumetrace_benchmark'))})")
    c.get(manifest, "version", "", str)
    suite = c.get(manifest, "suite", "", dict)
    for key in ("name", "version", "digest"):
        c.get(suite, key, "suite", str)
    c.get(suite, "title", "suite", str, optional=True)
    c.get(suite, "seed", "suite", int)
    if c.get(suite, "runs", "suite", int) < 1:
        c.fail("suite.runs", f"must be at least 1, not {suite['runs']}")
    tasks = c.get(suite, "tasks", "suite", list)
    if not tasks:
        c.fail("suite.tasks", "no task")
    for i, t in _named_entries(c, tasks, "suite.tasks", "task"):
        where = f"suite.tasks[{i}]"
        c.get(t, "digest", where, str)
        for key in ("title", "why", "source"):
            c.get(t, key, where, str, optional=True)
        if c.get(t, "success", where, str) not in SUCCESS_RULES:
            c.fail(f"{where}.success", f"'{t['success']}': use reach or declare")
        if c.get(t, "robots", where, int) < 1:
            c.fail(f"{where}.robots", f"must be at least 1, not {t['robots']}")
        c.get(t, "timeout", where, float, optional=True)
    controllers = c.get(manifest, "controllers", "", list)
    if not controllers:
        c.fail("controllers", "no controller")
    for i, k in _named_entries(c, controllers, "controllers", "controller"):
        where = f"controllers[{i}]"
        c.get(k, "origin", where, str, optional=True)
        c.get(k, "file", where, str, optional=True)
        c.get(k, "null_model", where, bool)
    runs_file = c.get(manifest, "runs_file", "", str)
    if not runs_file or Path(runs_file).is_absolute() or ".." in Path(runs_file).parts:
        c.fail("runs_file", f"'{runs_file}': a file name inside the results folder")
    return manifest


def manifest_path(out) -> Path:
    """OUT/benchmark.json for a results folder, or the file itself when `out` names one."""
    out = Path(out)
    return out / MANIFEST_NAME if out.is_dir() else out


def load_results(out) -> Results:
    """The checked manifest of the results folder `out` and its runs, grouped into cells."""
    path = manifest_path(out)
    manifest = check_manifest(read_json(path, "benchmark manifest"), path)
    runs_path = path.parent / manifest["runs_file"]
    try:
        text = read_input(runs_path, "benchmark runs file", MAX_RESULTS_BYTES).decode("utf-8")
    except BadPath as e:
        _raise_unreadable(runs_path, e)
    except UnicodeDecodeError as e:
        raise BenchmarkError(f"{runs_path}: not UTF-8 text ({e.reason} at byte {e.start})"
                             ) from None
    return _group(manifest, path, runs_path, text)


def _number(text: str, where: str, nullable: bool) -> float:
    """A cell of runs.csv as a float: empty is NaN where `nullable`."""
    if text == "" and nullable:
        return math.nan
    try:
        v = float(text)
    except ValueError:
        raise BenchmarkError(f"{where}: '{text}' is not a number") from None
    if not math.isfinite(v) and not nullable:
        raise BenchmarkError(f"{where}: '{text}' is not a finite number")
    return v


def _whole(text: str, where: str) -> int:
    if not text.isdigit():
        raise BenchmarkError(f"{where}: '{text}' is not a whole number >= 0")
    return int(text)


def _group(manifest: dict, path: Path, runs_path: Path, text: str) -> Results:
    """Reads runs.csv's rows into runs: one per (task, controller, trial) with all its robots."""
    reader = csv.DictReader(io.StringIO(text, newline=""))
    missing = [c for c in RUN_COLUMNS if c not in (reader.fieldnames or [])]
    if missing:
        raise BenchmarkError(f"{runs_path}: no column {', '.join(missing)} (a plumetrace sweep "
                             "export's runs.csv has them)")
    tasks = {t["name"]: t for t in manifest["suite"]["tasks"]}
    controllers = {k["name"] for k in manifest["controllers"]}
    n_runs = manifest["suite"]["runs"]
    robots: dict = {}  # (task, controller, trial) -> {agent: row}
    beyond = 0
    for row in reader:
        where = f"{runs_path}: line {reader.line_num}"
        if None in row or any(row[c] is None for c in RUN_COLUMNS):
            raise BenchmarkError(f"{where}: the row has {len(row) - (None in row)} cells for "
                                 f"{len(reader.fieldnames)} columns")
        task, controller = row["sweep"], row["controller.algorithm"]
        if task not in tasks:
            raise BenchmarkError(f"{where}: task '{task}' is not in the suite of {path.name}")
        if controller not in controllers:
            raise BenchmarkError(f"{where}: controller '{controller}' is not among the "
                                 f"controllers of {path.name}")
        trial = _whole(row["trial"], f"{where}, trial")
        agent = _whole(row["agent"], f"{where}, agent")
        if agent >= tasks[task]["robots"]:
            raise BenchmarkError(f"{where}: agent {agent}, but task '{task}' has "
                                 f"{tasks[task]['robots']} robot(s)")
        if row["outcome"] not in OUTCOMES:
            raise BenchmarkError(f"{where}: outcome '{row['outcome']}': one of "
                                 f"{', '.join(OUTCOMES)}")
        if row["success"] not in ("0", "1") or (row["success"] == "1") != (
                row["outcome"] == "success"):
            raise BenchmarkError(f"{where}: success '{row['success']}' does not match outcome "
                                 f"'{row['outcome']}'")
        if trial >= n_runs:
            beyond += 1  # a store may hold more trials than this benchmark asked for
            continue
        robot = (row["outcome"], _number(row["time_s"], f"{where}, time_s", False),
                 _number(row["overhead"], f"{where}, overhead", True),
                 _number(row["declaration_error"], f"{where}, declaration_error", True))
        same_run = robots.setdefault((task, controller, trial), {})
        if agent in same_run:
            raise BenchmarkError(f"{where}: a second row for task '{task}', controller "
                                 f"'{controller}', trial {trial}, agent {agent}")
        same_run[agent] = robot
    runs: dict = {}
    partial: dict = {}
    for (task, controller, trial), rows in sorted(robots.items()):
        if len(rows) < tasks[task]["robots"]:
            partial[(task, controller)] = partial.get((task, controller), 0) + 1
            continue
        runs.setdefault((task, controller), {})[trial] = _run(trial, rows)
    return Results(manifest, path, runs, partial, beyond)


def _run(trial: int, rows: dict) -> Run:
    """One run from its robots' rows {agent: (outcome, time_s, overhead, declaration_error)}."""
    order = sorted(rows, key=lambda a: (rows[a][1], a))  # by the time each robot ended
    won = [a for a in order if rows[a][0] == "success"]
    declared = [a for a in order if not math.isnan(rows[a][3])]
    outcomes: dict = {}
    for outcome, *_ in rows.values():
        outcomes[outcome] = outcomes.get(outcome, 0) + 1
    first: Optional[tuple] = rows[won[0]] if won else None
    return Run(trial=trial, success=first is not None,
               time=first[1] if first else math.nan,
               overhead=first[2] if first else math.nan,
               declared=bool(declared),
               declaration_error=rows[declared[0]][3] if declared else math.nan,
               outcomes=outcomes)
