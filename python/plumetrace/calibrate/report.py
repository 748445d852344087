"""The study's report, OUT/calibration.html: a single self-contained page (figures inline as
PNG). It only draws what the search and the validation left; it computes no score."""

import base64
import html
import io
import math
import time

from .._files import write_whole
from .search import completed
from .study import CALIBRATION_CLAIMS, HELD_OUT_CLAIMS, same_value


def _png(fig):
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100, bbox_inches="tight")
    import matplotlib.pyplot as plt

    plt.close(fig)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def _fmt(value):
    if isinstance(value, float):
        if not math.isfinite(value):
            return str(value)
        return f"{value:.6g}"
    return str(value)


def _margin(m):
    return "NaN" if m is None or (isinstance(m, float) and math.isnan(m)) else f"{m:+.2f}"


def distance_from_printed(unknown, chosen):
    """How far a chosen value lies from the printed one, in words."""
    p = unknown.printed
    if p is None:
        return "no printed value"
    if same_value(p, chosen):
        return "the printed value"
    numbers = (int, float)
    if isinstance(p, numbers) and isinstance(chosen, numbers) and not isinstance(p, bool):
        diff = chosen - p
        text = f"{diff:+.4g} from {p:.4g}"
        if p != 0 and chosen != 0 and (chosen / p > 0):
            ratio = chosen / p
            text += f" (x{ratio:.3g}" + (f", 10^{math.log10(ratio):+.1f}" if abs(
                math.log10(ratio)) >= 1 else "") + ")"
        return text
    return f"differs from the printed {p!r}"


def evidence_text(unknown, chosen):
    """The evidence for a chosen value, or that the optimiser chose it without any."""
    entries = unknown.evidence_for(chosen)
    if entries:
        return "; ".join(f"{e.source}: {e.says}" if e.says else e.source for e in entries)
    text = "no evidence: chosen by the optimiser"
    numeric = [e for e in unknown.evidence if isinstance(e.value, (int, float))
               and not isinstance(e.value, bool)]
    if not unknown.is_choice() and numeric and isinstance(chosen, (int, float)):
        near = min(numeric, key=lambda e: abs(e.value - chosen))
        text += f" (nearest evidenced value {_fmt(near.value)}: {near.source})"
    return text


def importances(opt):
    """Optuna's fANOVA parameter importances (seeded), or the reason they cannot be had."""
    import optuna

    try:
        evaluator = optuna.importance.FanovaImportanceEvaluator(seed=0)
        return optuna.importance.get_param_importances(opt, evaluator=evaluator), None
    except Exception as e:  # too few trials, a single distinct value, ...
        return None, str(e)


def _figure(plot, opt, **kw):
    try:
        ax = plot(opt, **kw)
        fig = ax.figure if hasattr(ax, "figure") else ax
        fig.set_size_inches(8, 4)
        return f'<img src="{_png(fig)}" alt="">'
    except Exception as e:
        return f"<p>(figure not drawn: {html.escape(str(e))})</p>"


def title_of(study, validation):
    """The report's title: what was done and what was found."""
    best = validation["candidates"][validation["best"]]
    n = len(study.unknowns)
    found = f"best reading holds {best['held_out_holds']} of {len(HELD_OUT_CLAIMS)} held-out claims"
    if study.target == "paper":
        on = "claims " + ", ".join(str(c) for c in CALIBRATION_CLAIMS)
    else:
        on = "a synthetic target"
        found = f"best reading at distance {best.get('distance', float('nan')):.3g}; " + found
    return f"Calibration of {n} unknown{'s' if n != 1 else ''} on {on}: {found}"


def render(study, opt, validation, evaluated_now=0):
    """The report's HTML."""
    import matplotlib

    matplotlib.use("Agg")
    import optuna
    import optuna.visualization.matplotlib as ovm

    e = html.escape
    cands = validation["candidates"]
    best = cands[validation["best"]]
    v = validation["validation"]
    trials = opt.get_trials(deepcopy=False)
    done = completed(opt)
    failed = [t for t in trials if t.state == optuna.trial.TrialState.FAIL]
    timed = [t.user_attrs["elapsed"] for t in done if "elapsed" in t.user_attrs]
    rate = 3600.0 * len(timed) / sum(timed) if timed and sum(timed) > 0 else float("nan")
    title = title_of(study, validation)

    out = ["<!DOCTYPE html><html><head><meta charset='utf-8'>", f"<title>{e(title)}</title>",
           "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;line-height:1.4}"
           "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;"
           "padding:3px 8px;vertical-align:top}th{background:#eee}.holds{background:#d8f5d8}"
           ".does-not-hold{background:#f8d8d8}.unclear{background:#f3f0d0}"
           ".role{font-size:90%;color:#555}small{color:#555}</style></head><body>",
           f"<h1>{e(title)}</h1>"]

    # what was done
    target = ("the paper's calibration claims " + ", ".join(map(str, CALIBRATION_CLAIMS)) +
              " (the success levels)" if study.target == "paper" else
              "a synthetic target: the per-point success rates and mean overheads of the study's "
              "[truth] values at the search's runs and seed")
    out.append(
        f"<p>Optuna's TPE sampler searched {len(study.unknowns)} unknowns of "
        f"<code>{e(study.unknowns_path.name)}</code> on sets {', '.join(study.sets)} at "
        f"{study.runs} runs per value (master seed {study.seed}), scoring {e(target)}. "
        f"{len(done)} trials completed, {len(failed)} failed or interrupted; "
        f"{len(timed)} candidates were simulated at about {rate:.0f} candidates per hour "
        f"({evaluated_now} in the last session). Claims {', '.join(map(str, HELD_OUT_CLAIMS))} "
        "are held out: they never entered the score. The best "
        f"{len(cands)} distinct candidate{'s were' if len(cands) != 1 else ' was'} rerun at {v['runs']} runs per value with a fresh "
        f"master seed ({v['seed']}); the best reading is the one with the highest score there, "
        "and only there were the held-out claims evaluated.</p>")

    # the best reading
    out.append(f"<h2>The best reading (trial {best['trial']})</h2>")
    out.append(f"<p>Score at validation {best['score']:+.4g} (search: "
               f"{best['search_score']:+.4g}); holds {best['calibration_holds']} of "
               f"{len(CALIBRATION_CLAIMS)} calibration claims and {best['held_out_holds']} of "
               f"{len(HELD_OUT_CLAIMS)} held-out claims. As a preset: "
               "<code>best.toml</code>.</p>")
    out.append("<table><tr><th>unknown</th><th>key</th><th>chosen</th><th>printed</th>"
               "<th>distance from the printed value</th><th>evidence for the chosen value</th>"
               "</tr>")
    for u in study.unknowns:
        chosen = best["params"][u.name]
        out.append(f"<tr><td>{e(u.name)}<br><small>{e(u.title)}</small></td>"
                   f"<td><code>{e(u.key)}</code></td><td>{e(_fmt(chosen))}</td>"
                   f"<td>{e(_fmt(u.printed))}</td><td>{e(distance_from_printed(u, chosen))}</td>"
                   f"<td>{e(evidence_text(u, chosen))}</td></tr>")
    out.append("</table>")
    others = [u for u in study.all_unknowns if u not in study.unknowns]
    if others:
        out.append("<p>Not searched (the scenario's value): " +
                   ", ".join(f"<code>{e(u.key)}</code>" for u in others) + ".</p>")
    if study.fixed:
        out.append("<p>Fixed for every candidate: " + ", ".join(
            f"<code>{e(k)} = {e(_fmt(x))}</code>" for k, x in study.fixed.items()) + ".</p>")

    # the claims per validated candidate, at validation and at the confirming run count
    out.append(f"<h2>Claims at validation ({v['runs']} runs per value, seed {v['seed']})</h2>")
    out += _claims_table(cands, best, [c["claims"] for c in cands])
    confirmed = [c.get("confirm") for c in cands]
    if all(confirmed):
        out.append(f"<h2>Claims at {confirmed[0]['runs']} runs per value (the same seed "
                   f"{v['seed']})</h2>")
        out += _claims_table(cands, best, [c["claims"] for c in confirmed])

    # which unknowns matter
    out.append("<h2>Which unknowns matter</h2>")
    imp, why = importances(opt)
    if imp:
        out.append("<p>Optuna's parameter importances (fANOVA over the completed trials; the "
                   "share of the score's variance each unknown explains):</p><table>"
                   "<tr><th>unknown</th><th>importance</th></tr>")
        for name, value in imp.items():
            out.append(f"<tr><td>{e(name)}</td><td>{value:.3f}</td></tr>")
        out.append("</table>")
        out.append(_figure(ovm.plot_param_importances, opt,
                           evaluator=optuna.importance.FanovaImportanceEvaluator(seed=0)))
    else:
        out.append(f"<p>Importances could not be computed: {e(why or '')}</p>")

    # the history
    out.append("<h2>Optimisation history</h2>")
    out.append(_figure(ovm.plot_optimization_history, opt))

    out.append(f"<p><small>Study file <code>{e(study.path.name)}</code>, study "
               f"'{e(study.name)}' in <code>study.sqlite</code>; validation in "
               f"<code>validation.json</code>. Score and format: docs/calibration.md. Drawn "
               f"{time.strftime('%Y-%m-%d %H:%M')}.</small></p></body></html>")
    return "\n".join(out)


def _claims_table(cands, best, claims_of):
    """The verdict and margin of each claim under each candidate (`claims_of`: a list of claims
    per candidate), with the best candidate's evidence."""
    e = html.escape
    head = "".join(f"<th>trial {c['trial']}{' (best)' if c is best else ''}<br>"
                   f"<small>score {c['score']:+.4g}</small></th>" for c in cands)
    out = [f"<table><tr><th>claim</th><th>role</th>{head}<th>evidence (best)</th></tr>"]
    by_cand = [{c["id"]: c for c in claims} for claims in claims_of]
    best_claims = by_cand[cands.index(best)]
    for cid in sorted({i for m in by_cand for i in m}):
        role = "calibration (scored)" if cid in CALIBRATION_CLAIMS else "held out"
        cells = ""
        for m in by_cand:
            c = m.get(cid)
            if c is None:
                cells += "<td>-</td>"
                continue
            cls = c["verdict"].replace(" ", "-")
            cells += f"<td class='{cls}'>{e(c['verdict'])}<br><small>margin " \
                     f"{_margin(c.get('margin'))}</small></td>"
        bc = best_claims.get(cid, {})
        out.append(f"<tr><td>{cid}<br><small>{e(bc.get('text', ''))}</small></td>"
                   f"<td class='role'>{role}</td>{cells}<td><small>"
                   f"{e(bc.get('evidence', ''))}</small></td></tr>")
    out.append("</table>")
    return out


def write_report(study, opt, validation, out_dir, evaluated_now=0):
    """Writes OUT/calibration.html; returns its path."""
    from pathlib import Path

    return write_whole(Path(out_dir) / "calibration.html",
                       render(study, opt, validation, evaluated_now))
