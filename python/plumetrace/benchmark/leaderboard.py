"""The leaderboard of a benchmark's results.

    python3 -m plumetrace.benchmark.leaderboard OUT

reads OUT/benchmark.json (the manifest `plumetrace benchmark` writes) and the runs file it names
(OUT/runs.csv), and writes OUT/leaderboard.html (self-contained: figures inlined, no scripts, no
links out), OUT/leaderboard.md, OUT/leaderboard.csv (one row per cell: task x controller),
OUT/leaderboard.json (everything: the suite's identity, every cell, the scores and ranks, the
separation) and OUT/figures/{heatmap,scores,time,overhead}.png. Exit status 0, 2 for a missing
or malformed input (named), 3 when a file cannot be read or written.

What each figure means, the score and its intervals: docs/benchmark.md, "Leaderboard" and
"Score". Pure Python (numpy, matplotlib); no C++ module.
"""

from __future__ import annotations

import csv
import io
import json
import math
import sys
from typing import Optional, Sequence

import numpy as np

from .._files import BadPath, exit_status, output_folder, write_whole
from ..report.page import Bullets, Fig, Para, Section, Table, render_html, render_markdown
from ..report.wording import counted, verb
from . import figures
from .data import BenchmarkError, Results, load_results
from .stats import (BOOTSTRAP_REPS, BOOTSTRAP_SEED, cell_figures, paired_scores, percentile,
                    ranks, separation, trial_matrix)

__all__ = ["BOARD_FORMAT", "CSV_COLUMNS", "compute_board", "main", "write_leaderboard"]

BOARD_FORMAT = 1
DASH = "\u2013"
CSV_COLUMNS = ("task", "controller", "null_model", "runs", "expected", "missing", "successes",
               "success_rate", "success_lo", "success_hi", "time_n", "time_mean", "time_lo",
               "time_hi", "overhead_n", "overhead_mean", "overhead_lo", "overhead_hi",
               "declarations", "declaration_error", "score", "score_lo", "score_hi", "rank",
               "rank_lo", "rank_hi")


# --- the figures ---------------------------------------------------------------------------

def _mean_or_none(values: Sequence[float]) -> Optional[float]:
    return math.fsum(values) / len(values) if values else None


def _whole(v: float) -> Optional[int]:
    return None if math.isnan(v) else int(v)


def _scores(results: Results, cells: dict) -> list:
    """Each controller's score, its bootstrap interval, rank and rank interval, in the
    leaderboard's order: ranked by score (ties share a rank and are listed by name), then those
    with a task without runs (no score)."""
    tasks = [t["name"] for t in results.tasks]
    names = [k["name"] for k in results.controllers]
    null = {k["name"] for k in results.controllers if k["null_model"]}
    scored = [c for c in names if all(cells[(t, c)]["runs"] > 0 for t in tasks)]
    point = {c: _mean_or_none([cells[(t, c)]["success_rate"] for t in tasks]) for c in scored}
    replicates = np.zeros((0, BOOTSTRAP_REPS))
    if scored:
        matrices = [trial_matrix([cells[(t, c)]["trials"] for c in scored]) for t in tasks]
        replicates = paired_scores(tasks, matrices)
    rank_reps = ranks(replicates)
    point_ranks = ranks(np.array([point[c] for c in scored]))
    out = []
    for i, c in enumerate(scored):
        out.append({"controller": c, "null_model": c in null, "score": point[c],
                    "lo": percentile(replicates[i], 0.025), "hi": percentile(replicates[i], 0.975),
                    "rank": int(point_ranks[i]),
                    "rank_lo": _whole(percentile(rank_reps[i], 0.025)),
                    "rank_hi": _whole(percentile(rank_reps[i], 0.975)),
                    "complete": all(cells[(t, c)]["missing"] == 0 for t in tasks)})
    out.sort(key=lambda s: (s["rank"], s["controller"]))
    for c in sorted(set(names) - set(scored)):
        out.append({"controller": c, "null_model": c in null, "score": None, "lo": None,
                    "hi": None, "rank": None, "rank_lo": None, "rank_hi": None,
                    "complete": False})
    return out


def _null_models(scores: list) -> list:
    ranked = [s for s in scores if s["rank"] is not None]
    out = []
    for s in scores:
        if not s["null_model"]:
            continue
        above = [o["controller"] for o in ranked if not o["null_model"] and s["rank"] is not None
                 and o["score"] < s["score"] - 1e-9]
        out.append({"controller": s["controller"], "rank": s["rank"], "rank_lo": s["rank_lo"],
                    "rank_hi": s["rank_hi"], "of": len(ranked), "score": s["score"],
                    "above": above})
    return out


def compute_board(results: Results) -> dict:
    """The leaderboard (what leaderboard.json holds) of checked results."""
    suite = results.suite
    runs = suite["runs"]
    tasks = [t["name"] for t in results.tasks]
    names = [k["name"] for k in results.controllers]
    cells = {}
    for t in tasks:
        for c in names:
            cell = cell_figures(t, c, results.runs.get((t, c), {}), runs)
            cell["partial_runs"] = results.partial.get((t, c), 0)
            cells[(t, c)] = cell
    scores = _scores(results, cells)
    order = [s["controller"] for s in scores]
    null = {k["name"] for k in results.controllers if k["null_model"]}
    per_task = [separation({c: cells[(t, c)] for c in names}, order, null, t) for t in tasks]
    assessed = [s for s in per_task if s["separated"] is not None]
    board = {
        "plumetrace_leaderboard": BOARD_FORMAT,
        "title": "",
        "suite": {key: suite.get(key) for key in ("name", "version", "title", "file", "digest",
                                                  "seed", "runs")},
        "plumetrace_version": results.manifest["version"],
        "controllers": results.controllers,
        "bootstrap": {"replicates": BOOTSTRAP_REPS, "seed": BOOTSTRAP_SEED,
                      "resampling": "trials within each task, the same for every controller"},
        "scores": scores,
        "null_models": _null_models(scores),
        "separation": {"tasks": per_task, "assessed": len(assessed),
                       "success_separated": sum(bool(s["success_separated"]) for s in assessed),
                       "time_separated": sum(bool(s["time_separated"]) for s in assessed),
                       "separated": sum(s["separated"] for s in assessed)},
        "missing": {"cells_short": sum(0 < c["runs"] < runs for c in cells.values()),
                    "cells_empty": sum(c["runs"] == 0 for c in cells.values()),
                    "runs_missing": sum(c["missing"] for c in cells.values()),
                    "runs_lacking_a_robot": sum(results.partial.values()),
                    "rows_beyond_runs": results.beyond},
        "cells": [cells[(t, c)] for t in tasks for c in order],
    }
    board["suite"]["tasks"] = [{key: t.get(key) for key in ("name", "title", "why", "source",
                                                           "success", "robots", "timeout",
                                                           "digest")} for t in results.tasks]
    board["title"] = board_title(board)
    return _no_nan(board)


def _no_nan(v):
    """`v` with every NaN float as None (JSON has no NaN)."""
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, dict):
        return {k: _no_nan(x) for k, x in v.items()}
    if isinstance(v, list):
        return [_no_nan(x) for x in v]
    return v


# --- the words -----------------------------------------------------------------------------

def _num(v: Optional[float], digits: int = 2) -> str:
    return DASH if v is None else f"{v:.{digits}f}"


def _interval(mean, lo, hi, digits: int = 2) -> str:
    if mean is None:
        return DASH
    if lo is None:
        return _num(mean, digits)
    return f"{_num(mean, digits)} ({_num(lo, digits)}{DASH}{_num(hi, digits)})"


def _rank_range(s: dict) -> str:
    if s["rank"] is None:
        return DASH
    return str(s["rank_lo"]) if s["rank_lo"] == s["rank_hi"] else \
        f"{s['rank_lo']}{DASH}{s['rank_hi']}"


def _names(names: Sequence[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def board_title(board: dict) -> str:
    """What the data say: who leads with what score, how many tasks separate the algorithms,
    where the null models rank."""
    suite = board["suite"]
    head = f"{suite['name']} v{suite['version']}"
    ranked = [s for s in board["scores"] if s["rank"] is not None]
    if not ranked:
        return f"{head}: no controller has runs on every task"
    leaders = [s for s in ranked if s["rank"] == 1]
    lead = leaders[0]
    ranks = _rank_range(lead)
    parts = [f"{_names([s['controller'] for s in leaders])} "
             f"{verb(len(leaders), 'leads', 'lead')} with "
             f"{_interval(lead['score'], lead['lo'], lead['hi'])}"
             + (f", rank {ranks}" if ranks != "1" else "")]
    sep = board["separation"]
    if sep["assessed"]:
        parts.append(f"{counted(sep['separated'], sep['assessed'], 'task', 'tasks')} "
                     f"{verb(sep['separated'], 'separates', 'separate')} the best and worst "
                     "algorithms")
    nulls = [n for n in board["null_models"] if n["rank"] is not None]
    if nulls:
        where = ", ".join(f"{n['controller']} {n['rank']}" for n in nulls)
        parts.append(f"null models rank {where} of {nulls[0]['of']}")
    return f"{head}: " + "; ".join(parts)


def _sentence(text: str) -> str:
    """`text` ended by a full stop (unless it ends in one, ! or ?) and a space."""
    text = text.strip()
    return text + (" " if text.endswith((".", "!", "?")) else ". ")


def _difference(d, lo, hi, digits: int) -> str:
    """A difference (here never below 0) with its interval, which may reach below: "0.23
    (-0.01 to 0.44)"."""
    if d is None:
        return DASH
    ends = "" if lo is None else f" ({lo:.{digits}f} to {hi:.{digits}f})"
    return f"{d:.{digits}f}{ends}"


def _cell_text(c: dict) -> str:
    if c["runs"] == 0:
        return "no runs"
    mark = "*" if c["missing"] else ""
    return f"{c['success_rate']:.2f} ({c['successes']}/{c['runs']}{mark})"


def _what(s: dict) -> str:
    return f"{s['controller']} (null model)" if s["null_model"] else s["controller"]


def _separation_blocks(board: dict) -> list:
    sep = board["separation"]
    blocks = []
    if sep["assessed"]:
        blocks.append(Para([
            f"On {counted(sep['separated'], sep['assessed'], 'task', 'tasks')} the best and the "
            f"worst non-null algorithms differ beyond their 95% intervals: "
            f"{sep['success_separated']} in success (Newcombe's interval of the difference "
            f"excludes 0), {sep['time_separated']} in mean time to source (the bootstrap "
            "interval of the difference of the fastest and slowest excludes 0)."]))
    else:
        blocks.append(Para(["No task has two non-null algorithms with runs to compare."]))
    def yes_no(v):
        return DASH if v is None else "yes" if v else "no"

    rows = []
    for s in sep["tasks"]:
        if s["separated"] is None:
            rows.append([s["task"]] + [DASH] * 8 + ["not assessed"])
            continue
        rows.append([s["task"], s["best"], s["worst"],
                     _difference(s["success_difference"], s["success_lo"], s["success_hi"], 2),
                     yes_no(s["success_separated"]), s["fastest"] or DASH,
                     s["slowest"] or DASH,
                     _difference(s["time_difference"], s["time_lo"], s["time_hi"], 1),
                     yes_no(s["time_separated"]), yes_no(s["separated"])])
    blocks.append(Table(["task", "best", "worst", "success difference (95%)", "apart",
                         "fastest", "slowest", "time difference, s (95%)", "apart",
                         "separated"], rows))
    items = []
    for n in board["null_models"]:
        if n["rank"] is None:
            items.append([f"{n['controller']}: not ranked (a task without runs)."])
            continue
        above = (f"above {_names(n['above'])}" if n["above"]
                 else "above no non-null algorithm")
        items.append([f"{n['controller']} ranks {n['rank']} of {n['of']} "
                      f"(95% interval {n['rank_lo']}{DASH}{n['rank_hi']}), score "
                      f"{_num(n['score'])}, {above}."])
    if items:
        blocks += [Para(["Where the null models (random walks) rank:"]), Bullets(items)]
    return blocks


def _task_section(board: dict, task: dict) -> Section:
    cells = {c["controller"]: c for c in board["cells"] if c["task"] == task["name"]}
    rows = []
    for s in board["scores"]:
        c = cells[s["controller"]]
        if c["runs"] == 0:
            rows.append([_what(s), "no runs", DASH, DASH, DASH, DASH, DASH])
            continue
        missing = f" ({c['missing']} missing)" if c["missing"] else ""
        decl = (f"{c['declarations']}, error {_num(c['declaration_error'])} m"
                if c["declarations"] else "0")
        outcomes = ", ".join(f"{k} {v}" for k, v in c["outcomes"].items())
        rows.append([_what(s), f"{c['successes']}/{c['runs']}{missing}",
                     f"{_num(c['success_rate'])} ({_num(c['success_lo'])}{DASH}"
                     f"{_num(c['success_hi'])})",
                     _interval(c["time"]["mean"], c["time"]["lo"], c["time"]["hi"], 1),
                     _interval(c["overhead"]["mean"], c["overhead"]["lo"], c["overhead"]["hi"]),
                     decl, outcomes])
    about = [_sentence(task.get("title") or task["name"])]
    if task.get("why"):
        about.append(_sentence(f"Why: {task['why']}"))
    if task.get("source"):
        about.append(_sentence(f"Source: {task['source']}"))
    robots = "1 robot" if task["robots"] == 1 else f"a team of {task['robots']} robots"
    about.append(f"Success: {task['success']}; {robots}; digest ")
    about.append(("code", task["digest"]))
    return Section(f"task-{task['name']}", f"Task {task['name']}", [
        Para(about),
        Table(["controller", "successes", "success rate (Wilson 95%)",
               "time to source, s (95%)", "overhead d_t/d_u (95%)", "declarations",
               "robot outcomes"], rows)], level=3)


def document(board: dict, fig_paths: dict) -> tuple:
    """(title, intro, sections) of the page, from the board and its figures {name: Fig}."""
    suite = board["suite"]
    tasks = [t["name"] for t in suite["tasks"]]
    intro = [Para([f"Suite {suite['name']} version {suite['version']}"
                   + (f" ({suite['title']})" if suite.get("title") else "") + ", digest ",
                   ("code", suite["digest"]),
                   f"; {suite['runs']} runs per cell, seed {suite['seed']}; plumetrace "
                   f"{board['plumetrace_version']}. Each figure's definition: ",
                   ("code", "docs/benchmark.md"), "."])]
    header = ["rank", "controller", "score (95%)", "rank (95%)"] + tasks
    rows = []
    for s in board["scores"]:
        cells = {c["task"]: c for c in board["cells"] if c["controller"] == s["controller"]}
        rows.append([DASH if s["rank"] is None else str(s["rank"]), _what(s),
                     _interval(s["score"], s["lo"], s["hi"]), _rank_range(s)]
                    + [_cell_text(cells[t]) for t in tasks])
    board_blocks = [
        Para(["Score: the mean over tasks of the success rate (each task weighs the same), with "
              f"its 95% bootstrap interval ({board['bootstrap']['replicates']} replicates "
              "resampling trials within each task, the same trials for every controller); rank "
              "(95%): the 2.5 to 97.5 percentiles of the rank over the same replicates. Equal "
              "scores share a rank. Cells: success rate (successes/runs); * runs missing."]),
        Table(header, rows),
        fig_paths["heatmap"], fig_paths["scores"]]
    missing = board["missing"]
    sections = [Section("leaderboard", "Leaderboard", board_blocks),
                Section("separation", "Separation", _separation_blocks(board)),
                Section("tasks", "Tasks", [
                    Para(["Per task and controller: success with its Wilson 95% interval; mean "
                          "time to source and mean distance overhead over the successful runs, "
                          "each with its percentile bootstrap 95% interval; declarations and "
                          "their mean error; how the robots' runs ended."]),
                    fig_paths["time"], fig_paths["overhead"]])]
    sections += [_task_section(board, t) for t in suite["tasks"]]
    if any(missing.values()):
        short = [c for c in board["cells"] if c["missing"]]
        items = [[f"{c['task']} x {c['controller']}: "
                  + ("no runs" if c["runs"] == 0 else f"{c['runs']} of {c['expected']} runs")
                  + (f" ({c['partial_runs']} lacking a robot's row)" if c["partial_runs"]
                     else "")] for c in short]
        if missing["rows_beyond_runs"]:
            items.append([f"{missing['rows_beyond_runs']} rows of trials beyond "
                          f"{suite['runs']} runs per cell were left out."])
        sections.append(Section("missing", "Missing runs", [
            Para(["These cells have fewer runs than the suite asks for; their figures use the "
                  "runs present, and a controller with a cell of no runs has no score."]),
            Bullets(items)]))
    controllers = [[k["name"], k.get("origin") or DASH, k.get("file") or DASH,
                    "yes" if k["null_model"] else "no"] for k in board["controllers"]]
    digests = [[t["name"], t.get("success") or DASH, str(t.get("robots")), t["digest"]]
               for t in suite["tasks"]]
    sections.append(Section("suite", "Suite and controllers", [
        Table(["controller", "origin", "file", "null model"], controllers),
        Table(["task", "success", "robots", "digest"], digests)]))
    return board["title"], intro, sections


# --- the files -----------------------------------------------------------------------------

def _csv_value(v) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "1" if v else "0"
    return repr(v) if isinstance(v, float) else str(v)


def render_csv(board: dict) -> str:
    """leaderboard.csv: one row per cell, with its controller's score and rank."""
    scores = {s["controller"]: s for s in board["scores"]}
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CSV_COLUMNS)
    for c in board["cells"]:
        s = scores[c["controller"]]
        w.writerow([_csv_value(v) for v in (
            c["task"], c["controller"], s["null_model"], c["runs"], c["expected"], c["missing"],
            c["successes"], c["success_rate"], c["success_lo"], c["success_hi"],
            c["time"]["n"], c["time"]["mean"], c["time"]["lo"], c["time"]["hi"],
            c["overhead"]["n"], c["overhead"]["mean"], c["overhead"]["lo"], c["overhead"]["hi"],
            c["declarations"], c["declaration_error"], s["score"], s["lo"], s["hi"], s["rank"],
            s["rank_lo"], s["rank_hi"])])
    return buf.getvalue()


def write_leaderboard(out) -> dict:
    """Writes the leaderboard of the results folder `out` (leaderboard.html, .md, .csv, .json
    and figures/*.png in it); returns what leaderboard.json holds. Raises BenchmarkError (bad
    input, the file named) or an OSError (a file that cannot be read or written)."""
    results = load_results(out)
    board = compute_board(results)
    folder = results.path.parent
    fig_dir = output_folder(folder / "figures", "the leaderboard's figures")
    drawn = {
        "heatmap": (figures.heat_map(fig_dir / "heatmap.png", board),
                    "Success rate per controller and task (successes/runs)."),
        "scores": (figures.score_figure(fig_dir / "scores.png", board),
                   "Score (mean success rate over tasks) with its 95% paired bootstrap "
                   "interval; rank with its 95% interval."),
        "time": (figures.metric_panels(fig_dir / "time.png", board, "time",
                                       "time to source (s)"),
                 "Mean time to source of the successful runs, bootstrap 95% interval."),
        "overhead": (figures.metric_panels(fig_dir / "overhead.png", board, "overhead",
                                           "distance overhead d_t/d_u"),
                     "Mean distance overhead of the successful runs, bootstrap 95% interval."),
    }
    figs = {name: Fig(path=p, rel=p.relative_to(folder).as_posix(), caption=cap, alt=cap)
            for name, (p, cap) in drawn.items()}
    title, intro, sections = document(board, figs)
    write_whole(folder / "leaderboard.json",
                json.dumps(board, indent=1, allow_nan=False, ensure_ascii=False) + "\n")
    write_whole(folder / "leaderboard.csv", render_csv(board))
    write_whole(folder / "leaderboard.md", render_markdown(title, intro, sections))
    write_whole(folder / "leaderboard.html", render_html(title, intro, sections))
    return board


def main(argv: Optional[Sequence[str]] = None) -> int:
    """The command line: OUT; exit 0, 2 (bad input) or 3 (a file cannot be read or written)."""
    import argparse

    parser = argparse.ArgumentParser(
        prog="python3 -m plumetrace.benchmark.leaderboard",
        description="Write OUT/leaderboard.{html,md,csv,json} and OUT/figures/ from a "
                    "benchmark's OUT/benchmark.json and runs.csv.")
    parser.add_argument("out", metavar="OUT", help="the benchmark's output folder")
    args = parser.parse_args(argv)
    try:
        board = write_leaderboard(args.out)
    except (BenchmarkError, BadPath, OSError) as e:
        print(f"plumetrace.benchmark.leaderboard: error: {e}", file=sys.stderr)
        return exit_status(e)
    print(board["title"])
    print(f"wrote leaderboard.html, .md, .csv, .json and figures/ in {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
