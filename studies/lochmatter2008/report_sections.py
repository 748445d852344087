"""What the report says about Lochmatter & Martinoli (2008): its sections, in order, with the
paper's own words for each claim. The report package (data, figures, page) does the rest."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, Optional

from plumetrace.report.data import (DASH, SENSITIVITY_NAME, Point, SweepSet, _centreline,
                                    _elapsed_text, _fixed_points, _held, _int, _is_number, _num,
                                    _old_rules, _readings, _rules_name, _sensitivity_grid, _verdict_counts, fmt_count,
                                    fmt_duration, fmt_median, fmt_oh, fmt_outcomes, fmt_overhead,
                                    fmt_pct, fmt_rate, fmt_raw_int, fmt_value, poisson_interval,
                                    verdict_style)
from plumetrace.report.figures import (claims_matrix_figure, failures_figure,
                                       plume_gaps_figure, readings_map_figure,
                                       readings_success_figure, set_figure, sensitivity_figure,
                                       trajectory_figure)
from plumetrace.report.page import (Bullets, Cell, Para, Pre, Section, Table, _doc_link, _fig,
                                    report_command)
from plumetrace.report.wording import counted, share_lead, verb

# The paper's three algorithms, in the order of its figures.
ALGORITHMS = ("casting", "surge-spiral", "surge-cast")


# The paper's own sentence behind each of the eleven claims (Lochmatter & Martinoli 2008,
# sections 4 and 5; docs/claims.md states each claim and gives its reading and test).
PAPER_QUOTES = {
    1: "The surge-spiral algorithm is extremely robust and virtually all 1350 runs succeeded.",
    2: "Small angles yield a low distance overhead, but also a low success rate. In our setup, "
       "only configurations with \u03b2 > 20\u00b0 resulted in acceptable success rates.",
    3: "On one end of the scale, the success rate drops significantly, whereas on the other "
       "end, the performance gets worse.",
    4: "The accuracy of the wind sensor only has a marginal impact on the performance, and no "
       "visible influence on the robustness as long as the accuracy is good enough. If the noise "
       "is too high, however, the algorithm does not work at all.",
    5: "As expected, a small spiral gap is advantageous, at least as long as the robot "
       "reacquires the plume within one turn.",
    6: "Figure 8 (E) also suggests that higher d_lost yield slightly better performance.",
    7: "Wind sensor accuracy only affects the distance overhead of surge-spiral, and not its "
       "success rate.",
    8: "The distance overhead grows almost linearly with the cast distance, but at a fairly low "
       "rate. Furthermore, for very low cast distances, the algorithm fails to work reliably.",
    9: "The wind sensor noise seems to mainly affect the success rate.",
    10: "The casting algorithm remains the worst among the three algorithm in terms of distance "
        "overhead and success ratio. The results obtained with the surge-cast algorithm are "
        "comparable to those of the surge-spiral algorithm.",
    11: "The plume lost distance, d_lost, does not have a significant influence on the "
        "performance of the algorithms. Well-chosen upwind angles, spiral gap or cast distances "
        "are much more important.",
}


def document(out_dir: Path, fig_dir: Path, summary: dict, sens: Optional[dict],
             written: list) -> tuple:
    """(title, intro blocks, sections) of the report; the figures drawn are appended to written.

    sens is sensitivity.json, or None when the folder has none.
    """
    sets = [SweepSet.from_json(s) for s in summary["sets"]]

    # what was found, the readings, sets (Figs. 7-9), sample runs (Fig. 6), claims,
    # sensitivity, reproducibility
    sections = [_verdict_section(out_dir, fig_dir, summary, written),
                _readings_section(out_dir, fig_dir, summary, written)]
    if len(summary.get("axis_readings") or []) > 1:
        sections.append(_axes_section(out_dir, summary))
    sections.append(_plume_section(out_dir, fig_dir, summary, written))
    sections += _set_sections(out_dir, fig_dir, sets, written)
    sections.append(_trajectory_section(out_dir, fig_dir, summary, written))
    sections.append(_claims_section(out_dir, summary))
    sections.append(_sensitivity_section(out_dir, fig_dir, summary, written))
    if sens is not None:
        sections.append(_sensitivity_claims_section(out_dir, fig_dir, sens, summary, written))
    sections.append(_reproducibility_section(summary, out_dir))
    return report_title(summary), _header_blocks(summary, out_dir), sections


def report_title(summary: dict) -> str:
    """What was done and what it found, never that the paper was reproduced."""
    main = _readings(summary)[0]
    held, _, _, n = _held(main)
    sets = len(summary.get("sets") or [])
    count = {9: "nine"}.get(sets, str(sets))
    return (f"Lochmatter & Martinoli (2008), {count} experiment sets re-run: "
            f"{counted(held, n, 'claim', 'claims')} {verb(held, 'holds', 'hold')} under the "
            f"{main.get('name')} reading")


def _old_verdicts(entry: dict) -> dict:
    """{claim id: verdict} under rules 0.3.0 of a reading, axis reading or summary; empty when
    the summary has none."""
    old = _old_rules(entry) or {}
    return {_int(c.get("id")): c.get("verdict") for c in old.get("claims") or []}


def _old_held(entry: dict) -> Optional[int]:
    """Claims that hold under rules 0.3.0; None when the summary has no such verdicts."""
    old = _old_verdicts(entry)
    return sum(v == "holds" for v in old.values()) if old else None


def _rules_sentence(summary: dict, main: dict, out_dir: Path) -> list:
    """Which rules decided, and what rules 0.3.0 decide on the same data, naming the claims whose
    verdict differs (docs/claims.md, "Two rule sets")."""
    old = _old_verdicts(main)
    if not old:
        return [f" Rules {_rules_name(summary)} of ", _doc_link(out_dir, "docs/claims.md"), "."]
    new = {_int(c.get("id")): c.get("verdict") for c in main.get("claims") or []}
    differ = [f"{cid} ({new.get(cid)}; under 0.3.0 {old[cid]})" for cid in sorted(old)
              if cid is not None and old[cid] != new.get(cid)]
    held = _old_held(main)
    return [f" These are the verdicts of rules {_rules_name(summary)} (",
            _doc_link(out_dir, "docs/claims.md"), ", “Rules 0.4: rules that converge”); "
            f"rules 0.3.0, as first written, decide the same runs with "
            f"{counted(held, len(old), 'claim', 'claims')} holding"
            + (", and differ on claim" + ("s " if len(differ) > 1 else " ") + "; ".join(differ)
               if differ else ", every verdict the same") + "."]


def _header_blocks(summary: dict, out_dir: Path) -> list:
    claims = summary.get("claims") or []
    counts = _verdict_counts(claims)
    meta = [
        ("version", summary.get("version") or DASH),
        ("command", summary.get("generated_by") or DASH),
        ("main reading", summary.get("preset") or DASH),
        ("other readings", ", ".join(r.get("name") for r in _readings(summary)[1:]) or DASH),
        ("master seed", fmt_raw_int(summary.get("seed"))),
        ("runs per point", fmt_value(_num(summary.get("runs_per_point")))),
        ("total runs", fmt_value(_num(summary.get("total_runs")))),
        ("elapsed", _elapsed_text(summary)),
        ("threads", fmt_value(_num(summary.get("threads")))),
    ]
    if claims:
        meta.append(("claims (main reading)",
                     f"{counts['holds']} hold, {counts['does not hold']} do not hold, "
                     f"{counts['unclear']} unclear (of {len(claims)})"))
    rows = [[Cell(k, cls="key"), Cell(v, cls="mono" if k == "command" else None)] for k, v in meta]
    return [
        Para(["The nine experiment sets of Lochmatter & Martinoli (2008), \u201cSimulation "
              "Experiments with Bio-Inspired Algorithms for Odor Source Localization in Laminar "
              "Wind Flow\u201d (its section 3.6), re-run in plumetrace under one or more "
              "readings of what the paper leaves unsaid, with its Figs. 6\u20139 redrawn and the "
              "claims of its section 4 checked (the model and its metrics: ",
              _doc_link(out_dir, "docs/model.md"), "; the sets and their statistics: ",
              _doc_link(out_dir, "docs/experiments.md"), "; the claims: ",
              _doc_link(out_dir, "docs/claims.md"), ")."]),
        Table(header=None, rows=rows),
    ]


def _verdict_section(out_dir: Path, fig_dir: Path, summary: dict, written: list) -> Section:
    readings = _readings(summary)
    main = readings[0]
    held, no, unclear, n = _held(main)
    runs = fmt_value(_num(summary.get("runs_per_point")))
    blocks = [Para([("b", f"Under the {main.get('name')} reading, "
                          f"{counted(held, n, 'claim', 'claims')} {verb(held, 'holds', 'hold')}"),
                    f", {no} {verb(no, 'does', 'do')} not hold and {unclear} "
                    f"{verb(unclear, 'is', 'are')} unclear, at {runs} runs per value."]
                   + _rules_sentence(summary, main, out_dir) + [
                    " A reading fixes what the paper leaves unsaid or prints inconsistently "
                    "(the amount per filament, the plume's noise and kernel, the success "
                    "radius, ...); each is listed with its evidence in ",
                    _doc_link(out_dir, "docs/fidelity.md"), ". The model: ",
                    _doc_link(out_dir, "docs/model.md"), "; how each claim is tested: ",
                    _doc_link(out_dir, "docs/claims.md"), "."])]
    rows = []
    with_old = all(_old_rules(r) is not None for r in readings)
    for r in readings:
        h, d, u, total = _held(r)
        rows.append([Cell(r.get("name") + (" (main)" if r.get("main") else ""), cls="key"),
                     Cell(str(r.get("file") or "built-in defaults"), cls="mono"),
                     Cell(str(h), cls="holds", num=True), Cell(str(d), cls="fails", num=True),
                     Cell(str(u), cls="unclear", num=True), Cell(str(total), num=True)]
                    + ([Cell(str(_old_held(r)), num=True)] if with_old else []))
    blocks.append(Table(header=["reading", "preset file", "hold", "do not hold", "unclear",
                                "claims"] + (["hold under rules 0.3.0"] if with_old else []),
                        rows=rows))

    sentence = failure_sentence(summary)
    if sentence:
        blocks.append(Para([("b", "Main failure mode: "), sentence]))
        path = failures_figure(summary, fig_dir / "failures.png")
        written.append(path)
        examined = _int((summary.get("failures") or {}).get("examined_max"))
        blocks.append(_fig(out_dir, path,
                           "Left: how the runs at the paper's fixed values end, per algorithm "
                           "(main reading). Right: where failed runs end"
                           + (f" (the first {examined} failed runs per algorithm, re-run from "
                              "their seed and trial)" if examined else "")
                           + "; red disc: source, dashed: success radius, dotted: 1 m around "
                           "the source, vertical line: the source's x. Wind blows along +x.",
                           "Outcomes at the fixed values and where failed runs end"))

    claim_rows = []
    main_claims = {_int(c.get("id")): c for c in main.get("claims") or []}
    by_reading = [{_int(c.get("id")): c for c in r.get("claims") or []} for r in readings]
    old = _old_verdicts(main)
    for cid in sorted(i for i in main_claims if i is not None):
        c = main_claims[cid]
        row = [Cell(str(cid), num=True),
               Cell("\u201c" + PAPER_QUOTES.get(cid, c.get("text") or "") + "\u201d")]
        for claims in by_reading:
            v = (claims.get(cid) or {}).get("verdict")
            cls, _, symbol = verdict_style(v)
            row.append(Cell(symbol, cls=f"cell {cls}", title=v or DASH))
        if old:
            cls, _, symbol = verdict_style(old.get(cid))
            row.append(Cell(symbol, cls=f"cell {cls}", title=old.get(cid) or DASH))
        row.append(Cell(short_figure(c), cls="mono"))
        claim_rows.append(row)
    if claim_rows:
        blocks.append(Para(["Each claim as the paper words it, the verdict under each reading "
                            "(\u2713 holds, \u2717 does not hold, ? unclear) and what the data say "
                            f"under the {main.get('name')} reading: the figure that decided its "
                            "verdict. The full evidence is under ",
                            ("a", "the claims", "#claims"), "."]))
        blocks.append(Table(header=["id", "the paper says"] + [r.get("name") for r in readings]
                            + ([f"{main.get('name')}, rules 0.3.0"] if old else [])
                            + [f"what the data say ({main.get('name')})"], rows=claim_rows))
    changes = what_would_change(summary)
    if changes:
        blocks.append(Para([("b", "What would change each verdict that is not \u201cholds\u201d"),
                            f" under the {main.get('name')} reading, from the data: the part "
                            "that decides it, and the readings (model values) and axis readings "
                            "under which the claim holds instead. Rules and thresholds: ",
                            _doc_link(out_dir, "docs/claims.md"), "."]))
        blocks.append(Bullets([[f"Claim {cid}: {text}"] for cid, text in changes]))
    return Section("verdict", "What was found", blocks)


def _part_words(part: dict) -> str:
    """One part in a few words: its label (the text before the first colon), its estimate and 95%
    interval against its threshold, and its support; the text's last clause when the part has no
    interval (claim 3's patterns, claim 8's linearity, claim 9's "mainly")."""
    text = (part.get("text") or "").strip()
    support = part.get("support") or "unclear"
    figures = [_num(part.get(k)) for k in ("estimate", "lo", "hi", "threshold")]
    if all(f is not None for f in figures):
        est, lo, hi, threshold = figures
        label = text.split(": ", 1)[0] if ": " in text[:80] else "the part"
        # differences signed, levels (a success rate against 0.95, say) not
        sign = "+" if threshold == 0 or lo < 0 else ""
        return (f"{label}: {est:{sign}.3f} [{lo:{sign}.3f}, {hi:{sign}.3f}] against "
                f"{threshold:.3g} -> {support}")
    return text.split("; ")[-1] if len(text) > 160 else text


def _deciding_parts(claim: dict) -> list:
    """The parts of a claim's evidence that keep it from holding (those not supported), in a few
    words each; from the evidence string when the summary has no structured parts."""
    parts = claim.get("parts")
    if isinstance(parts, list) and parts:
        return [_part_words(p) for p in parts
                if isinstance(p, dict) and p.get("support") in ("no", "unclear")]
    parts = [p.strip() for p in (claim.get("evidence") or "").split("; ") if p.strip()]
    return [p for p in parts if p.endswith("-> no") or p.endswith("-> unclear")]


# claim 2's "acceptable" success rate: the rules' assumption, the paper gives no number
# (docs/claims.md, "What stays, and why")
ACCEPTABLE = 0.80


def _acceptable_level(claim: dict) -> Optional[str]:
    """For claim 2, when its verdict hinges on the assumed "acceptable" level: the levels at which
    each of its two level parts would be supported, from their intervals."""
    parts = [p for p in claim.get("parts") or [] if isinstance(p, dict)
             and _num(p.get("threshold")) == ACCEPTABLE and _num(p.get("lo")) is not None
             and _num(p.get("hi")) is not None]
    if len(parts) != 2 or all(p.get("support") == "yes" for p in parts):
        return None
    # part 3 (beta > 20 acceptable) holds for a level up to its lower end; part 4 (no beta <= 20
    # acceptable) for a level above the best small angle's upper end
    upper, lower = _num(parts[0].get("lo")), _num(parts[1].get("hi"))
    both = (f"a level between {lower:.3f} and {upper:.3f} would make both hold" if lower < upper
            else "no level makes both hold")
    return (f"It hinges on the \u201cacceptable\u201d level {ACCEPTABLE:.2f}, an assumption of "
            f"the rules (the paper gives no number): beta > 20 is acceptable at any level up to "
            f"{upper:.3f}, and no beta <= 20 at any level above {lower:.3f}, so {both}")


def what_would_change(summary: dict) -> list:
    """(claim id, one sentence) for each claim that does not hold under the main reading: the
    parts that decide it, and the readings and axis readings under which it holds. Computed from
    summary.json alone (docs/report.md)."""
    readings = _readings(summary)
    if not readings:
        return []
    main = readings[0]
    main_values = main.get("values") or {}
    axes = [a for a in summary.get("axis_readings") or [] if a.get("name") != "sets"]
    out = []
    for claim in main.get("claims") or []:
        cid = _int(claim.get("id"))
        if cid is None or claim.get("verdict") == "holds":
            continue
        parts = _deciding_parts(claim)
        text = ("it " + ("does not hold" if claim.get("verdict") == "does not hold"
                         else "is unclear")
                + (" on " + "; ".join(parts) if parts else ""))
        holds_under = []
        for r in readings[1:]:
            if any(_int(c.get("id")) == cid and c.get("verdict") == "holds"
                   for c in r.get("claims") or []):
                differ = [k for k, v in (r.get("values") or {}).items()
                          if main_values.get(k) != v]
                holds_under.append(f"the {r.get('name')} reading"
                                   + (f" ({', '.join(differ)} differ)" if differ else ""))
        for a in axes:
            if any(_int(c.get("id")) == cid and c.get("verdict") == "holds"
                   for c in a.get("claims") or []):
                holds_under.append(f"the {a.get('name')} axes ({a.get('title')})")
        text += (". It holds under " + " and under ".join(holds_under) if holds_under
                 else ". It holds under no other reading or axis reading run here")
        level = _acceptable_level(claim) if cid == 2 else None
        if level:
            text += ". " + level
        out.append((cid, text + "."))
    return out


def short_figure(claim: dict) -> str:
    """The evidence part that decided the verdict: the first contradicted part of a claim that
    does not hold, the first unclear part of an unclear one, else the first part."""
    want = {"does not hold": "-> no", "unclear": "-> unclear"}.get(
        (claim.get("verdict") or "").strip().lower())
    structured = [p for p in claim.get("parts") or [] if isinstance(p, dict)]
    if structured and want:
        chosen = next((p for p in structured if "-> " + str(p.get("support")) == want), None)
        if chosen is not None:
            words = _part_words(chosen)
            return words[: -len(want)].rstrip() if words.endswith(want) else words
    parts = [p.strip() for p in (claim.get("evidence") or "").split("; ") if p.strip()]
    if not parts:
        return DASH
    chosen = next((p for p in parts if want and p.endswith(want)), parts[0])
    for suffix in ("-> yes", "-> no", "-> unclear"):
        if chosen.endswith(suffix):
            chosen = chosen[: -len(suffix)].rstrip()
    return chosen if len(chosen) <= 140 else chosen[:137] + "..."


def _failure_totals(summary: dict) -> Optional[dict]:
    fails = (summary.get("failures") or {}).get("algorithms") or []
    if not fails:
        return None
    total = {k: sum(_int(a.get(k)) or 0 for a in fails)
             for k in ("runs", "failed", "walls", "timeouts", "gave_up", "examined")}
    ends = [e for a in fails for e in (a.get("ends") or [])]
    src = {a.get("algorithm"): (_num(a.get("source_x")) or 0.0, _num(a.get("source_y")) or 0.0)
           for a in fails}
    upwind_wall = upwind = near = 0
    for a in fails:
        sx, sy = src[a.get("algorithm")]
        for e in a.get("ends") or []:
            x, y = _num(e.get("x")), _num(e.get("y"))
            if x is None or y is None:
                continue
            if x < sx:
                upwind += 1
                upwind_wall += e.get("outcome") == "wall"
            elif math.hypot(x - sx, y - sy) <= 1.0:
                near += 1
    total.update(ends=len(ends), upwind_wall=upwind_wall, upwind_other=upwind - upwind_wall,
                 near=near, far=len(ends) - upwind - near,
                 closest=[_num(a.get("closest_median_m")) for a in fails
                          if _num(a.get("closest_median_m")) is not None])
    return total


def failure_sentence(summary: dict) -> Optional[str]:
    """The main failure mode at the fixed values in one sentence, from the summary's numbers,
    worded as the counts are (report/wording.py: "All", "Most", "Half of the" ...)."""
    t = _failure_totals(summary)
    if t is None:
        return None
    failed, runs = t["failed"], t["runs"]
    if failed == 0:
        return f"{_capital(counted(0, runs, 'run', 'runs'))} at the paper's fixed values failed."
    head = (f"{_capital(counted(failed, runs, 'run', 'runs'))} at the paper's fixed values "
            f"{verb(failed, 'fails', 'fail')} ({fmt_pct(failed / runs)}): {t['walls']} at a "
            f"wall, {t['timeouts']} by timeout, {t['gave_up']} giving up.")
    n = t["ends"]
    if n == 0:
        return head
    places = [
        (t["upwind_wall"], "ended at a wall upwind of the source, after passing beside it"),
        (t["upwind_other"], "ended upwind of the source (not at a wall), after passing beside it"),
        (t["near"], "ended downwind of the source but within 1 m of it"),
        (t["far"], "ended more than 1 m downwind of the source"),
    ]
    count, where = max(places, key=lambda p: p[0])
    rerun = "" if n == failed else "re-run "
    if count == n:
        subject = _capital(counted(n, n, f"{rerun}failed run", f"{rerun}failed runs"))
    else:
        subject = f"{share_lead(count, n)} failed runs ({count} of {n}{' re-run' * bool(rerun)})"
    closest = sorted(t["closest"])
    near_text = ""
    if closest:
        span = (f"{closest[0]:.2f} m" if closest[-1] - closest[0] < 0.005
                else f"{closest[0]:.2f}\u2013{closest[-1]:.2f} m")
        near_text = (f". On its way, the {rerun}failed run came within {span} of the source's "
                     "centre" if n == 1 else
                     f". On their way, the {rerun}failed runs came within a median {span} of "
                     "the source's centre (per algorithm)")
    return f"{subject} {where}{near_text}. {head}"


def _capital(text: str) -> str:
    return text[:1].upper() + text[1:]


def _setting_text(v: Any) -> str:
    if _is_number(v):
        return f"{v:g}"
    return json.dumps(v)


def _readings_section(out_dir: Path, fig_dir: Path, summary: dict, written: list) -> Section:
    readings = [r for r in _readings(summary) if r.get("fixed") or r.get("detection_map")]
    title = "The readings side by side"
    if not readings:
        return Section("readings", title, [Para(["This summary has no readings."])])
    keys = list(dict.fromkeys(k for r in readings for k in (r.get("settings") or {})))
    blocks = [Para(["Each reading is a preset file (", ("code", "studies/lochmatter2008/"
                                                                "presets/NAME.toml"),
                    ") applied on top of every experiment set; ", ("code", "default"),
                    " adds nothing to the sets' own scenario (its column shows the built-in "
                    "values). Why each value: ", _doc_link(out_dir, "docs/fidelity.md"), "."])]

    def value(r, k):
        # the value the reading's runs used; older summaries only have the preset's settings
        if k in (r.get("values") or {}):
            return _setting_text(r["values"][k])
        if k in (r.get("settings") or {}):
            return _setting_text(r["settings"][k])
        return "(default)"

    if keys:
        blocks.append(Table(header=["key"] + [r.get("name") for r in readings], rows=[
            [Cell(k, cls="mono")] + [Cell(value(r, k), cls="mono") for r in readings]
            for k in keys]))
    path = readings_success_figure(readings, ALGORITHMS, fig_dir / "readings_success.png")
    written.append(path)
    blocks.append(_fig(out_dir, path, "Success rate of the three algorithms at the paper's fixed "
                       "values under each reading, with Wilson 95% intervals.",
                       "Success at the fixed values per reading"))
    rows = []
    for r in readings:
        pts = _fixed_points(r)
        row = [Cell(r.get("name") + (" (main)" if r.get("main") else ""), cls="key")]
        for alg in ALGORITHMS:
            p = pts.get(alg)
            row.append(Cell(DASH) if p is None else
                       Cell(f"{p.successes}/{p.runs} = {fmt_rate(p)}\n{fmt_overhead(p)}",
                            num=True))
        rows.append(row)
    blocks.append(Table(header=["reading"] + list(ALGORITHMS), rows=rows,
                        caption="At the fixed values: successes/runs = success rate [Wilson 95%], "
                                "then the mean overhead [bootstrap 95%] of the successful runs."))
    path = readings_map_figure(summary, readings, fig_dir / "readings_map.png")
    written.append(path)
    blocks.append(_fig(out_dir, path, "Detection map of each reading: the fraction of instants "
                       "at which a sensor at that point perceives odor (the same scale, 0 to 1, "
                       "in every panel), over the upwind 8 m of the arena. Red disc: the source; "
                       "dashed circle: the reading's success radius.",
                       "Detection maps of the readings"))
    return Section("readings", title, blocks)


# the caption of the paper's Fig. 7 (set C): "The last bar is omitted because of the small
# number of successful runs"; the two readings of "small" in the axes' evidence (docs/
# fidelity.md, "The axes"): fewer than 2 successful runs, where no interval of the mean can be
# drawn, and fewer than a tenth of the runs (5 of 50)
_SMALL = (("fewer than 2 successful runs", lambda k, n: k < 2),
          ("under 10% success", lambda k, n: k < 0.1 * n))


def _axes_section(out_dir: Path, summary: dict) -> Section:
    """The claims under each axis reading, side by side, and the caption's evidence on set C."""
    axes = summary.get("axis_readings") or []
    main = (_readings(summary) or [{}])[0]
    blocks = [Para(["The paper does not publish its axes. Each axis reading gives other values to "
                    "the axes of some sets (", ("code", "studies/lochmatter2008/axes/NAME.toml"),
                    "), run under the ", main.get("name") or "main", " reading; ",
                    ("code", "sets"), " is the set files' own. An axis reading is chosen by its "
                    "evidence, never by the claims it moves: ",
                    _doc_link(out_dir, "docs/fidelity.md"), ", \u201cThe axes\u201d."])]
    rows = []
    with_old = all(_old_rules(a) is not None for a in axes)
    for a in axes:
        changed = ", ".join(s.get("set", "?") for s in a.get("sets") or []) or DASH
        rows.append([Cell(a.get("name") or DASH, cls="key"), Cell(a.get("title") or DASH),
                     Cell(changed, cls="mono"), Cell(str(_int(a.get("held")) or 0), cls="holds",
                                                     num=True),
                     Cell(str(_int(a.get("not_held")) or 0), cls="fails", num=True),
                     Cell(str(_int(a.get("unclear")) or 0), cls="unclear", num=True)]
                    + ([Cell(str(_old_held(a)), num=True)] if with_old else []))
    blocks.append(Table(header=["axes", "what they are", "sets changed", "hold", "do not hold",
                                "unclear"] + (["hold under rules 0.3.0"] if with_old else []),
                        rows=rows))

    # the captions' evidence: the paper's Figs. 7-9 draw every bar but set C's last ("The last
    # bar is omitted because of the small number of successful runs"); which bars would each axis
    # reading's runs leave without enough successful runs?
    main_sets = {s.get("name"): s for s in summary.get("sets") or []}

    def lacking(a, small):
        changed = {s.get("set"): s for s in a.get("sets") or []}
        out = []
        for name in sorted(main_sets):
            points = (changed.get(name) or main_sets[name]).get("points") or []
            few = [p for p in points if _int(p.get("successes")) is not None
                   and _int(p.get("runs")) and small(_int(p.get("successes")), _int(p.get("runs")))]
            last = points[-1] if points else None
            out += [(name, fmt_value(_num(p.get("value"))), p is last) for p in few]
        return out

    ev_rows = []
    for a in axes:
        row = [Cell(a.get("name") or DASH, cls="key")]
        for _, small in _SMALL:
            bars = lacking(a, small)
            as_paper = [(n, last) for n, _, last in bars] == [("C", True)]
            text = "; ".join(f"{n} at {v}" for n, v, _ in bars) or "none"
            row.append(Cell(text + (" (as the paper)" if as_paper else ""), cls="mono"))
        ev_rows.append(row)
    if ev_rows and main_sets:
        blocks.append(Para(["The paper's Figs. 7\u20139 draw every bar of the nine sets but one: "
                            "of set C, \u201cThe last bar is omitted because of the small number "
                            "of successful runs.\u201d Under each axis reading, the values whose "
                            "runs would leave a bar without enough successful runs, in each of "
                            "two readings of \u201csmall\u201d:"]))
        blocks.append(Table(header=["axes"] + [f"bars lacking: {words}" for words, _ in _SMALL],
                            rows=ev_rows))

    claim_rows = []
    by_axes = [{_int(c.get("id")): c for c in a.get("claims") or []} for a in axes]
    ids = sorted({i for claims in by_axes for i in claims if i is not None})
    for cid in ids:
        row = [Cell(str(cid), num=True), Cell("\u201c" + PAPER_QUOTES.get(cid, "") + "\u201d")]
        for claims in by_axes:
            v = (claims.get(cid) or {}).get("verdict")
            cls, _, symbol = verdict_style(v)
            row.append(Cell(symbol, cls=f"cell {cls}", title=v or DASH))
        claim_rows.append(row)
    if claim_rows:
        blocks.append(Para(["Each claim under each axis reading (\u2713 holds, \u2717 does not "
                            "hold, ? unclear), the model reading ", main.get("name") or "main",
                            " throughout:"]))
        blocks.append(Table(header=["id", "the paper says"] + [a.get("name") for a in axes],
                            rows=claim_rows))
    return Section("axes", "The axes side by side", blocks)


# The paper's sentences about its plume, each tested by a plume statistic: (key, section, the
# sentence as printed, a short name). The rules: docs/plume-statistics.md, "When a plume
# contradicts a sentence".
PLUME_SENTENCES = (
    ("intermittent", "3.3", "Yet, it generates an intermittent plume which is similar to the "
     "real plume in the wind tunnel.", "an intermittent plume"),
    ("d_lost", "3.4", "Since the concentration is anyway thresholded and filtered through "
     "d_lost by the algorithms in use here, a precise calibration of the odor propagation and "
     "odor sensor model is not required.", "filtered through d_lost"),
    ("released", "3.6", "In each run, the robot was released in the odor at a position about "
     "14.5 m downwind from the target area.", "released in the odor"),
    ("spiral", "4.2", "With the simple plume used in this setup, a spiral of increasing radius "
     "will always reacquire the plume.", "a spiral will always reacquire the plume"),
)
CONSISTENT, CONTRADICTED, UNCLEAR, NOT_TESTED = ("consistent", "contradicted", "unclear",
                                                 "not tested")
# how each verdict is drawn: the claims' styles (consistent as holds, contradicted as does not
# hold, unclear and not tested as unclear)
PLUME_STYLE = {CONSISTENT: "holds", CONTRADICTED: "does not hold", UNCLEAR: "unclear",
               NOT_TESTED: "unclear"}
# gaps a robot meets per run along the centreline, at or above which the plume is intermittent
# and d_lost filters it (docs/plume-statistics.md)
GAPS_PER_TRAVERSE = 1.0


def smallest_d_lost(summary: dict) -> Optional[float]:
    """The smallest d_lost of the sets that vary it (B, E, H: d_lost / 4 = 0.1535 m)."""
    values = [v for st in summary.get("sets") or [] if str(st.get("key") or "").endswith("d_lost")
              for v in st.get("values") or [] if _is_number(v)]
    return min(values) if values else None


def _m(v: Optional[float]) -> str:
    return DASH if v is None else f"{v:.2f} m"


def _of(k: Optional[int], n: Optional[int]) -> str:
    return DASH if k is None or not n else f"{k}/{n}"


def per_traverse(k: int, traverses: int) -> tuple:
    """(verdict, "r [lo, hi] per run") for k events met on `traverses` runs' ways to the
    source, against GAPS_PER_TRAVERSE (docs/plume-statistics.md)."""
    lo, hi = poisson_interval(k, traverses)
    verdict = (CONSISTENT if lo > GAPS_PER_TRAVERSE else
               CONTRADICTED if hi < GAPS_PER_TRAVERSE else UNCLEAR)
    return verdict, f"{k / traverses:.2f} [{lo:.2f}, {hi:.2f}] per run"


def plume_verdicts(ps: dict, smallest: Optional[float]) -> dict:
    """Sentence key -> (verdict, what the statistic shows) for one reading's plume statistics,
    by the rules of docs/plume-statistics.md."""
    out = {}
    d_lost = _num(ps.get("d_lost"))
    line = _centreline(ps)
    traverses = _int((line or {}).get("paths")) or 0
    lengths = [x for x in (line or {}).get("lengths") or [] if _is_number(x)]
    if not traverses or len(lengths) != (_int(line.get("gaps")) or 0):
        out["intermittent"] = out["d_lost"] = (NOT_TESTED, "no centreline gaps measured")
    else:
        verdict, rate = per_traverse(len(lengths), traverses)
        out["intermittent"] = (verdict, f"gaps along the centreline: {rate} (odor at "
                               f"{fmt_pct(_num(line.get('detected_fraction')))} of the samples)")
        if smallest is None:
            out["d_lost"] = (NOT_TESTED, "no set varies d_lost")
        else:
            verdict, rate = per_traverse(sum(x >= smallest for x in lengths), traverses)
            _, fixed = per_traverse(sum(x >= d_lost for x in lengths), traverses)
            out["d_lost"] = (verdict, f"gaps at least {_m(smallest)}: {rate}; at least d_lost "
                             f"({_m(d_lost)}): {fixed}; longest {_m(_num(line.get('longest')))}")
    rel = ps.get("release") or {}
    n, k, near = _int(rel.get("trials")), _int(rel.get("in_odor")), _int(rel.get("within_d_lost"))
    if not n:
        out["released"] = (NOT_TESTED, "no release measured")
    else:
        text = (f"odor at release in {k} of {n} plumes, within d_lost upwind in {near} of {n}")
        out["released"] = (CONSISTENT if k == n else CONTRADICTED, text)
    sp = ps.get("spirals") or {}
    lost, found = _int(sp.get("lost")) or 0, _int(sp.get("reacquired")) or 0
    one = _int(sp.get("within_one_turn")) or 0
    if lost == 0:
        out["spiral"] = (NOT_TESTED, f"none of the {_int(sp.get('surges')) or 0} virtual surges "
                         "lost the plume")
    else:
        text = (f"{found} of {lost} spirals found odor ({one} within one turn)")
        if found < lost:
            text += (f"; {_int(sp.get('walls')) or 0} met a wall and "
                     f"{_int(sp.get('out_of_turns')) or 0} ran out of turns without odor")
        out["spiral"] = (CONSISTENT if found == lost else CONTRADICTED, text)
    return out


def _plume_section(out_dir: Path, fig_dir: Path, summary: dict, written: list) -> Section:
    readings = [r for r in _readings(summary) if r.get("plume_stats")]
    title = "The plume against the paper's words"
    if not readings:
        return Section("plume", title, [Para(["This summary has no plume statistics."])])
    smallest = smallest_d_lost(summary)
    verdicts = [plume_verdicts(r["plume_stats"], smallest) for r in readings]
    main, ps0 = readings[0], readings[0]["plume_stats"]
    against = [key for key, *_ in PLUME_SENTENCES if verdicts[0][key][0] == CONTRADICTED]
    title += (f": the {main.get('name')} reading's plume contradicts "
              f"{counted(len(against), len(PLUME_SENTENCES), 'sentence', 'sentences')}")
    trials = _int(ps0.get("trials"))
    blocks = [Para([
        "The paper describes its plume in four sentences. Each is tested here by what a binary "
        "odor sensor moving at the robot's speed (", fmt_value(_num(ps0.get("speed"))),
        " m/s) meets while the plume evolves: straight upwind along the plume, crosswind across "
        "it, at the robot's start, and along the surge-spiral's own spiral from where a surge "
        f"loses the plume, in {counted(trials or 0, trials or 0, 'plume', 'plumes')} of each "
        "reading (the plumes of the runs' first trials). The statistics, and the rules by which "
        "a plume contradicts a sentence, are defined in ",
        _doc_link(out_dir, "docs/plume-statistics.md"),
        "; a reading whose plume contradicts a sentence loses that sentence's support for its "
        "values (", _doc_link(out_dir, "docs/fidelity.md"), ")."])]
    blocks.append(Bullets([[("b", f"{i}."), f" \u201c{quote}\u201d (section {sec})"]
                           for i, (_, sec, quote, _) in enumerate(PLUME_SENTENCES, 1)]))
    plain = []
    for key, _, _, short in PLUME_SENTENCES:
        names = [r.get("name") for r, v in zip(readings, verdicts) if v[key][0] == CONTRADICTED]
        if names:
            plain.append(f"\u201c{short}\u201d is contradicted by the plume of "
                         f"{_listed(names)}")
        else:
            plain.append(f"no reading's plume contradicts \u201c{short}\u201d")
    blocks.append(Para([("b", "What the statistics say: "), _capital("; ".join(plain)) + "."]))
    rows = []
    for r, v in zip(readings, verdicts):
        row = [Cell(r.get("name") + (" (main)" if r.get("main") else ""), cls="key")]
        for key, *_ in PLUME_SENTENCES:
            verdict, text = v[key]
            cls, _, symbol = verdict_style(PLUME_STYLE[verdict])
            row.append(Cell(f"{symbol} {verdict}: {text}", cls=f"cell {cls}", title=verdict))
        rows.append(row)
    blocks.append(Table(header=["reading"] + [f"{i}. {short}" for i, (*_, short)
                                              in enumerate(PLUME_SENTENCES, 1)], rows=rows,
                        caption="\u2713 consistent, \u2717 contradicted, ? unclear or not "
                                "tested; rates per run are per traverse of the centreline from "
                                "the start to the source, with 95% Poisson intervals."))
    rows = []
    for r in readings:
        ps = r["plume_stats"]
        line = _centreline(ps) or {}
        gaps = _int(line.get("gaps")) or 0
        across = "; ".join(f"{fmt_value(_num(c.get('distance')))} m: "
                           f"{_m(_num(c.get('band_median')))}"
                           for c in ps.get("across") or [])
        across_gap = max([g for g in (_num(c.get("longest")) for c in ps.get("across") or [])
                          if g is not None], default=None)
        off = "; ".join(f"{fmt_value(_num(a.get('offset')))}: {_m(_num(a.get('longest')))}"
                        for a in ps.get("along") or [] if _num(a.get("offset")) != 0.0)
        rows.append([Cell(r.get("name") + (" (main)" if r.get("main") else ""), cls="key"),
                     Cell(fmt_pct(_num(line.get("detected_fraction"))), num=True),
                     Cell(str(gaps), num=True),
                     Cell(_m(_num(line.get("median"))), num=True),
                     Cell(_m(_num(line.get("p90"))), num=True),
                     Cell(_m(_num(line.get("longest"))), num=True),
                     Cell(f"{_int(line.get('longer_than_d_lost')) or 0} of {gaps}", num=True),
                     Cell(off or DASH), Cell(across or DASH), Cell(_m(across_gap), num=True)])
    d_lost = _num(ps0.get("d_lost"))
    blocks.append(Table(
        header=["reading", "odor along the centreline", "gaps", "median gap", "90th percentile",
                "longest gap", f"gaps \u2265 d_lost ({_m(d_lost)})",
                "longest gap at other offsets (m: gap)", "band width across (distance: median)",
                "longest gap across"],
        rows=rows,
        caption="Along: a sensor moving upwind from the robot's start to the source's x at "
                "y = source.y (the centreline) and at the other offsets; the gaps of every "
                "plume pooled. Across: a sensor moving crosswind wall to wall at each distance "
                "downwind of the source; the band runs from its first to its last detection."))
    rows = []
    for r in readings:
        ps = r["plume_stats"]
        rel, sp = ps.get("release") or {}, ps.get("spirals") or {}
        lost = _int(sp.get("lost"))
        rows.append([Cell(r.get("name") + (" (main)" if r.get("main") else ""), cls="key"),
                     Cell(_of(_int(rel.get("in_odor")), _int(rel.get("trials"))), num=True),
                     Cell(_of(_int(rel.get("within_d_lost")), _int(rel.get("trials"))), num=True),
                     Cell(_of(lost, _int(sp.get("surges"))), num=True),
                     Cell(_of(_int(sp.get("within_one_turn")), lost), num=True),
                     Cell(_of(_int(sp.get("reacquired")), lost), num=True),
                     Cell(f"{_int(sp.get('walls')) or 0} / {_int(sp.get('out_of_turns')) or 0}",
                          num=True),
                     Cell(_m(_num(sp.get("distance_median"))), num=True)])
    blocks.append(Table(
        header=["reading", "odor at release", "odor within d_lost upwind",
                "surges that lost the plume", "spirals with odor within one turn",
                "spirals with odor", "spirals without odor: wall / turns",
                "median path to odor"],
        rows=rows,
        caption="Release: a sensor at the robot's start at release (t = 0 after the warm-up), "
                "then moving upwind for d_lost. Spirals: virtual surges from the start at a "
                "measured upwind heading, each followed, where it loses the plume, by the "
                "surge-spiral's spiral (its d_gap and start radius) until odor, a wall or "
                f"{fmt_value(_num(ps0.get('turns')))} turns."))
    marks = [(d_lost, f"d_lost {_m(d_lost)}")] if d_lost else []
    if smallest is not None and smallest != d_lost:
        marks.append((smallest, f"smallest d_lost of the sets {_m(smallest)}"))
    path = plume_gaps_figure(readings, marks, fig_dir / "plume_gaps.png")
    written.append(path)
    blocks.append(_fig(out_dir, path, "Gaps between detections along the centreline, per "
                       "reading: the share of gaps at least as long as L against L (both axes "
                       "logarithmic); a gap is the distance a sensor goes without odor between "
                       "two detections, the distance the controllers compare with d_lost. "
                       "Dashed: the paper's fixed d_lost and the smallest d_lost of sets B, E "
                       "and H. A reading without a gap has no curve.",
                       "Gap lengths along the centreline per reading, beside d_lost"))
    return Section("plume", title, blocks)


def _listed(names: list) -> str:
    """"a", "a and b", "a, b and c"."""
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def _safe_name(name: str) -> str:
    cleaned = "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in name)
    return cleaned or "set"


def _point_row(p: Point, first: str) -> list:
    return [
        Cell(first, num=True),
        Cell(str(p.runs), num=True),
        Cell(fmt_rate(p), num=True),
        Cell(fmt_overhead(p), num=True),
        Cell(fmt_median(p), num=True),
        Cell(fmt_outcomes(p), num=True),
        Cell(DASH if p.mean_time is None else f"{p.mean_time:.1f}", num=True),
        Cell(DASH if p.mean_losses is None else f"{p.mean_losses:.1f}", num=True),
    ]


POINT_HEADER = ["runs", "success rate [Wilson 95%]", "overhead mean [bootstrap 95%]",
                "overhead median [q1, q3]", "success / wall / timeout / gave up", "mean time (s)",
                "mean losses"]


def _set_sections(out_dir: Path, fig_dir: Path, sets: list, written: list) -> list:
    intro = Section("sets", "Experiment sets A\u2013I (paper Figs. 7\u20139)", [
        Para(["For each set, left: success rate with its Wilson 95% interval (labels: successes/"
              "runs); right: mean distance overhead d_t/d_u over the successful runs with a 95% "
              "percentile bootstrap interval (it never reaches below 1, the bound of an "
              "overhead; the claims' verdicts use the t interval, see ",
              _doc_link(out_dir, "docs/claims.md"),
              "), bars drawn from 1 (the straight-line optimum), diamonds at the median, n = "
              "successful runs. The darker bar and the bold row are the fixed value the other "
              "sets use. Outcome counts are success / wall / timeout / gave up."]),
    ])
    if not sets:
        intro.blocks.append(Para(["This summary has no experiment sets."]))
    sections = [intro]
    stems = []
    for s in sets:
        stem = _safe_name(s.name)
        while stem in stems:
            stem += "_"
        stems.append(stem)
    links = []
    for s, stem in zip(sets, stems):
        links += [" \u00b7 " if links else "Sets: ", ("a", s.name, f"#set-{stem}")]
    if links:
        intro.blocks.append(Para(links))
    for s, stem in zip(sets, stems):
        path = set_figure(s, fig_dir / f"set_{stem}.png")
        written.append(path)
        no_success = [fmt_value(p.value) for p in s.points if p.oh_mean is None]
        caption = (f"Set {s.name} ({s.algorithm or 'algorithm ' + DASH}): {s.title or s.key}. "
                   f"Varies {s.key or s.label}")
        if s.fixed_value is not None:
            caption += f"; fixed value {fmt_value(s.fixed_value)} (darker bar)"
        caption += "."
        if no_success:
            caption += (" No overhead bar where no run succeeded: "
                        f"{s.label} = {', '.join(no_success)}.")
        rows, classes = [], []
        for i, p in enumerate(s.points):
            first = fmt_value(p.value) + (" (fixed)" if i == s.fixed_index else "")
            rows.append(_point_row(p, first))
            classes.append("fixed" if i == s.fixed_index else "")
        rows_cells = [r + [Cell((p.config_hash or DASH)[:12], cls="mono")]
                      for r, p in zip(rows, s.points)]
        title = f"Set {s.name}: {s.title}" if s.title else f"Set {s.name}"
        sections.append(Section(f"set-{stem}", title, [
            Para(["Algorithm ", ("b", s.algorithm or DASH), "; varies ", ("code", s.key or "?"),
                  f" ({s.label})."]),
            _fig(out_dir, path, caption, f"Set {s.name}: success rate and overhead vs {s.label}"),
            Table(header=[s.label] + POINT_HEADER + ["config"], rows=rows_cells,
                  row_classes=classes),
        ], level=3))
    return sections


def _trajectory_panels(summary: dict) -> list:
    """(algorithm, "success" or "failure", trajectory or None): per algorithm in the paper's
    order (then any other), a successful run and a failed one."""
    first = {}
    for t in summary.get("trajectories") or []:
        kind = "success" if (t.get("outcome") or "success") == "success" else "failure"
        first.setdefault((t["algorithm"], kind), t)
    algorithms = list(ALGORITHMS) + [a for a, _ in first if a not in ALGORITHMS]
    panels = []
    for a in dict.fromkeys(algorithms):
        panels.append((a, "success", first.get((a, "success"))))
        if (a, "failure") in first or summary.get("failures") is not None:
            panels.append((a, "failure", first.get((a, "failure"))))
    return panels


def _trajectory_section(out_dir: Path, fig_dir: Path, summary: dict, written: list) -> Section:
    panels = _trajectory_panels(summary)
    path = trajectory_figure(summary, panels, fig_dir / "trajectories.png")
    written.append(path)
    missing = list(dict.fromkeys(list(summary.get("trajectories_missing") or [])
                                 + [a for a, k, t in panels if t is None and k == "success"]))
    blocks = [_fig(out_dir, path,
                   "Sample runs at the fixed values (paper Fig. 6): per algorithm the first "
                   "successful and the first failed run (by trial), re-run from their seed and "
                   "trial. Grey: fraction of sampled instants with odor (detection map). Red "
                   "disc: the source; dashed circle: the success radius. The trajectory is "
                   "coloured by controller state; triangle: start, circle: end. Grey arrows: "
                   "the true wind field at the run's release (0.5 m per m/s); the wind blows "
                   "along +x (left to right).",
                   "Sample trajectories of the three algorithms, successful and failed, over "
                   "the detection map")]
    rows = []
    for alg, kind, t in panels:
        if t is None:
            rows.append([alg, DASH, DASH, DASH, DASH, DASH,
                         Cell(f"no {'successful' if kind == 'success' else 'failed'} run",
                              cls="unclear" if kind == "success" else None)])
        else:
            outcome = str(t.get("outcome") or DASH)
            rows.append([alg, str(t.get("set") or DASH), fmt_raw_int(t.get("trial")),
                         fmt_raw_int(t.get("seed")),
                         fmt_oh(_num(t.get("overhead"))) if kind == "success" else DASH,
                         fmt_oh(_num(t.get("closest_m"))),
                         Cell(outcome, cls="holds" if outcome == "success" else "fails")])
    blocks.append(Table(header=["algorithm", "set", "trial", "seed", "overhead",
                                "closest to the source (m)", "outcome"], rows=rows))
    if missing:
        blocks.append(Para(["No successful run at the fixed values for: ",
                            ", ".join(missing), "; those panels show the plume only."]))
    return Section("trajectories", "Sample trajectories, successful and failed (paper Fig. 6)",
                   blocks)


def _claims_section(out_dir: Path, summary: dict) -> Section:
    claims = summary.get("claims") or []
    if not claims:
        return Section("claims", "The paper's claims", [Para(["This summary has no claims."])])
    rows = []
    old = {_int(c.get("id")): c for c in (_old_rules(summary) or {}).get("claims") or []}
    for cl in claims:
        cls, _, symbol = verdict_style(cl.get("verdict"))
        row = [Cell(fmt_count(_int(cl.get("id"))) if _is_number(cl.get("id"))
                    else str(cl.get("id", DASH)), num=True),
               cl.get("text") or "",
               Cell(f"{symbol} {cl.get('verdict')}", cls=f"verdict {cls}"),
               cl.get("evidence") or DASH]
        if old:
            o = old.get(_int(cl.get("id"))) or {}
            ocls, _, osym = verdict_style(o.get("verdict"))
            # the old evidence only where it decides otherwise
            row.append(Cell(f"{osym} {o.get('verdict') or DASH}"
                            + (": " + (o.get("evidence") or DASH)
                               if o.get("verdict") != cl.get("verdict") else ""),
                            cls=f"verdict {ocls}"))
        rows.append(row)
    return Section("claims", f"The claims and their evidence ({summary.get('preset') or 'main'} "
                   "reading)", [
        Para(["Each claim of the paper's section 4, as ", _doc_link(out_dir, "docs/claims.md"),
              " states it, checked against the sets above, never tuned to pass; the rules are "
              "in the same document. Verdicts: holds (green), does not hold "
              "(red), unclear (amber). The verdicts of the other readings are under ",
              ("a", "What was found", "#verdict"), f". Rules {_rules_name(summary)} decide"]
             + ([": the last column is the verdict of rules 0.3.0 on the same runs, with its "
                 "evidence where it differs."] if old else ["."])),
        Table(header=["id", "claim", f"verdict (rules {_rules_name(summary)})", "evidence"]
              + (["rules 0.3.0"] if old else []), rows=rows),
    ])


def _sensitivity_section(out_dir: Path, fig_dir: Path, summary: dict, written: list) -> Section:
    sens = summary.get("sensitivity")
    title = "Sensitivity of the three algorithms at their fixed values"
    if not sens or not sens.get("rows"):
        return Section("sensitivity", title,
                       [Para(["This summary has no sensitivity block."])])
    variants, algorithms, grid = _sensitivity_grid(sens, ALGORITHMS)
    path = sensitivity_figure(sens, ALGORITHMS, fig_dir / "sensitivity.png")
    written.append(path)
    rows = []
    for v in variants:
        row = [Cell(v, cls="mono")]
        for a in algorithms:
            p = grid.get((a, v))
            row.append(Cell(DASH) if p is None else
                       Cell(f"{fmt_rate(p)}\n{fmt_overhead(p)}", num=True))
        rows.append(row)
    return Section("sensitivity", title, [
        Para(["The three algorithms at their fixed values (sets A, D, G) rerun under each "
              "success radius the supervisor accepts (", _doc_link(out_dir, "docs/model.md"),
              " section 8, and ", _doc_link(out_dir, "docs/fidelity.md"), ", unknown 6; "
              "0.185 m is the default). Each cell: success rate [Wilson 95%], then mean overhead "
              "[bootstrap 95%] of the successful runs."]),
        Table(header=["variant"] + algorithms, rows=rows),
        _fig(out_dir, path, "Success rate (left) and mean distance overhead of the successful runs "
             "(right) per algorithm, one bar per variant, with 95% intervals.",
             "Sensitivity: success rate and overhead per algorithm and variant"),
    ])


def _sensitivity_claims_section(out_dir: Path, fig_dir: Path, sens: dict, summary: dict,
                                written: list) -> Section:
    claims = sens.get("claims") or summary.get("claims") or []
    rows_json = sens.get("rows") or []
    n_claims = max([len(claims)] + [len(r["verdicts"]) for r in rows_json] + [0])
    header = ["noise_mode", "kernel", "success_radius"] + [str(j + 1) for j in range(n_claims)] \
        + ["held"]
    rows = []
    held_per_claim = [0] * n_claims
    for r in rows_json:
        cells = [Cell(str(r.get("noise_mode") or DASH), cls="mono"),
                 Cell(str(r.get("kernel") or DASH), cls="mono"),
                 Cell(fmt_value(_num(r.get("success_radius"))), num=True)]
        for j in range(n_claims):
            v = r["verdicts"][j] if j < len(r["verdicts"]) else None
            cls, _, symbol = verdict_style(v)
            if cls == "holds":
                held_per_claim[j] += 1
            cells.append(Cell(symbol, cls=f"cell {cls}", title=f"claim {j + 1}: {v or DASH}"))
        held = _int(r.get("held"))
        if held is None:
            held = sum(verdict_style(v)[0] == "holds" for v in r["verdicts"])
        cells.append(Cell(f"{held}/{n_claims}", num=True))
        rows.append(cells)
    if rows:
        rows.append([Cell("held in", cls="key"), "", ""]
                    + [Cell(str(h), num=True) for h in held_per_claim] + [""])
    blocks = [
        Para(["From ", ("code", SENSITIVITY_NAME), f" (version {sens.get('version') or DASH}): "
              "the nine sets rerun with ", ("b", f"{fmt_value(_num(sens.get('runs_per_point')))} "
                                                 "runs per point"),
              " under every combination of noise_mode, kernel and success radius (",
              _doc_link(out_dir, "docs/experiments.md"), ", ", ("code", "plumetrace sensitivity"),
              f"); elapsed {fmt_duration(_num(sens.get('elapsed_s')))}. Cells: "
              "\u2713 holds (green), \u2717 does not hold (red), ? unclear (amber). The last row "
              "counts the combinations under which each claim holds."]),
        Table(header=header, rows=rows),
    ]
    if rows_json:
        path = claims_matrix_figure(sens, fig_dir / "sensitivity_claims.png")
        written.append(path)
        blocks.append(_fig(out_dir, path, "The same matrix as a picture: one row per combination "
                           "(noise_mode \u00b7 kernel \u00b7 success radius), one column per "
                           "claim.",
                           "Sensitivity claims matrix"))
    if claims:
        blocks.append(Para(["Claims:"]))
        blocks.append(Bullets([[("b", f"{c.get('id', j + 1)}:"), f" {c.get('text') or ''}"]
                               for j, c in enumerate(claims)]))
    return Section("sensitivity-claims", "Sensitivity study: which claims hold", blocks)


def _reproducibility_section(summary: dict, out_dir: Path) -> Section:
    blocks = []
    items = [
        ["version: ", ("code", summary.get("version") or DASH)],
        ["preset: ", ("code", summary.get("preset") or DASH)],
        ["master seed: ", ("code", fmt_raw_int(summary.get("seed"))),
         "; every run's random streams (plume, wind sensor, controller) are derived from "
         "(master seed, trial index, stream), so trial k meets the same plume at every value "
         "of a set and results do not depend on the thread count (",
         _doc_link(out_dir, "docs/model.md"), " section 10)."],
        ["runs per point: ", fmt_value(_num(summary.get("runs_per_point"))),
         "; threads: ", fmt_value(_num(summary.get("threads")))],
    ]
    for t in summary.get("trajectories") or []:
        items.append([f"sample run ({t.get('algorithm')}): set {t.get('set') or DASH}, trial ",
                      ("code", fmt_raw_int(t.get("trial"))), ", seed ",
                      ("code", fmt_raw_int(t.get("seed")))])
    blocks.append(Bullets(items))
    blocks.append(Para(["To regenerate the results and this report (the runs already in the "
                        "store are not run again), then this report alone from its summary.json "
                        "(with the Python package installed, README \"From Python\"):"]))
    command = summary.get("generated_by") or "plumetrace reproduce ..."
    blocks.append(Pre(f"{command}\n{report_command(out_dir)}", "sh"))
    sweeps = summary.get("sweeps") or []
    if sweeps:
        blocks.append(Para(["Sweep definitions:"]))
        blocks.append(Table(header=["set", "file", "definition"], rows=[
            [str(sw.get("name", DASH)), Cell(str(sw.get("file") or DASH), cls="mono"),
             Cell(json.dumps(sw.get("definition"), sort_keys=True), cls="mono")]
            for sw in sweeps]))
    config = summary.get("config_toml")
    if config:
        blocks.append(Para(["The resolved base scenario (every key, as ",
                            ("code", "plumetrace config"), " prints it):"]))
        blocks.append(Pre(config, "toml"))
    else:
        blocks.append(Para(["This summary does not include the resolved configuration."]))
    return Section("reproducibility", "Reproducibility", blocks)
