"""The baselines study's report (docs/baselines.md).

Reads OUT/runs.csv and OUT/results.json of `plumetrace study studies/baselines` and, for each
wind and start, tabulates every algorithm built into the library (the random walks also with an
upwind bias, Hayes' spiral-surge also as a team of 3 with and without messages): success with
its Wilson 95% interval, the time to the source and the distance overhead d_t/d_u of successful
runs (mean, percentile-bootstrap 95% interval), how many runs declared a source and the
declaration error. A heat map shows success per algorithm and condition. The title says, from
the data, which one-robot algorithms are tied with the best in every condition ("tied": Newcombe's
95% interval of the difference to the best includes 0, the evidence library's directional test
with m = 0 is not "yes"), which fall below half somewhere (Wilson's upper end < 50%), and how far
the random walks get, the biased ones against the leaders' time.
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

ALGORITHM, START, RANGE = "controller.algorithm", "start.region", "team.range"
# the order of the rows: the paper's three, the baselines, the null models last
ORDER = ["casting", "surge-spiral", "surge-cast", "infotaxis", "particle-filter", "chemotaxis",
         "hayes", "hayes, team of 3, messages", "hayes, team of 3, no messages", "crw",
         "crw + upwind bias", "levy", "levy + upwind bias"]
NULLS = ("crw", "levy")
WINDS = {"L": "laminar", "W": "weak meander", "S": "strong meander"}
STARTS = {"point": "from the paper's start (in the plume)",
          "rectangle": "from starts mostly outside the plume"}
MIN_EFFECT = 0.0  # "tied with the best": the difference's interval reaches 0


class BaselinesReportError(Exception):
    """runs.csv or results.json is missing, unreadable or not from the baselines study."""


class Cell:
    """The runs of one algorithm variant in one wind from one start: one entry per trial."""

    def __init__(self) -> None:
        self.trials: dict = {}  # trial -> list of robot rows (dicts)

    def add(self, trial: int, row: dict) -> None:
        self.trials.setdefault(trial, []).append(row)

    @property
    def runs(self) -> int:
        return len(self.trials)

    def first_arrivals(self) -> list:
        """The first arriving robot's row of every run in which a robot succeeded."""
        out = []
        for robots in self.trials.values():
            done = [r for r in robots if r["outcome"] == "success"]
            if done:
                out.append(min(done, key=lambda r: (float(r["time_s"]), int(r["agent"]))))
        return out

    @property
    def successes(self) -> int:
        return len(self.first_arrivals())

    def declarations(self) -> list:
        """The declaration error (m) of every robot that declared."""
        return [float(r["declaration_error"]) for robots in self.trials.values()
                for r in robots if r.get("declaration_error", "") not in ("", None)]

    def outcomes(self) -> dict:
        counts: dict = {}
        for robots in self.trials.values():
            for r in robots:
                counts[r["outcome"]] = counts.get(r["outcome"], 0) + 1
        return dict(sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])))


def variant(sweep: str, row: dict) -> str:
    alg = row[ALGORITHM]
    if sweep.endswith("B"):
        return f"{alg} + upwind bias"
    if sweep.endswith("T"):
        reach = float(row.get(RANGE, "inf") or "inf")
        return f"{alg}, team of 3, " + ("messages" if reach > 0 else "no messages")
    return alg


def read_cells(out: Path) -> dict:
    """(wind letter, start, variant) -> Cell, from runs.csv."""
    path = out / "runs.csv"
    try:
        text = read_input(path, "runs file", MAX_RESULTS_BYTES).decode("utf-8")
    except (OSError, ValueError) as e:
        raise BaselinesReportError(f"cannot read {path}: {e}") from e
    reader = csv.DictReader(io.StringIO(text))
    need = {"sweep", ALGORITHM, START, "trial", "agent", "outcome", "time_s", "d_t", "overhead",
            "declaration_error"}
    missing = need - set(reader.fieldnames or ())
    if missing:
        raise BaselinesReportError(f"{path} is not from the baselines study: it lacks "
                                   f"{', '.join(sorted(missing))}")
    cells: dict = {}
    for row in reader:
        sweep = row["sweep"]
        if not sweep or sweep[0] not in WINDS:
            raise BaselinesReportError(f"{path}: sweep '{sweep}' is not one of the study's")
        key = (sweep[0], row[START], variant(sweep, row))
        cells.setdefault(key, Cell()).add(int(row["trial"]), row)
    return cells


def pct(v: float) -> str:
    return "n/a" if v is None or math.isnan(v) else f"{100 * v:.0f}%"


def rate(c: Cell) -> float:
    return c.successes / c.runs if c.runs else math.nan


def success_cell(c: Cell) -> str:
    lo, hi = evidence.wilson_interval(c.successes, c.runs)
    return f"{c.successes}/{c.runs} [{pct(lo)}, {pct(hi)}]"


def mean_cell(values: list, unit: str, digits: int) -> str:
    if not values:
        return "n/a"
    m = math.fsum(values) / len(values)
    lo, hi = evidence.bootstrap_mean_interval(values)
    if math.isnan(lo):
        return f"{m:.{digits}f}{unit}"
    return f"{m:.{digits}f}{unit} [{lo:.{digits}f}, {hi:.{digits}f}]"


def overheads(c: Cell) -> list:
    return [float(r["overhead"]) for r in c.first_arrivals() if r["overhead"] not in ("", None)]


def declared_cell(c: Cell) -> str:
    errors = c.declarations()
    if not errors:
        return "none"
    return f"{len(errors)}; error {mean_cell(errors, ' m', 2)}"


def ordered(variants) -> list:
    return sorted(variants, key=lambda v: (ORDER.index(v) if v in ORDER else 99, v))


def leaders(cells: dict, wind: str, start: str) -> tuple:
    """(best success rate, the variants tied with the best) among the non-null variants."""
    here = {v: c for (w, s, v), c in cells.items() if w == wind and s == start and c.runs}
    candidates = {v: c for v, c in here.items() if not v.startswith(NULLS)}
    if not candidates:
        return math.nan, []
    best = max(candidates.values(), key=lambda c: (rate(c), c.runs))
    tied = [v for v, c in candidates.items()
            if evidence.directional(evidence.newcombe_difference(best.successes, best.runs,
                                                                 c.successes, c.runs),
                                    MIN_EFFECT).verdict != evidence.YES]
    return rate(best), ordered(tied)


def listed(names: list) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def is_null(v: str) -> bool:
    return v.startswith(NULLS)


def mean_time(c: Cell) -> float:
    t = [float(r["time_s"]) for r in c.first_arrivals()]
    return math.fsum(t) / len(t) if t else math.nan


def headline(cells: dict) -> list:
    """What the data say, for the title: the one-robot algorithms tied with the best in every
    condition, those below half somewhere (Wilson's upper end < 50%), and the random walks'
    best success, the biased walks' with their time against the leaders'."""
    conditions = sorted({(w, s) for (w, s, _) in cells})
    single = ordered({v for (_, _, v) in cells if "team of" not in v})
    tied = {c: leaders(cells, *c)[1] for c in conditions}
    everywhere = [v for v in single if not is_null(v) and all(v in tied[c] for c in conditions)]
    weak = [v for v in single if not is_null(v) and any(
        (w, s, v) in cells and evidence.wilson_interval(cells[(w, s, v)].successes,
                                                        cells[(w, s, v)].runs)[1] < 0.5
        for (w, s) in conditions)]
    out = []
    if everywhere:
        out.append(f"{listed(everywhere)} {'is' if len(everywhere) == 1 else 'are'} tied with "
                   f"the best in all {len(conditions)} conditions")
    if weak:
        out.append(f"{listed(weak)} fall{'s' if len(weak) == 1 else ''} below half in at least "
                   "one")
    biased = [(rate(c), mean_time(c), w, s) for (w, s, v), c in cells.items()
              if is_null(v) and "upwind" in v]
    plain = [rate(c) for (_, _, v), c in cells.items() if is_null(v) and "upwind" not in v]
    if biased:
        best = max(biased)
        lead = [mean_time(cells[(best[2], best[3], v)]) for v in everywhere
                if (best[2], best[3], v) in cells]
        slower = (f" but take {best[1] / min(lead):.1f} times the leaders' time"
                  if lead and not math.isnan(best[1]) else "")
        out.append(f"random walks biased upwind reach up to {pct(best[0])}{slower}")
    if plain:
        out.append(f"unbiased walks at most {pct(max(plain))}")
    return out


def heat_map(cells: dict, path: Path) -> Path:
    columns = [(w, s) for w in WINDS for s in STARTS]
    rows = ordered({v for (_, _, v) in cells})
    fig = _new_figure(9.5, 0.42 * len(rows) + 1.8)
    ax = fig.subplots()
    grid = [[rate(cells[(w, s, v)]) if (w, s, v) in cells else math.nan for (w, s) in columns]
            for v in rows]
    im = ax.imshow(grid, cmap="viridis", vmin=0.0, vmax=1.0, aspect="auto")
    for i, line in enumerate(grid):
        for j, value in enumerate(line):
            if not math.isnan(value):
                ax.text(j, i, pct(value), ha="center", va="center", fontsize=8,
                        color="black" if value > 0.6 else "white")
    ax.set_xticks(range(len(columns)))
    ax.set_xticklabels([f"{WINDS[w]}\n{'in plume' if s == 'point' else 'outside'}"
                        for (w, s) in columns], fontsize=8)
    ax.set_yticks(range(len(rows)))
    ax.set_yticklabels(rows, fontsize=8)
    fig.colorbar(im, ax=ax, label="success rate")
    ax.set_title("Success per algorithm, wind and start (50 runs per cell)", fontsize=10)
    return _save(fig, path)


def build_report(out_dir) -> list:
    out = Path(out_dir)
    path = out / "results.json"
    try:
        json.loads(read_input(path, "results file", MAX_RESULTS_BYTES).decode("utf-8"))
    except (OSError, ValueError) as e:
        raise BaselinesReportError(f"cannot read {path}: {e}") from e
    cells = read_cells(out)
    if not cells:
        raise BaselinesReportError(f"{out / 'runs.csv'} holds no runs")
    fig_dir = output_folder(out / "figures", "the report's figures")
    png = heat_map(cells, fig_dir / "baselines_success.png")
    sections = [Section(anchor="overview", title="Success at a glance", blocks=[
        Fig(path=png, rel=png.relative_to(out).as_posix(),
            caption="Success rate of every algorithm variant in each wind, from the paper's "
                    "start in the plume and from starts mostly outside it (a team succeeds "
                    "when any robot reaches the source or declares it within "
                    "supervisor.declaration_radius).",
            alt="heat map of success rates, algorithms by condition")])]
    for wind, wname in WINDS.items():
        for start, sname in STARTS.items():
            here = {v: c for (w, s, v), c in cells.items() if w == wind and s == start}
            if not here:
                continue
            rows = []
            for v in ordered(here):
                c = here[v]
                ends = ", ".join(f"{n} {o}" for o, n in c.outcomes().items())
                rows.append([v, success_cell(c),
                             mean_cell([float(r["time_s"]) for r in c.first_arrivals()], " s", 0),
                             mean_cell(overheads(c), "", 2), declared_cell(c), ends])
            best, tied = leaders(cells, wind, start)
            nulls = [rate(c) for v, c in here.items() if v.startswith(NULLS)]
            words = (f"Best success {pct(best)}; tied with the best (Newcombe's 95% interval "
                     f"of the difference includes 0): {'; '.join(tied) or 'none'}.")
            if nulls:
                words += f" The random walks reach at most {pct(max(nulls))}."
            sections.append(Section(
                anchor=f"{wind}-{start}", title=f"{wname.capitalize()} wind, {sname}",
                blocks=[Para([words]),
                        Table(header=["algorithm", "success [Wilson 95%]",
                                      "time to source, successful runs [bootstrap 95%]",
                                      "overhead d_t/d_u [bootstrap 95%]",
                                      "declared; error [bootstrap 95%]", "how runs ended"],
                              rows=rows)]))
    title = "Baselines of the field: " + "; ".join(headline(cells))
    intro = [Para(["Every algorithm built into the library, one robot each (Hayes' spiral-surge "
                   "also as a team of 3, with and without messages; the correlated and Levy "
                   "random walks also with an upwind bias), in laminar, weak and strong "
                   "meandering wind, from the paper's start in the plume and from starts drawn "
                   "10-14.5 m downwind across 3 m of the arena, mostly outside the plume. Walls "
                   "only block. 50 runs per cell. Times and overheads are of successful runs. "
                   "The algorithms: ", _doc_link(out, "docs/algorithms.md"), "; the study: ",
                   _doc_link(out, "docs/baselines.md"), "."])]
    return write_pages(out, title, intro, sections)


def main(argv: Optional[list] = None) -> int:
    return study_report_main(argv, build_report, (BaselinesReportError,), "report.py",
                             "baselines report")


if __name__ == "__main__":
    sys.exit(main())
