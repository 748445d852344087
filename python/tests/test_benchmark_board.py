"""The benchmark's leaderboard and comparison (python/plumetrace/benchmark/): each cell's figures
against hand values, the team rule, the score and its rank intervals, the separation of the
best and worst algorithms, the four outputs agreeing, and compare's verdicts and refusals.
Every case is built from a synthetic OUT/benchmark.json and runs.csv of known outcomes."""

import csv
import json
import os
import re
import subprocess
import sys

import pytest

from plumetrace.benchmark import compare, leaderboard
from plumetrace.benchmark.compare import compare_files
from plumetrace.benchmark.data import load_results
from plumetrace.benchmark.leaderboard import compute_board, write_leaderboard

COLUMNS = ("sweep,point,controller.algorithm,trial,agent,seed,config_hash,outcome,success,"
           "time_s,d_t,d_u,overhead,losses,odor_fraction,steps,wind_samples,t_first_odor,"
           "d_first_odor,declaration_error")


def robot(outcome="success", time=100.0, overhead=1.25, declaration_error=None):
    """One robot's row of runs.csv (the columns the leaderboard reads)."""
    return {"outcome": outcome, "time": time, "overhead": overhead if outcome == "success"
            else None, "declaration_error": declaration_error}


def win_if(ok, time=100.0):
    return robot("success", time) if ok else robot("timeout", 1200.0)


def write_results(folder, tasks, controllers, runs, outcome, suite="toy", version="1",
                  digest="00000000000000aa", task_digest=None):
    """OUT/benchmark.json and OUT/runs.csv: `tasks` [(name, robots, success rule)],
    `controllers` [(name, null model?)]; outcome(task, controller, trial, agent) gives a robot()
    row, or None for no row."""
    folder.mkdir(parents=True, exist_ok=True)
    lines = [COLUMNS]
    for task, robots, _ in tasks:
        for point, (controller, _) in enumerate(controllers):
            for trial in range(runs):
                for agent in range(robots):
                    r = outcome(task, controller, trial, agent)
                    if r is None:
                        continue
                    cells = lambda v: "" if v is None else repr(v)  # noqa: E731
                    lines.append(
                        f"{task},{point},{controller},{trial},{agent},7,abc,{r['outcome']},"
                        f"{int(r['outcome'] == 'success')},{r['time']!r},1,1,"
                        f"{cells(r['overhead'])},0,0.1,10,1,,,{cells(r['declaration_error'])}")
    (folder / "runs.csv").write_text("\n".join(lines) + "\n")
    manifest = {
        "plumetrace_benchmark": 1, "version": "0.7.0",
        "suite": {"name": suite, "version": version, "title": "a toy suite",
                  "file": "studies/benchmark/suite.toml", "digest": digest, "seed": 11,
                  "runs": runs,
                  "tasks": [{"name": t, "title": t, "why": "a test", "source": "none",
                             "success": rule, "robots": robots, "timeout": 1200.0,
                             "digest": (task_digest or {}).get(t, f"{i:016x}")}
                            for i, (t, robots, rule) in enumerate(tasks)]},
        "controllers": [{"name": c, "origin": "built-in", "file": None, "null_model": null}
                        for c, null in controllers],
        "runs_file": "runs.csv"}
    (folder / "benchmark.json").write_text(json.dumps(manifest, indent=1))
    return folder


def board_of(folder):
    return compute_board(load_results(folder))


def cell(board, task, controller):
    return next(c for c in board["cells"] if c["task"] == task and c["controller"] == controller)


def score(board, controller):
    return next(s for s in board["scores"] if s["controller"] == controller)


def run_module(module, *args):
    """`python3 -m module args` in a process of its own."""
    return subprocess.run([sys.executable, "-m", module, *map(str, args)], capture_output=True,
                          text=True, env=os.environ.copy(), timeout=300)


def run_main(capsys, main, *args):
    """A command's main(args) in this process (faster than run_module), as run_module reports."""
    capsys.readouterr()
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return subprocess.CompletedProcess(args, code, out, err)


ONE_TASK = [("laminar", 1, "reach")]


# -- each cell ----------------------------------------------------------------------------------

def test_cell_success_has_the_wilson_interval_of_hand_values(tmp_path):
    out = write_results(tmp_path, ONE_TASK, [("seven", False), ("none", False)], 10,
                        lambda t, c, trial, a: win_if(c == "seven" and trial < 7))
    board = board_of(out)
    seven, none = cell(board, "laminar", "seven"), cell(board, "laminar", "none")
    # Wilson 95% of 7/10: centre (0.7 + z^2/20) / (1 + z^2/10), by hand 0.3968 to 0.8922
    assert (seven["successes"], seven["runs"], seven["success_rate"]) == (7, 10, 0.7)
    assert seven["success_lo"] == pytest.approx(0.39677, abs=1e-4)
    assert seven["success_hi"] == pytest.approx(0.89222, abs=1e-4)
    # 0/10: the interval touches 0 and reaches z^2 / (n + z^2) = 0.2775
    assert none["success_lo"] == 0.0
    assert none["success_hi"] == pytest.approx(1.959963985 ** 2 / (10 + 1.959963985 ** 2), abs=1e-9)
    assert none["time"]["mean"] is None and none["time"]["n"] == 0


def test_time_and_overhead_are_means_of_the_successful_runs_with_intervals_inside_their_range(
        tmp_path):
    times = [100.0, 110.0, 130.0, 160.0]
    out = write_results(tmp_path, ONE_TASK, [("a", False)], 6, lambda t, c, trial, a: (
        robot("success", times[trial], 1.0 + 0.1 * trial) if trial < 4
        else robot("wall", 50.0)))
    c = cell(board_of(out), "laminar", "a")
    assert c["time"]["n"] == 4 and c["time"]["mean"] == pytest.approx(125.0)
    assert 100.0 <= c["time"]["lo"] < 125.0 < c["time"]["hi"] <= 160.0
    assert c["overhead"]["mean"] == pytest.approx(1.15)
    assert 1.0 <= c["overhead"]["lo"] < 1.15 < c["overhead"]["hi"] <= 1.3
    assert c["outcomes"] == {"success": 4, "wall": 2}


def test_overhead_leaves_out_successful_runs_where_it_is_undefined(tmp_path):
    out = write_results(tmp_path, ONE_TASK, [("a", False)], 3, lambda t, c, trial, a: (
        robot("success", 100.0, None if trial == 0 else 2.0)))
    c = cell(board_of(out), "laminar", "a")
    assert (c["time"]["n"], c["overhead"]["n"], c["overhead"]["mean"]) == (3, 2, 2.0)


def test_declarations_are_counted_with_their_mean_error(tmp_path):
    out = write_results(tmp_path, [("declare", 1, "declare")], [("a", False)], 4,
                        lambda t, c, trial, a: (
                            robot("success", 90.0, 1.1, 0.1) if trial == 0 else
                            robot("wrong_declaration", 80.0, None, 0.9) if trial == 1 else
                            robot("timeout", 1200.0)))
    c = cell(board_of(out), "declare", "a")
    assert (c["declarations"], c["successes"]) == (2, 1)
    assert c["declaration_error"] == pytest.approx(0.5)


def test_a_team_run_succeeds_when_any_robot_does_and_takes_the_earliest_success(tmp_path):
    def team(task, controller, trial, agent):
        if trial == 0:  # robot 0 times out, robot 2 reaches the source first
            return [robot("timeout", 1200.0), robot("success", 300.0, 1.5),
                    robot("success", 200.0, 1.2)][agent]
        if trial == 1:
            return robot("wall", 40.0 + agent)  # nobody succeeds
        return None if agent == 2 else robot("success", 10.0)  # a run lacking a robot's row

    out = write_results(tmp_path, [("team", 3, "reach")], [("hayes", False)], 3, team)
    board = board_of(out)
    c = cell(board, "team", "hayes")
    assert (c["runs"], c["successes"], c["missing"], c["partial_runs"]) == (2, 1, 1, 1)
    assert c["time"]["mean"] == 200.0 and c["overhead"]["mean"] == 1.2
    assert c["trials"] == "10-"
    # a team's outcomes count robots: 3 per run
    assert c["outcomes"] == {"success": 2, "timeout": 1, "wall": 3}
    assert board["missing"]["runs_lacking_a_robot"] == 1


# -- the score and the ranks --------------------------------------------------------------------

THREE_TASKS = [("a", 1, "reach"), ("b", 1, "reach"), ("c", 1, "reach")]
FIELD = [("ace", False), ("mid", False), ("poor", False), ("levy", True), ("crw", True)]


def field_outcome(task, controller, trial, agent):
    """ace always succeeds, mid half the time, levy (a null model) 2 in 5, poor 1 in 5, crw
    never."""
    wins = {"ace": True, "mid": trial % 2 == 0, "levy": trial % 5 < 2, "poor": trial % 5 == 0,
            "crw": False}
    return win_if(wins[controller], 100.0 + trial)


def test_the_score_is_the_mean_of_the_cells_success_rates(tmp_path):
    out = write_results(tmp_path, THREE_TASKS, [("x", False)], 20, lambda t, c, trial, a: (
        win_if(trial < {"a": 20, "b": 10, "c": 3}[t])))
    s = score(board_of(out), "x")
    assert s["score"] == pytest.approx((1.0 + 0.5 + 0.15) / 3, abs=1e-15)
    assert s["lo"] < s["score"] < s["hi"]


def test_a_controller_that_always_succeeds_ranks_first_with_rank_interval_1_to_1(tmp_path):
    board = board_of(write_results(tmp_path, THREE_TASKS, FIELD, 30, field_outcome))
    assert [s["controller"] for s in board["scores"]] == ["ace", "mid", "levy", "poor", "crw"]
    ace = score(board, "ace")
    assert (ace["score"], ace["lo"], ace["hi"]) == (1.0, 1.0, 1.0)
    assert (ace["rank"], ace["rank_lo"], ace["rank_hi"]) == (1, 1, 1)
    assert score(board, "mid")["rank"] == 2
    assert board["title"].startswith("toy v1: ace leads with 1.00 (1.00")


def test_the_null_models_rank_where_their_scores_put_them(tmp_path):
    board = board_of(write_results(tmp_path, THREE_TASKS, FIELD, 30, field_outcome))
    nulls = {n["controller"]: n for n in board["null_models"]}
    # levy (0.4) is above poor (0.2) only; crw (0) is last, with no doubt about it
    assert (nulls["levy"]["rank"], nulls["levy"]["above"], nulls["levy"]["of"]) == (3, ["poor"], 5)
    assert (nulls["crw"]["rank"], nulls["crw"]["rank_lo"], nulls["crw"]["rank_hi"]) == (5, 5, 5)
    assert nulls["crw"]["above"] == []
    assert "null models rank levy 3, crw 5 of 5" in board["title"]


def test_rank_intervals_widen_when_scores_are_within_noise(tmp_path):
    # 10 and 11 of 20, won on different trials: either may come first in a replicate
    out = write_results(tmp_path, ONE_TASK, [("p", False), ("q", False)], 20,
                        lambda t, c, trial, a: win_if(trial < 10 if c == "p" else 5 <= trial < 16))
    board = board_of(out)
    assert (score(board, "q")["rank"], score(board, "p")["rank"]) == (1, 2)
    for name in ("p", "q"):
        assert (score(board, name)["rank_lo"], score(board, name)["rank_hi"]) == (1, 2)


def test_paired_resampling_keeps_first_a_controller_better_run_for_run(tmp_path):
    # q wins every trial p wins, and one more (11 and 10 of 20): the same trials drawn for both,
    # q is never behind, though the two rates lie well within each other's intervals
    out = write_results(tmp_path, ONE_TASK, [("p", False), ("q", False)], 20,
                        lambda t, c, trial, a: win_if(trial < (10 if c == "p" else 11)))
    board = board_of(out)
    assert (score(board, "q")["rank_lo"], score(board, "q")["rank_hi"]) == (1, 1)
    assert (score(board, "p")["rank_lo"], score(board, "p")["rank_hi"]) == (1, 2)
    assert score(board, "p")["hi"] > score(board, "q")["lo"]


def test_equal_scores_share_a_rank_and_are_listed_by_name(tmp_path):
    out = write_results(tmp_path, ONE_TASK, [("zed", False), ("abe", False), ("low", False)], 10,
                        lambda t, c, trial, a: win_if(trial < (3 if c == "low" else 8)))
    board = board_of(out)
    assert [(s["controller"], s["rank"]) for s in board["scores"]] == [
        ("abe", 1), ("zed", 1), ("low", 3)]
    assert board["title"].startswith("toy v1: abe and zed lead with 0.80")


# -- separation ---------------------------------------------------------------------------------

def test_separation_counts_tasks_where_best_and_worst_differ_beyond_their_intervals(tmp_path):
    def outcome(task, controller, trial, agent):
        if controller == "crw":  # a null model far ahead everywhere: it must not count
            return robot("success", 5.0 + trial % 3)
        if task == "apart-in-success":
            return win_if(controller == "fast")
        if task == "apart-in-time":
            return robot("success", (100.0 if controller == "fast" else 300.0) + trial % 4)
        return win_if(trial % 2 == 0, 100.0 + trial % 4)  # "alike": the same for both

    tasks = [("apart-in-success", 1, "reach"), ("apart-in-time", 1, "reach"),
             ("alike", 1, "reach")]
    board = board_of(write_results(tmp_path, tasks, [("fast", False), ("slow", False),
                                                     ("crw", True)], 30, outcome))
    sep = board["separation"]
    assert (sep["assessed"], sep["separated"], sep["success_separated"],
            sep["time_separated"]) == (3, 2, 1, 1)
    by_task = {s["task"]: s for s in sep["tasks"]}
    s = by_task["apart-in-success"]
    assert (s["best"], s["worst"], s["success_separated"], s["time_separated"]) == (
        "fast", "slow", True, None)  # slow has no successful run: no time to compare
    assert s["success_difference"] == 1.0 and s["success_lo"] > 0.8
    t = by_task["apart-in-time"]
    assert (t["fastest"], t["slowest"], t["success_separated"], t["time_separated"]) == (
        "fast", "slow", False, True)
    assert t["time_difference"] == pytest.approx(200.0)
    assert t["time_lo"] > 190.0
    a = by_task["alike"]
    assert (a["success_separated"], a["time_separated"], a["separated"]) == (False, False, False)
    assert a["success_lo"] < 0.0 < a["success_hi"]
    assert "2 of 3 tasks separate the best and worst algorithms" in board["title"]


def test_separation_needs_two_non_null_controllers(tmp_path):
    board = board_of(write_results(tmp_path, ONE_TASK, [("only", False), ("crw", True)], 5,
                                   lambda t, c, trial, a: win_if(c == "only")))
    assert board["separation"]["assessed"] == 0
    assert board["separation"]["tasks"][0]["separated"] is None


# -- missing runs -------------------------------------------------------------------------------

def test_missing_runs_are_marked_and_an_empty_cell_shows_no_runs(tmp_path):
    def outcome(task, controller, trial, agent):
        if controller == "gappy" and task == "b":
            return None  # no runs at all
        if controller == "gappy" and trial >= 7:
            return None  # 7 of 10
        return win_if(trial % 2 == 0)

    out = write_results(tmp_path, [("a", 1, "reach"), ("b", 1, "reach")],
                        [("full", False), ("gappy", False)], 10, outcome)
    board = write_leaderboard(out)
    short, empty = cell(board, "a", "gappy"), cell(board, "b", "gappy")
    assert (short["runs"], short["missing"], short["trials"]) == (7, 3, "1010101---")
    assert (empty["runs"], empty["missing"], empty["success_rate"]) == (0, 10, None)
    assert score(board, "gappy")["score"] is None and score(board, "gappy")["rank"] is None
    assert score(board, "full")["rank"] == 1
    assert board["missing"] == {"cells_short": 1, "cells_empty": 1, "runs_missing": 13,
                                "runs_lacking_a_robot": 0, "rows_beyond_runs": 0}
    md = (out / "leaderboard.md").read_text()
    assert "| – | gappy | – | – | 0.57 (4/7\\*) | no runs |" in md
    assert "a x gappy: 7 of 10 runs" in md and "b x gappy: no runs" in md


def test_a_runs_file_without_rows_gives_a_page_of_empty_cells(tmp_path):
    out = write_results(tmp_path, ONE_TASK, [("a", False), ("b", True)], 5, lambda *_: None)
    board = write_leaderboard(out)
    assert board["title"] == "toy v1: no controller has runs on every task"
    assert all(s["rank"] is None for s in board["scores"])
    assert (out / "leaderboard.md").read_text().count("no runs") >= 2


def test_rows_of_trials_beyond_the_runs_asked_for_are_left_out(tmp_path):
    out = write_results(tmp_path, ONE_TASK, [("a", False)], 8,
                        lambda t, c, trial, a: win_if(trial < 4))
    manifest = json.loads((out / "benchmark.json").read_text())
    manifest["suite"]["runs"] = 4  # the store held 8 trials; this benchmark asked for 4
    (out / "benchmark.json").write_text(json.dumps(manifest))
    board = board_of(out)
    assert (cell(board, "laminar", "a")["runs"], cell(board, "laminar", "a")["successes"]) == (4, 4)
    assert board["missing"]["rows_beyond_runs"] == 4


# -- the four outputs ---------------------------------------------------------------------------

@pytest.fixture(scope="module")
def written(tmp_path_factory):
    tasks = [("laminar", 1, "reach"), ("team", 3, "reach")]
    out = write_results(tmp_path_factory.mktemp("board"), tasks, FIELD, 12, lambda t, c, trial, a:
                        field_outcome(t, c, trial, a) if a == 0 else robot("timeout", 1200.0))
    return out, write_leaderboard(out)


def test_the_page_holds_no_reference_outside_itself(written):
    out, _ = written
    page = (out / "leaderboard.html").read_text()
    assert "<script" not in page and "<link" not in page and "@import" not in page
    assert "http://" not in page and "https://" not in page and "url(" not in page
    assert re.findall(r'src="([^"]*)"', page) and all(
        s.startswith("data:image/png;base64,") for s in re.findall(r'src="([^"]*)"', page))
    assert all(h.startswith("#") for h in re.findall(r'href="([^"]*)"', page))
    assert len(re.findall(r"<img ", page)) == 4
    for name in ("heatmap", "scores", "time", "overhead"):
        assert (out / "figures" / f"{name}.png").stat().st_size > 1000


def test_md_csv_and_json_say_the_same(written):
    out, board = written
    on_disk = json.loads((out / "leaderboard.json").read_text())
    assert on_disk == board
    md = (out / "leaderboard.md").read_text()
    page = (out / "leaderboard.html").read_text()
    assert md.splitlines()[0] == "# " + board["title"]
    assert f"<h1>{board['title']}</h1>" in page
    rows = list(csv.DictReader((out / "leaderboard.csv").open()))
    assert len(rows) == len(board["cells"]) == 2 * len(FIELD)
    for row, c in zip(rows, board["cells"]):
        s = score(board, c["controller"])
        assert (row["task"], row["controller"]) == (c["task"], c["controller"])
        assert int(row["successes"]) == c["successes"] and int(row["runs"]) == c["runs"]
        assert float(row["success_lo"]) == c["success_lo"]
        assert row["time_mean"] == ("" if c["time"]["mean"] is None else repr(c["time"]["mean"]))
        assert float(row["score"]) == s["score"] and int(row["rank_hi"]) == s["rank_hi"]
    # the leaderboard table of the Markdown: one row per controller, in the json's order
    table = [line for line in md.splitlines() if re.match(r"\| (\d+|–) \| ", line)]
    assert len(table) == len(board["scores"])
    for line, s in zip(table, board["scores"]):
        cells = [x.strip() for x in line.strip("|").split("|")]
        assert cells[0] == str(s["rank"]) and cells[1].startswith(s["controller"])
        assert cells[2] == f"{s['score']:.2f} ({s['lo']:.2f}–{s['hi']:.2f})"
        for text, task in zip(cells[4:], ("laminar", "team")):
            c = cell(board, task, s["controller"])
            assert text == f"{c['success_rate']:.2f} ({c['successes']}/{c['runs']})"
    # the json carries the suite's identity and the manifest's controllers
    assert (board["suite"]["name"], board["suite"]["version"], board["suite"]["digest"]) == (
        "toy", "1", "00000000000000aa")
    assert [k["name"] for k in board["controllers"]] == [c for c, _ in FIELD]


def test_the_leaderboard_is_the_same_byte_for_byte_when_drawn_again(written, tmp_path):
    out, _ = written
    names = ["leaderboard.html", "leaderboard.md", "leaderboard.csv", "leaderboard.json",
             "figures/heatmap.png", "figures/time.png"]
    before = {n: (out / n).read_bytes() for n in names}
    write_leaderboard(out)
    assert {n: (out / n).read_bytes() for n in names} == before


# -- bad input ----------------------------------------------------------------------------------

def test_the_command_writes_the_pages_and_exits_0(tmp_path):
    out = write_results(tmp_path, ONE_TASK, [("a", False), ("b", False)], 4,
                        lambda t, c, trial, a: win_if(c == "a"))
    done = run_module("plumetrace.benchmark.leaderboard", out)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("toy v1: a leads with 1.00")
    assert "Warning" not in done.stderr
    assert (out / "leaderboard.html").is_file()


@pytest.mark.parametrize("edit, words", [
    (lambda m: m.pop("suite"), "suite: missing"),
    (lambda m: m["suite"].update(runs=0), "suite.runs: must be at least 1"),
    (lambda m: m["suite"]["tasks"].append(dict(m["suite"]["tasks"][0])),
     "suite.tasks[1].name: task 'laminar' is listed twice"),
    (lambda m: m["controllers"][0].update(null_model="no"), "controllers[0].null_model"),
    (lambda m: m["controllers"].clear(), "controllers: no controller"),
    (lambda m: m.update(plumetrace_benchmark=9), "not a plumetrace benchmark manifest"),
    (lambda m: m.update(runs_file="/etc/passwd"), "runs_file"),
])
def test_a_malformed_manifest_exits_2_naming_the_file_and_key(tmp_path, edit, words, capsys):
    out = write_results(tmp_path, ONE_TASK, [("a", False)], 2, lambda t, c, trial, a: win_if(1))
    manifest = json.loads((out / "benchmark.json").read_text())
    edit(manifest)
    (out / "benchmark.json").write_text(json.dumps(manifest))
    done = run_main(capsys, leaderboard.main, out)
    assert done.returncode == 2
    assert str(out / "benchmark.json") in done.stderr and words in done.stderr
    assert not (out / "leaderboard.html").exists()


@pytest.mark.parametrize("swap, words", [
    (("laminar,0,a,1,", "laminar,0,nobody,1,"), "line 3: controller 'nobody' is not among"),
    (("laminar,0,a,1,", "elsewhere,0,a,1,"), "line 3: task 'elsewhere' is not in the suite"),
    (("laminar,0,a,1,", "laminar,0,a,0,"), "line 3: a second row for task 'laminar'"),
    (("success,1,", "success,0,"), "does not match outcome"),
    (("controller.algorithm,", "algorithm,"), "no column controller.algorithm"),
])
def test_a_malformed_runs_file_exits_2_naming_the_line(tmp_path, swap, words, capsys):
    out = write_results(tmp_path, ONE_TASK, [("a", False)], 2, lambda t, c, trial, a: win_if(1))
    text = (out / "runs.csv").read_text()
    (out / "runs.csv").write_text(text.replace(*swap, 1))
    done = run_main(capsys, leaderboard.main, out)
    assert done.returncode == 2 and str(out / "runs.csv") in done.stderr
    assert words in done.stderr


def test_a_folder_without_a_manifest_exits_2_naming_it(tmp_path, capsys):
    done = run_main(capsys, leaderboard.main, tmp_path)
    assert done.returncode == 2 and str(tmp_path / "benchmark.json") in done.stderr


# -- compare ------------------------------------------------------------------------------------

def save_board(folder):
    """leaderboard.json of the results in `folder` (its numbers only: no pages)."""
    (folder / "leaderboard.json").write_text(json.dumps(board_of(folder)))
    return folder / "leaderboard.json"


def pair(tmp_path, changed=True, runs_b=30, digest_b="00000000000000aa", suite_b="toy",
         version_b="1", extra_b=()):
    """Results A and B of one suite; in B, mid wins 28 of 30 on task a (A: 15) in the same mean
    time, and ace takes 100 s longer on task b; everything else the same run for run."""
    def outcome_b(task, controller, trial, agent):
        if changed and task == "a" and controller == "mid":
            return win_if(trial < 28, 114.0)  # A's mean time: 100 + the even trials' mean
        if changed and task == "b" and controller == "ace":
            return robot("success", 200.0 + trial)
        if controller == "new":
            return win_if(True)
        return field_outcome(task, controller, trial, agent)

    tasks = THREE_TASKS
    a = save_board(write_results(tmp_path / "A", tasks, FIELD, 30, field_outcome))
    b = save_board(write_results(tmp_path / "B", tasks, FIELD + list(extra_b), runs_b,
                                 outcome_b, suite=suite_b, version=version_b, digest=digest_b))
    return a, b


def test_compare_flags_the_differences_made_and_no_other(tmp_path):
    a, b = pair(tmp_path)
    result = compare_files(a, b)
    assert result["relation"] == "same" and result["paired"]
    beyond = {(c["task"], c["controller"]): c for c in result["cells"]}
    mid = beyond[("a", "mid")]
    assert mid["success_difference"] == pytest.approx(28 / 30 - 15 / 30)
    assert mid["success_beyond_noise"] is True and mid["success_lo"] > 0
    ace = beyond[("b", "ace")]
    assert ace["success_beyond_noise"] is False
    assert ace["time_difference"] == pytest.approx(100.0) and ace["time_beyond_noise"] is True
    others = [c for k, c in beyond.items() if k not in (("a", "mid"), ("b", "ace"))]
    assert len(others) == 3 * 5 - 2
    assert not any(c["success_beyond_noise"] or c["time_beyond_noise"] for c in others)
    assert all(c["success_difference"] == 0.0 for c in others)
    scores = {s["controller"]: s for s in result["scores"]}
    assert scores["mid"]["beyond_noise"] is True
    assert scores["mid"]["difference"] == pytest.approx((28 / 30 - 15 / 30) / 3)
    # the same runs in both: the paired interval of the difference is exactly 0
    assert (scores["poor"]["lo"], scores["poor"]["hi"], scores["poor"]["beyond_noise"]) == (
        0.0, 0.0, False)
    assert result["beyond_noise"] == 3
    assert result["only_a"] == [] and result["only_b"] == []


def test_compare_finds_nothing_between_a_result_and_itself(tmp_path):
    a, _ = pair(tmp_path)
    result = compare_files(a, a.parent)  # a folder holding leaderboard.json is taken too
    assert result["beyond_noise"] == 0


def test_compare_lists_cells_in_one_file_only(tmp_path, capsys):
    a, b = pair(tmp_path, changed=False, extra_b=[("new", False)])
    result = compare_files(a, b)
    assert sorted(result["only_b"]) == [["a", "new"], ["b", "new"], ["c", "new"]]
    assert "new" not in {s["controller"] for s in result["scores"]}
    done = run_main(capsys, compare.main, a, b)
    assert done.returncode == 0 and "a, new: only in B" in done.stdout


def test_compare_prints_what_is_beyond_noise(tmp_path):
    a, b = pair(tmp_path)
    done = run_module("plumetrace.benchmark.compare", a, b)
    assert done.returncode == 0, done.stderr
    line = next(x for x in done.stdout.splitlines() if x.startswith("  a, mid:"))
    assert "success 0.50 -> 0.93" in line and "BEYOND NOISE" in line
    assert "3 difference(s) beyond noise." in done.stdout


@pytest.mark.parametrize("kwargs, words", [
    ({"digest_b": "00000000000000bb", "runs_b": 30}, "task(s)"),
    ({"suite_b": "other"}, "different suites: 'toy' and 'other'"),
    ({"version_b": "2"}, "different versions of suite 'toy': 1 and 2"),
])
def test_compare_refuses_other_suites_naming_both_files(tmp_path, kwargs, words, capsys):
    a, b = pair(tmp_path, **kwargs)
    if "digest_b" in kwargs:  # a changed task under the same version
        board = json.loads(b.read_text())
        board["suite"]["tasks"][0]["digest"] = "ffffffffffffffff"
        b.write_text(json.dumps(board))
    done = run_main(capsys, compare.main, a, b)
    assert done.returncode == 2 and done.stdout == ""
    assert str(a) in done.stderr and str(b) in done.stderr and words in done.stderr


def test_compare_says_same_tasks_other_run_counts_and_needs_allow_runs(tmp_path, capsys):
    a, b = pair(tmp_path, runs_b=20, digest_b="00000000000000cc")
    done = run_main(capsys, compare.main, a, b)
    assert done.returncode == 2 and str(a) in done.stderr and str(b) in done.stderr
    assert "same tasks, other run counts" in done.stderr and "--allow-runs" in done.stderr
    done = run_main(capsys, compare.main, a, b, "--allow-runs")
    assert done.returncode == 0, done.stderr
    result = compare_files(a, b, allow_runs=True)
    assert result["relation"] == "runs" and not result["paired"]


@pytest.mark.parametrize("content", ['{"plumetrace_leaderboard": 1}', "[1, 2]", "not json",
                                    '{"plumetrace_results": 1, "sweeps": []}'])
def test_compare_exits_2_naming_a_file_that_is_not_a_leaderboard(tmp_path, content, capsys):
    a, _ = pair(tmp_path, changed=False)
    bad = tmp_path / "bad.json"
    bad.write_text(content)
    done = run_main(capsys, compare.main, a, bad)
    assert done.returncode == 2 and str(bad) in done.stderr and str(a) not in done.stderr


def test_compare_exits_3_when_a_file_cannot_be_read(tmp_path, monkeypatch, capsys):
    from plumetrace.benchmark import data
    from plumetrace._files import BadPath

    a, b = pair(tmp_path, changed=False)

    def unreadable(path, what, max_bytes=0):
        raise BadPath(f"cannot read {what} '{path}': Permission denied")

    # why: the tests may run as root, who reads any file; the refusal is what is checked
    monkeypatch.setattr(data, "read_input", unreadable)
    monkeypatch.setattr(data.os, "access", lambda path, mode: False)
    assert compare.main([str(a), str(b)]) == 3
    assert str(a) in capsys.readouterr().err
