"""The comparison of two benchmark results: are they the same suite, and which differences are
beyond noise.

    python3 -m plumetrace.benchmark.compare A B [--allow-runs]

A and B are leaderboard.json files, or the folders holding them. Results of different suites
(name, version or digest) are refused, exit 2, naming both files and what differs; the same
suite at other run counts ("same tasks, other run counts") only with --allow-runs. Otherwise it
prints, as B - A: each controller's score with the paired bootstrap 95% interval of the
difference, and for each (task, controller) cell of both the difference of success rates with
Newcombe's 95% interval and of mean times to source with a two-sample bootstrap 95% interval,
each marked where the interval excludes 0; cells in one file only are listed. Exit 0; 2 for a
file that is not a leaderboard (named); 3 when a file cannot be read. docs/benchmark.md,
"Comparing results".
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Optional, Sequence


from .._files import BadPath, exit_status
from ..evidence import newcombe_difference
from .data import BenchmarkError, read_json
from .stats import bootstrap_difference, paired_scores, percentile, trial_matrix

__all__ = ["BOARD_NAME", "compare_files", "load_board", "main", "suite_relation"]

BOARD_NAME = "leaderboard.json"
DASH = "\u2013"


def _board_path(path) -> Path:
    path = Path(path)
    return path / BOARD_NAME if path.is_dir() else path


def load_board(path) -> tuple:
    """(the file's path, its content): a leaderboard.json, or the one in the folder `path`;
    BenchmarkError naming the file when it is not a leaderboard."""
    path = _board_path(path)
    board = read_json(path, "leaderboard")

    def refuse(why: str):
        raise BenchmarkError(f"{path}: not a plumetrace leaderboard ({why})")

    if not isinstance(board, dict) or board.get("plumetrace_leaderboard") != 1:
        refuse('no "plumetrace_leaderboard": 1 at the top')
    suite = board.get("suite")
    if not isinstance(suite, dict):
        refuse("no suite")
    for key in ("name", "version", "digest"):
        if not isinstance(suite.get(key), str):
            refuse(f"suite.{key} is not a string")
    if not isinstance(suite.get("runs"), int) or not isinstance(suite.get("tasks"), list):
        refuse("suite.runs or suite.tasks missing")
    for i, t in enumerate(suite["tasks"]):
        if not isinstance(t, dict) or not isinstance(t.get("name"), str) or not isinstance(
                t.get("digest"), str):
            refuse(f"suite.tasks[{i}] lacks a name or digest")
    if not isinstance(board.get("scores"), list) or not isinstance(board.get("cells"), list):
        refuse("no scores or cells")
    for i, s in enumerate(board["scores"]):
        if not isinstance(s, dict) or not isinstance(s.get("controller"), str):
            refuse(f"scores[{i}] lacks a controller")
    for i, c in enumerate(board["cells"]):
        ok = (isinstance(c, dict) and isinstance(c.get("task"), str)
              and isinstance(c.get("controller"), str) and isinstance(c.get("runs"), int)
              and isinstance(c.get("successes"), int) and isinstance(c.get("trials"), str)
              and len(c["trials"]) == suite["runs"] and set(c["trials"]) <= set("01-")
              and isinstance(c.get("times"), list)
              and all(isinstance(x, (int, float)) for x in c["times"]))
        if not ok:
            refuse(f"cells[{i}] lacks task, controller, runs, successes, trials or times")
    return path, board


def suite_relation(a: dict, b: dict) -> tuple:
    """("same" | "runs" | "other", what differs in words): "runs" when name, version and every
    task's digest agree but the suite digest differs (other run counts)."""
    sa, sb = a["suite"], b["suite"]
    if sa["name"] != sb["name"]:
        return "other", f"different suites: '{sa['name']}' and '{sb['name']}'"
    if sa["version"] != sb["version"]:
        return "other", (f"different versions of suite '{sa['name']}': {sa['version']} and "
                         f"{sb['version']}")
    if sa["digest"] == sb["digest"]:
        return "same", f"the same suite: {sa['name']} v{sa['version']}, digest {sa['digest']}"
    ta = {t["name"]: t["digest"] for t in sa["tasks"]}
    tb = {t["name"]: t["digest"] for t in sb["tasks"]}
    if ta == tb:
        return "runs", (f"same tasks, other run counts: suite {sa['name']} v{sa['version']} at "
                        f"{sa['runs']} and {sb['runs']} runs per cell (digests {sa['digest']} "
                        f"and {sb['digest']})")
    changed = sorted(set(ta) ^ set(tb) | {t for t in set(ta) & set(tb) if ta[t] != tb[t]})
    return "other", (f"suite {sa['name']} v{sa['version']} with different digests "
                     f"({sa['digest']} and {sb['digest']}): task(s) {', '.join(changed)} "
                     "differ, though a changed task makes a new version")


def _beyond(lo: Optional[float], hi: Optional[float]) -> Optional[bool]:
    if lo is None or hi is None or math.isnan(lo) or math.isnan(hi):
        return None
    return bool(lo > 0 or hi < 0)


def _number(v: float) -> Optional[float]:
    return None if v is None or not math.isfinite(v) else float(v)


def _cells(board: dict) -> dict:
    return {(c["task"], c["controller"]): c for c in board["cells"] if c["runs"] > 0}


def _score_differences(a: dict, b: dict, paired: bool) -> list:
    """B - A of each controller scored in both, with a bootstrap 95% interval: the same trials
    drawn in A and B when they hold the same trials (paired), apart otherwise."""
    sa = {s["controller"]: s for s in a["scores"] if s.get("score") is not None}
    sb = {s["controller"]: s for s in b["scores"] if s.get("score") is not None}
    both = [c for c in sa if c in sb]
    if not both:
        return []
    tasks = [t["name"] for t in a["suite"]["tasks"]]
    ca, cb = _cells(a), _cells(b)
    if any((t, c) not in ca or (t, c) not in cb for t in tasks for c in both):
        raise BenchmarkError("a scored controller lacks a cell of runs (a leaderboard edited "
                             "by hand?)")
    if paired:
        stacked = [trial_matrix([ca[(t, c)]["trials"] for c in both]
                                + [cb[(t, c)]["trials"] for c in both]) for t in tasks]
        reps = paired_scores(tasks, stacked, names=("compare",))
        ra, rb = reps[:len(both)], reps[len(both):]
    else:
        ra = paired_scores(tasks, [trial_matrix([ca[(t, c)]["trials"] for c in both])
                                   for t in tasks], names=("compare", "A"))
        rb = paired_scores(tasks, [trial_matrix([cb[(t, c)]["trials"] for c in both])
                                   for t in tasks], names=("compare", "B"))
    out = []
    for i, c in enumerate(both):
        d = rb[i] - ra[i]
        lo, hi = percentile(d, 0.025), percentile(d, 0.975)
        out.append({"controller": c, "a": sa[c]["score"], "b": sb[c]["score"],
                    "difference": sb[c]["score"] - sa[c]["score"], "lo": _number(lo),
                    "hi": _number(hi), "beyond_noise": _beyond(lo, hi)})
    return out


def _cell_difference(task: str, controller: str, a: dict, b: dict) -> dict:
    """B - A of one cell: success (Newcombe 95%) and mean time to source (bootstrap 95%)."""
    lo, hi = newcombe_difference(b["successes"], b["runs"], a["successes"], a["runs"])
    out = {"task": task, "controller": controller,
           "success_a": a["successes"] / a["runs"], "success_b": b["successes"] / b["runs"],
           "runs_a": a["runs"], "runs_b": b["runs"],
           "success_difference": b["successes"] / b["runs"] - a["successes"] / a["runs"],
           "success_lo": _number(lo), "success_hi": _number(hi),
           "success_beyond_noise": _beyond(lo, hi),
           "time_a": None, "time_b": None, "time_difference": None, "time_lo": None,
           "time_hi": None, "time_beyond_noise": None}
    ta, tb = a["times"], b["times"]
    if ta and tb:
        mean_a, mean_b = math.fsum(ta) / len(ta), math.fsum(tb) / len(tb)
        lo, hi = bootstrap_difference(tb, ta, "compare", task, controller)
        out.update(time_a=mean_a, time_b=mean_b, time_difference=mean_b - mean_a,
                   time_lo=_number(lo), time_hi=_number(hi), time_beyond_noise=_beyond(lo, hi))
    return out


def compare_files(a, b, allow_runs: bool = False) -> dict:
    """The comparison B - A of two leaderboards (files or folders holding leaderboard.json).
    Raises BenchmarkError naming both files when their suites differ (or, without
    `allow_runs`, when they differ only in run counts) or naming the one that is not a
    leaderboard."""
    path_a, board_a = load_board(a)
    path_b, board_b = load_board(b)
    relation, words = suite_relation(board_a, board_b)
    if relation == "other" or (relation == "runs" and not allow_runs):
        hint = "; give --allow-runs to compare them anyway" if relation == "runs" else ""
        raise BenchmarkError(f"cannot compare '{path_a}' and '{path_b}': {words}{hint}")
    ca, cb = _cells(board_a), _cells(board_b)
    cells = [_cell_difference(t, c, ca[(t, c)], cb[(t, c)]) for (t, c) in ca if (t, c) in cb]
    paired = board_a["suite"]["runs"] == board_b["suite"]["runs"]
    scores = _score_differences(board_a, board_b, paired)
    beyond = sum(bool(c["success_beyond_noise"]) for c in cells) + sum(
        bool(c["time_beyond_noise"]) for c in cells) + sum(bool(s["beyond_noise"])
                                                           for s in scores)
    return {"a": str(path_a), "b": str(path_b), "relation": relation, "suite": words,
            "paired": paired, "scores": scores, "cells": cells,
            "only_a": [list(k) for k in ca if k not in cb],
            "only_b": [list(k) for k in cb if k not in ca],
            "beyond_noise": beyond}


def _fmt(v: Optional[float], digits: int = 2, sign: bool = False) -> str:
    if v is None:
        return DASH
    return f"{v:+.{digits}f}" if sign else f"{v:.{digits}f}"


def _diff(d, lo, hi, digits: int) -> str:
    if d is None:
        return DASH
    ends = "" if lo is None else f" ({_fmt(lo, digits, True)} to {_fmt(hi, digits, True)})"
    return _fmt(d, digits, True) + ends


def _mark(beyond: Optional[bool]) -> str:
    return "" if beyond is None else "BEYOND NOISE" if beyond else "within noise"


def format_comparison(result: dict) -> str:
    """The comparison as the command prints it."""
    lines = [f"A: {result['a']}", f"B: {result['b']}", result["suite"] + ".",
             "Differences are B - A with 95% intervals; BEYOND NOISE where the interval "
             "excludes 0.", ""]
    lines.append("score (mean success over tasks), "
                 + ("paired" if result["paired"] else "unpaired") + " bootstrap:")
    width = max([len(s["controller"]) for s in result["scores"]] + [10])
    for s in result["scores"]:
        lines.append(f"  {s['controller']:<{width}}  {_fmt(s['a'])} -> {_fmt(s['b'])}  "
                     f"{_diff(s['difference'], s['lo'], s['hi'], 2)}  {_mark(s['beyond_noise'])}")
    if not result["scores"]:
        lines.append("  no controller is scored in both")
    lines += ["", "cells (task, controller): success rate (Newcombe), mean time to source in s "
              "(bootstrap):"]
    for c in result["cells"]:
        lines.append(f"  {c['task']}, {c['controller']}: success {_fmt(c['success_a'])} -> "
                     f"{_fmt(c['success_b'])} "
                     f"{_diff(c['success_difference'], c['success_lo'], c['success_hi'], 2)} "
                     f"{_mark(c['success_beyond_noise'])}; time {_fmt(c['time_a'], 1)} -> "
                     f"{_fmt(c['time_b'], 1)} "
                     f"{_diff(c['time_difference'], c['time_lo'], c['time_hi'], 1)} "
                     f"{_mark(c['time_beyond_noise'])}".rstrip())
    for key, which in (("only_a", "A"), ("only_b", "B")):
        for task, controller in result[key]:
            lines.append(f"  {task}, {controller}: only in {which}")
    lines += ["", f"{result['beyond_noise']} difference(s) beyond noise."]
    return "\n".join(lines)


def main(argv: Optional[Sequence[str]] = None) -> int:
    """The command line: A B [--allow-runs]; exit 0, 2 (bad input, different suites) or 3."""
    import argparse

    parser = argparse.ArgumentParser(
        prog="python3 -m plumetrace.benchmark.compare",
        description="Compare two benchmark results (leaderboard.json files or their folders): "
                    "the same suite? which differences are beyond noise?")
    parser.add_argument("a", metavar="A", help="the first leaderboard.json (or its folder)")
    parser.add_argument("b", metavar="B", help="the second leaderboard.json (or its folder)")
    parser.add_argument("--allow-runs", action="store_true",
                        help="compare results of the same tasks at other run counts")
    args = parser.parse_args(argv)
    try:
        result = compare_files(args.a, args.b, allow_runs=args.allow_runs)
    except (BenchmarkError, BadPath, OSError) as e:
        print(f"plumetrace.benchmark.compare: error: {e}", file=sys.stderr)
        return exit_status(e)
    print(format_comparison(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
