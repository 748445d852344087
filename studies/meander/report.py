"""The meander study's report: "Beyond the paper" (docs/meander.md).

Reads OUT/results.json of `plumetrace study studies/meander` and draws, for each sweep, the two
panels of the paper (success rate and distance overhead) against meander strength, one line per
value of the sweep's other axis; then states from the data which algorithm degrades least and
whether a larger d_lost hurts in meander, each by the evidence library's directional test on
Newcombe's interval of a difference of success rates (plumetrace.evidence; docs/meander.md).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

from plumetrace import evidence
from plumetrace._files import MAX_RESULTS_BYTES, output_folder, read_input

from plumetrace.report.figures import _new_figure, _save
from plumetrace.report.page import (Fig, Para, Section, Table, _doc_link,
                                    study_report_main, write_pages)
from plumetrace.report.wording import change, difference, points

STRENGTH_KEY = "meander.gain"
# the strength axis's key in results of sweeps written before it was renamed (until the next
# version, as the core accepts the old name)
OLD_STRENGTH_KEY = "wind.meander_gain"
COLORS = ("#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2", "#b07aa1")
# The smallest difference of success rates the statements need: they state directions only
# ("degrades least", "hurts", "helps"), so m = 0, where the single-threshold rule and the rule
# of 0.3.0 agree (docs/meander.md, "How the report decides").
MIN_EFFECT = 0.0


class MeanderReportError(Exception):
    """results.json is missing, unreadable or not from the meander study."""


class Curve:
    """One line of a panel: the points of one value of the sweep's other axis, by strength."""

    def __init__(self, label: str):
        self.label = label
        self.failures: list = []  # per point: counts of walls, timeouts and gave_up
        self.x: list = []
        self.successes: list = []
        self.rate: list = []
        self.lo: list = []
        self.hi: list = []
        self.runs: list = []
        self.overhead: list = []
        self.oh_lo: list = []
        self.oh_hi: list = []

    def add(self, x: float, stats: dict) -> None:
        oh = stats.get("overhead") or {}
        self.x.append(x)
        self.successes.append(stats["successes"])
        self.rate.append(stats["success_rate"])
        self.lo.append(stats["success_lo"])
        self.hi.append(stats["success_hi"])
        self.runs.append(stats["runs"])
        self.failures.append({k: stats.get(k, 0) for k in ("walls", "timeouts", "gave_up")})
        self.overhead.append(oh.get("mean"))
        # the percentile bootstrap interval (docs/experiments.md): never below 1, as an overhead
        self.oh_lo.append(oh.get("boot_lo"))
        self.oh_hi.append(oh.get("boot_hi"))


def curves(sweep: dict) -> tuple:
    """(label of the other axis, its key, [Curve]) of a sweep with a strength axis."""
    keys = [STRENGTH_KEY if a["key"] == OLD_STRENGTH_KEY else a["key"] for a in sweep["axes"]]
    if STRENGTH_KEY not in keys or len(keys) != 2:
        raise MeanderReportError(f"sweep {sweep['name']}: needs two axes, one of them "
                                 f"{STRENGTH_KEY} (has {', '.join(keys)})")
    s = keys.index(STRENGTH_KEY)
    o = 1 - s
    by_value: dict = {}
    for p in sweep["points"]:
        value = p["values"][o]
        by_value.setdefault(str(value), Curve(str(value))).add(float(p["values"][s]), p["stats"])
    for c in by_value.values():
        order = sorted(range(len(c.x)), key=lambda i: c.x[i])
        for name in ("x", "successes", "rate", "lo", "hi", "runs", "overhead", "oh_lo", "oh_hi",
                     "failures"):
            setattr(c, name, [getattr(c, name)[i] for i in order])
    axis = sweep["axes"][o]
    return axis.get("label") or axis["key"], axis["key"], list(by_value.values())


def panels(sweep: dict, label: str, lines: list, path: Path) -> Path:
    fig = _new_figure(9.0, 3.4)
    ax_s, ax_o = fig.subplots(1, 2)
    for k, c in enumerate(lines):
        color = COLORS[k % len(COLORS)]
        err = [[r - lo for r, lo in zip(c.rate, c.lo)], [hi - r for r, hi in zip(c.rate, c.hi)]]
        ax_s.errorbar(c.x, c.rate, yerr=err, color=color, marker="o", ms=3, capsize=2,
                      label=c.label)
        # every mean, with its interval where there is one (two successful runs or more)
        pts = [(x, m, lo, hi) for x, m, lo, hi in zip(c.x, c.overhead, c.oh_lo, c.oh_hi)
               if m is not None]
        if pts:
            err = [[0.0 if lo is None else m - lo for _, m, lo, _ in pts],
                   [0.0 if hi is None else hi - m for _, m, _, hi in pts]]
            ax_o.errorbar([p[0] for p in pts], [p[1] for p in pts], yerr=err, color=color,
                          marker="o", ms=3, capsize=2)
    ax_s.set_ylim(0, 1.05)
    ax_s.set_xlabel("meander strength: boundary noise gain")
    ax_s.set_ylabel("success rate (95% Wilson CI)")
    ax_o.set_xlabel("meander strength: boundary noise gain")
    ax_o.set_ylabel("mean overhead d_t / d_u (bootstrap 95%)")
    ax_s.legend(title=label, fontsize=8, title_fontsize=8)
    fig.suptitle(f"{sweep['name']}: {sweep['title']}", fontsize=10)
    return _save(fig, path)


def pct(v: Optional[float]) -> str:
    return "n/a" if v is None else f"{100 * v:.0f}%"


def interval(c: Curve, i: int) -> str:
    return f"{pct(c.rate[i])} [{pct(c.lo[i])}, {pct(c.hi[i])}]"


def compare(a: Curve, b: Curve, i: int) -> tuple:
    """Whether line a succeeds more than line b at point i: the directional test (m =
    MIN_EFFECT) on Newcombe's 95% interval of the difference, the interval in words, and the
    rule of 0.3.0 beside it (the two Wilson intervals apart: True, False or None when unknown)."""
    d = evidence.newcombe_difference(a.successes[i], a.runs[i], b.successes[i], b.runs[i])
    test = evidence.directional(d, MIN_EFFECT)
    apart = None if None in (a.lo[i], a.hi[i], b.lo[i], b.hi[i]) else (
        a.lo[i] > b.hi[i] or a.hi[i] < b.lo[i])
    return test, f"Newcombe 95%: {range_words(*d)}", apart


def range_words(lo: float, hi: float) -> str:
    """An interval of a difference of rates in words: "11 to 43 points higher", "4 to 17 points
    lower", "17 points lower to 4 points higher"."""
    if lo != lo or hi != hi:
        return "unknown"
    if lo >= 0:
        return f"{round(100 * lo)} to {points(hi)} higher"
    if hi <= 0:
        return f"{round(-100 * hi)} to {points(lo)} lower"
    return f"{points(lo)} lower to {points(hi)} higher"


def old_rule(apart) -> str:
    return ("unknown" if apart is None else "apart" if apart else "overlapping")


def degradation(lines: list) -> tuple:
    """Sentence and short verdict on which line loses least success from the weakest to the
    strongest meander; the data separate it from the runner-up when Newcombe's interval of the
    difference of their success at the strongest meander lies wholly on one side of 0."""
    drops = sorted(((c.rate[0] - c.rate[-1], c) for c in lines), key=lambda d: d[0])
    best = drops[0][1]
    parts = [f"{c.label}: {interval(c, 0)} at gain {c.x[0]:g}, {interval(c, -1)} at gain "
             f"{c.x[-1]:g} (success {change(c.rate[0], c.rate[-1])})" for _, c in drops]
    runner = drops[1][1] if len(drops) > 1 else None
    # why: a line whose success does not fall is not said to degrade
    least = ("degrades least" if change(best.rate[0], best.rate[-1]).startswith("falls")
             else "does not degrade")
    if runner is None:
        return f"{best.label} alone", "; ".join(parts) + "."
    test, figures, apart = compare(best, runner, -1)
    if test.verdict == evidence.YES:
        verdict = f"{best.label} {least}"
    elif test.verdict == evidence.NO:
        verdict = (f"{best.label} {least}, but still succeeds less than {runner.label} at the "
                   f"strongest meander")
    else:
        verdict = (f"{best.label} {least} in the point estimates, but the data do not "
                   f"separate it from {runner.label} at the strongest meander")
    parts.append(f"at the strongest meander {best.label} against {runner.label}: "
                 f"{difference(best.rate[-1], runner.rate[-1])} ({figures}) -> {test.verdict} "
                 f"(0.3.0's rule: Wilson intervals {old_rule(apart)})")
    return verdict, "; ".join(parts) + "."


def d_lost_effect(lines: list) -> tuple:
    """Whether the largest d_lost succeeds less or more than the smallest at the strongest
    meander (the directional test on Newcombe's interval of the difference), with the same
    difference in the weakest meander and the verdict of the rule of 0.3.0 beside."""
    by_d = sorted(lines, key=lambda c: float(c.label))
    small, large = by_d[0], by_d[-1]
    test, figures, apart = compare(large, small, -1)
    verdict = {evidence.YES: "helps", evidence.NO: "hurts"}.get(test.verdict,
                                                              "makes no clear difference")
    before = ("makes no clear difference" if not apart else
              "helps" if large.rate[-1] > small.rate[-1] else "hurts")
    text = (f"d_lost {large.label} against {small.label}: {interval(large, -1)} against "
            f"{interval(small, -1)} at the strongest meander "
            f"({difference(large.rate[-1], small.rate[-1])}; {figures} -> {test.verdict}), "
            f"{difference(large.rate[0], small.rate[0])} in the weakest. By 0.3.0's rule (the "
            f"Wilson intervals {old_rule(apart)}) it {before}.")
    return verdict, text


def outcome_words(outcome: str, n: int) -> str:
    """"walls", "timeouts", "gave_up" as words for n runs: 1 wall, 2 walls, 3 gave up."""
    if outcome == "gave_up":
        return "gave up"
    return outcome if n != 1 else outcome[:-1]


def failures_text(lines: list) -> str:
    """How the runs at the strongest meander failed, per line, with what each outcome means."""
    parts = []
    for c in lines:
        f = {k: v for k, v in c.failures[-1].items() if v}
        if f:
            parts.append(f"{c.label}: " + ", ".join(f"{v} {outcome_words(k, v)}" for k, v in f.items()))
    if not parts:
        return "At the strongest meander no run failed."
    text = "How runs failed at the strongest meander: " + "; ".join(parts) + "."
    if any(c.failures[-1].get("gave_up") for c in lines):
        text += (" \u201cGave up\u201d is the algorithm's own rule ending the run: surge-cast "
                 "stops when both of its casts find no odor (docs/model.md, section 7.4); in a "
                 "meandering plume the odor has often moved sideways beyond the casts.")
    return text


def build_report(out_dir) -> list:
    out = Path(out_dir)
    path = out / "results.json"
    try:
        results = json.loads(read_input(path, "results file", MAX_RESULTS_BYTES).decode("utf-8"))
    except (OSError, ValueError) as e:
        raise MeanderReportError(f"cannot read {path}: {e}") from e
    fig_dir = output_folder(out / "figures", "the report's figures")
    sections, findings, d_verdicts = [], [], []
    algorithm_verdict = None
    for sweep in results.get("sweeps", []):
        label, key, lines = curves(sweep)
        png = panels(sweep, label, lines, fig_dir / f"meander_{sweep['name']}.png")
        blocks = [Fig(path=png, rel=png.relative_to(out).as_posix(),
                      caption=f"{sweep['title']}: success rate and distance overhead against "
                              f"meander strength, one line per {label}.",
                      alt=f"two panels for sweep {sweep['name']}")]
        rows = []
        for c in lines:
            for i, x in enumerate(c.x):
                oh = "n/a" if c.overhead[i] is None else f"{c.overhead[i]:.3f}"
                if c.overhead[i] is not None and None not in (c.oh_lo[i], c.oh_hi[i]):
                    oh += f" [{c.oh_lo[i]:.3f}, {c.oh_hi[i]:.3f}]"
                rows.append([c.label, f"{x:g}", str(c.runs[i]), interval(c, i), oh])
        blocks.append(Table(header=[label, "gain", "runs", "success [Wilson 95%]",
                                    "overhead [bootstrap 95%]"],
                            rows=rows))
        if key == "controller.algorithm":
            algorithm_verdict, text = degradation(lines)
            blocks.insert(0, Para([f"{algorithm_verdict[0].upper()}{algorithm_verdict[1:]}: {text}"]))
            blocks.insert(1, Para([failures_text(lines)]))
        elif key.endswith(".d_lost"):
            verdict, text = d_lost_effect(lines)
            d_verdicts.append((sweep["title"].split(":")[0], verdict))
            blocks.insert(0, Para([f"A larger d_lost {verdict} here: {text}"]))
            blocks.insert(1, Para([failures_text(lines)]))
        sections.append(Section(anchor=f"sweep-{sweep['name']}",
                                title=f"{sweep['name']}: {sweep['title']}", blocks=blocks))
    if algorithm_verdict:
        findings.append(algorithm_verdict)
    hurts = [t for t, v in d_verdicts if v == "hurts"]
    helps = [t for t, v in d_verdicts if v == "helps"]
    if d_verdicts:
        said = []
        if hurts:
            said.append(f"a larger d_lost hurts {' and '.join(hurts)} in strong meander")
        if helps:
            said.append(f"a larger d_lost helps {' and '.join(helps)}")
        if not said:
            said.append("no algorithm is clearly hurt by a larger d_lost in strong meander")
        elif not hurts:
            said.insert(0, "no algorithm is clearly hurt by a larger d_lost in strong meander")
        findings.append(", ".join(said))
    title = "Beyond the paper: " + ("; ".join(findings) if findings else "meandering wind")
    intro = [Para(["The paper closes: \u201cIn future work, we will test the algorithms in "
                   "turbulent flow and/or meandering plume conditions.\u201d This study runs its "
                   "three algorithms at their fixed values, and each one's d_lost, in the "
                   "meandering wind of Farrell et al. (2002), from laminar (gain 0) to strong "
                   "meander. How the wind and the presets are defined: ",
                   _doc_link(out, "docs/model.md"), "; the study: ",
                   _doc_link(out, "docs/meander.md"), "."])]
    return write_pages(out, title, intro, sections)


def main(argv: Optional[list] = None) -> int:
    return study_report_main(argv, build_report, (MeanderReportError,),
                             "python -m plumetrace.studies.meander", "plumetrace.studies.meander")
