"""The multirobot study's report (docs/multirobot.md).

Reads OUT/runs.csv and OUT/results.json of `plumetrace study studies/multirobot` and, for each
wind, tabulates the team outcomes of 1 to 5 robots of each algorithm, with and without contacts:
the team's success (any robot reaches the source) with its Wilson 95% interval, the first
arrival's time, how many robots arrived and the distance each robot drove. Then it states from
the data, for each algorithm and wind, whether five robots find the source more often than one
and sooner, by the evidence library's directional test (m = 0) on Newcombe's interval of the
difference of success rates and on Welch's interval of the relative difference of the mean
first-arrival times; the page's title says what they found.
"""

from __future__ import annotations

import csv
import io
import json
import math
import sys
from pathlib import Path
from typing import Optional

from plumetrace import evidence
from plumetrace._files import MAX_RESULTS_BYTES, output_folder, read_input
from plumetrace.report.figures import _new_figure, _save
from plumetrace.report.page import (Fig, Para, Section, Table, _doc_link,
                                    study_report_main, write_pages)

ALGORITHM, COUNT, CONTACT = "controller.algorithm", "team.count", "team.contact"
COLORS = {"casting": "#4e79a7", "surge-spiral": "#f28e2b", "surge-cast": "#59a14f"}
# The statements give directions only ("more often", "sooner"), so m = 0, as the meander study
# (docs/meander.md, "How the report decides").
MIN_EFFECT = 0.0
# how a robot's run ended, in words
ENDS = {"success": "arrived", "wall": "met a wall", "timeout": "timed out",
        "gave_up": "gave up", "wrong_declaration": "declared a wrong source"}


class MultirobotReportError(Exception):
    """runs.csv or results.json is missing, unreadable or not from the multirobot study."""


class Teams:
    """The team outcomes of one point: one entry per trial."""

    def __init__(self) -> None:
        self.robots: dict = {}  # trial -> list of (agent, outcome, time, d_t)

    def add(self, trial: int, agent: int, outcome: str, time: float, d_t: float) -> None:
        self.robots.setdefault(trial, []).append((agent, outcome, time, d_t))

    @property
    def runs(self) -> int:
        return len(self.robots)

    def first_arrivals(self) -> list:
        """The first arrival's time (s) of every team in which a robot arrived."""
        out = []
        for robots in self.robots.values():
            times = [t for _, o, t, _ in robots if o == "success"]
            if times:
                out.append(min(times))
        return out

    @property
    def successes(self) -> int:
        return len(self.first_arrivals())

    def arrivals(self) -> float:
        """Mean number of robots that arrived, per team."""
        n = [sum(o == "success" for _, o, _, _ in r) for r in self.robots.values()]
        return sum(n) / len(n) if n else math.nan

    def outcomes(self) -> dict:
        """How many robots ended in each outcome, most frequent first."""
        counts: dict = {}
        for r in self.robots.values():
            for _, o, _, _ in r:
                counts[o] = counts.get(o, 0) + 1
        return dict(sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])))

    def distance_per_robot(self) -> float:
        d = [x for r in self.robots.values() for _, _, _, x in r]
        return sum(d) / len(d) if d else math.nan


def mean_sd(values: list) -> tuple:
    n = len(values)
    if n == 0:
        return (0, math.nan, math.nan)
    m = sum(values) / n
    sd = math.sqrt(sum((v - m) ** 2 for v in values) / (n - 1)) if n > 1 else math.nan
    return (n, m, sd)


def read_teams(out: Path) -> dict:
    """(sweep, algorithm, robots, contact) -> Teams, from runs.csv."""
    path = out / "runs.csv"
    try:
        text = read_input(path, "runs file", MAX_RESULTS_BYTES).decode("utf-8")
    except (OSError, ValueError) as e:
        raise MultirobotReportError(f"cannot read {path}: {e}") from e
    teams: dict = {}
    reader = csv.DictReader(io.StringIO(text))
    need = {"sweep", ALGORITHM, COUNT, CONTACT, "trial", "agent", "outcome", "time_s", "d_t"}
    if not need <= set(reader.fieldnames or ()):
        raise MultirobotReportError(f"{path} is not from the multirobot study: it lacks "
                                    f"{', '.join(sorted(need - set(reader.fieldnames or ())))}")
    for row in reader:
        key = (row["sweep"], row[ALGORITHM], int(row[COUNT]), row[CONTACT])
        teams.setdefault(key, Teams()).add(int(row["trial"]), int(row["agent"]), row["outcome"],
                                           float(row["time_s"]), float(row["d_t"]))
    return teams


def pct(v: float) -> str:
    return "n/a" if v is None or math.isnan(v) else f"{100 * v:.0f}%"


def success_cell(t: Teams) -> str:
    lo, hi = evidence.wilson_interval(t.successes, t.runs)
    return f"{t.successes}/{t.runs} [{pct(lo)}, {pct(hi)}]"


def time_cell(t: Teams) -> str:
    n, m, sd = mean_sd(t.first_arrivals())
    if n == 0:
        return "n/a"
    return f"{m:.0f} s" + (f" (sd {sd:.0f})" if n > 1 else "")


def panel(sweep: str, title: str, teams: dict, counts: list, algorithms: list,
          path: Path) -> Path:
    """Team success and first-arrival time against team size, contacts on (solid) and off."""
    fig = _new_figure(10, 3.8)
    a, b = fig.subplots(1, 2)
    for alg in algorithms:
        for contact, style in (("on", "-"), ("off", ":")):
            pts = [(c, teams.get((sweep, alg, c, contact))) for c in counts]
            pts = [(c, t) for c, t in pts if t and t.runs]
            if not pts:
                continue
            label = f"{alg}, contacts {contact}"
            rate = [t.successes / t.runs for _, t in pts]
            ci = [evidence.wilson_interval(t.successes, t.runs) for _, t in pts]
            xs = [c for c, _ in pts]
            a.plot(xs, rate, style, marker="o", color=COLORS.get(alg), label=label)
            if contact == "on":
                a.fill_between(xs, [lo for lo, _ in ci], [hi for _, hi in ci],
                               color=COLORS.get(alg), alpha=0.12, linewidth=0)
            times = [mean_sd(t.first_arrivals())[1] for _, t in pts]
            b.plot(xs, times, style, marker="o", color=COLORS.get(alg), label=label)
    a.set_xlabel("robots released together")
    a.set_ylabel("team success (a robot reaches the source)")
    a.set_ylim(-0.03, 1.03)
    a.set_xticks(counts)
    b.set_xlabel("robots released together")
    b.set_ylabel("first arrival, mean of successful teams (s)")
    b.set_xticks(counts)
    b.set_ylim(bottom=0)
    a.legend(fontsize=7, loc="lower right")
    fig.suptitle(title, fontsize=10)
    return _save(fig, path)


def compare(one: Teams, many: Teams) -> tuple:
    """(success verdict, time verdict, words) of many robots against one."""
    d = evidence.newcombe_difference(many.successes, many.runs, one.successes, one.runs)
    success = evidence.directional(d, MIN_EFFECT).verdict
    words = (f"success {one.successes}/{one.runs} with one robot, {many.successes}/{many.runs} "
             f"with {max(1, len(next(iter(many.robots.values()), [])))}; difference "
             f"[{pct(d[0])}, {pct(d[1])}]")
    a, b = mean_sd(many.first_arrivals()), mean_sd(one.first_arrivals())
    time = evidence.UNCLEAR
    if a[0] >= 2 and b[0] >= 2:
        rel = evidence.relative_difference(a, b, b)
        # sooner: the relative difference of the times is below 0
        time = evidence.directional(evidence.negate(rel), MIN_EFFECT).verdict
        words += (f"; first arrival {b[1]:.0f} s with one, {a[1]:.0f} s with more, relative "
                  f"difference [{100 * rel[0]:.1f}%, {100 * rel[1]:.1f}%]")
    return success, time, words


def build_report(out_dir) -> list:
    out = Path(out_dir)
    path = out / "results.json"
    try:
        results = json.loads(read_input(path, "results file", MAX_RESULTS_BYTES).decode("utf-8"))
    except (OSError, ValueError) as e:
        raise MultirobotReportError(f"cannot read {path}: {e}") from e
    teams = read_teams(out)
    fig_dir = output_folder(out / "figures", "the report's figures")
    sections, more_often, sooner, not_more, failing = [], [], [], [], []
    for sweep in results.get("sweeps", []):
        name, title = sweep["name"], sweep.get("title", sweep["name"])
        wind = "meandering" if "meander" in title.lower() else "laminar"
        algorithms = sorted({k[1] for k in teams if k[0] == name},
                            key=lambda a: list(COLORS).index(a) if a in COLORS else 99)
        counts = sorted({k[2] for k in teams if k[0] == name})
        if not counts:
            continue
        png = panel(name, title, teams, counts, algorithms, fig_dir / f"multirobot_{name}.png")
        blocks = [Fig(path=png, rel=png.relative_to(out).as_posix(),
                      caption=f"{title}: the team's success (Wilson 95% band, contacts on) and "
                              "the mean time of its first arrival against the number of robots; "
                              "solid: contacts on, dotted: off.",
                      alt=f"two panels for sweep {name}")]
        rows = []
        for alg in algorithms:
            for contact in ("on", "off"):
                for c in counts:
                    t = teams.get((name, alg, c, contact))
                    if not t:
                        continue
                    rows.append([alg, contact, str(c), success_cell(t), time_cell(t),
                                 f"{t.arrivals():.2f}", f"{t.distance_per_robot():.2f} m"])
        blocks.append(Table(header=["algorithm", "contacts", "robots",
                                    "team success [Wilson 95%]", "first arrival",
                                    "robots arrived", "distance per robot"], rows=rows))
        said = []
        for alg in algorithms:
            one = teams.get((name, alg, counts[0], "on"))
            many = teams.get((name, alg, counts[-1], "on"))
            if not one or not many:
                continue
            success, time, words = compare(one, many)
            if success == evidence.YES:
                more_often.append(f"{alg} ({wind})")
            elif success == evidence.NO:
                not_more.append(f"{alg} ({wind})")
            if time == evidence.YES:
                sooner.append(f"{alg} ({wind})")
            said.append(f"{alg}: {counts[-1]} robots find the source more often than one: "
                        f"{success}; sooner: {time} ({words}).")
            # why: a team of any size that mostly fails is a finding; say how its robots ended
            if evidence.wilson_interval(many.successes, many.runs)[1] < 0.5:
                failing.append(f"{alg} ({wind})")
                ends = many.outcomes()
                total = sum(ends.values())
                said.append(f"{alg} fails in {wind} wind whatever the team: of the "
                            f"{total} robots of its {counts[-1]}-robot teams, " +
                            ", ".join(f"{n} {ENDS.get(o, o)}" for o, n in ends.items()) + ".")
        blocks.insert(0, Para([" ".join(said)]))
        sections.append(Section(anchor=f"sweep-{name}", title=f"{name}: {title}", blocks=blocks))
    findings = []
    if more_often:
        findings.append("more robots find the source more often for " + ", ".join(more_often))
    if sooner:
        findings.append("sooner for " + ", ".join(sooner))
    if failing:
        findings.append("teams of any size fail for " + ", ".join(failing))
    if not more_often and not sooner:
        findings.append("more robots neither find the source clearly more often nor sooner")
    title = "Several robots on one plume: " + "; ".join(findings)
    intro = [Para(["Lochmatter & Martinoli asked next what several robots gain in one plume "
                   "(\u201cUnderstanding the potential impact of multiple robots in odor source "
                   "localization\u201d, DARS 2008). This study releases 1 to 5 robots of each "
                   "of the paper's algorithms together at its start, on a line across the wind "
                   "0.3 m apart, with and without contacts between their bodies, in laminar and "
                   "in strong meandering wind. A team succeeds when any robot reaches the "
                   "source. Each verdict compares five robots with one by the directional test "
                   "with m = 0: \u201cyes\u201d when the 95% interval of the difference lies "
                   "above 0, \u201cno\u201d when below, else \u201cunclear\u201d. The study: ",
                   _doc_link(out, "docs/multirobot.md"), "; teams: ",
                   _doc_link(out, "docs/agents.md"), "."])]
    return write_pages(out, title, intro, sections)


def main(argv: Optional[list] = None) -> int:
    return study_report_main(argv, build_report, (MultirobotReportError,), "report.py", "multirobot report")


if __name__ == "__main__":
    sys.exit(main())
