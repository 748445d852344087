"""The search: Optuna's TPE over the declared unknowns, kept in DIR/study.sqlite so that an
interrupted study resumes, then the validation of the best candidates on every claim.

The score and the validation are described in docs/calibration.md.
"""

import json
import math
import sys
import time
import warnings
from pathlib import Path

from .._files import BadPath, read_input, write_whole
from .study import CALIBRATION_CLAIMS, HELD_OUT_CLAIMS, StudyError

# the score of target "paper" (docs/calibration.md): per calibration claim, its margin clipped
# to +-MARGIN_CLIP (a NaN margin counts as -MARGIN_CLIP) plus HOLDS_BONUS when it holds
MARGIN_CLIP = 3.0
HOLDS_BONUS = 1.0
# a synthetic target's distance counts a point that has an overhead on one side only as this
NAN_MISMATCH = 1.0
# consecutive failed candidates (a value the simulator refuses) before the search gives up
MAX_FAILURES = 10


def _optuna():
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    warnings.filterwarnings("ignore", category=optuna.exceptions.ExperimentalWarning)
    return optuna


def check_settings(settings):
    """Raises ValueError (ConfigError) when the simulator refuses a key or value."""
    from .. import _core

    _core.resolve_json(None, list(settings.items()))


def evaluate(study, settings, runs, seed, claims):
    """Runs the study's sets under `settings` (dotted key -> value) at `runs` per value with
    master seed `seed`; only the claims whose ids are in `claims` are returned (empty: all).
    The one place the search touches the simulator (tests replace it)."""
    from .. import _core

    return _core.evaluate_sets(str(study.sets_dir), dict(settings), int(runs), int(seed),
                               int(study.threads), list(study.sets), list(claims))


def candidate_settings(study, params):
    """The settings of a candidate: the study's fixed ones, then one per searched unknown."""
    settings = dict(study.fixed)
    by_name = {u.name: u for u in study.all_unknowns}
    for name, value in params.items():
        settings[by_name[name].key] = value
    return settings


def distributions(study):
    """Optuna's distribution of each searched unknown."""
    optuna = _optuna()
    d = {}
    for u in study.unknowns:
        if u.is_choice():
            d[u.name] = optuna.distributions.CategoricalDistribution(u.choices)
        elif u.integer:
            d[u.name] = optuna.distributions.IntDistribution(u.low, u.high, log=u.log)
        else:
            d[u.name] = optuna.distributions.FloatDistribution(u.low, u.high, log=u.log)
    return d


def _finite(x):
    return x is not None and isinstance(x, (int, float)) and math.isfinite(x)


def paper_score(claims):
    """Sum over claims 1, 2 and 10 of clip(margin, -3, 3) (NaN: -3) + 1 if the claim holds.
    Every other claim in `claims` is ignored."""
    by_id = {c["id"]: c for c in claims}
    score = 0.0
    for cid in CALIBRATION_CLAIMS:
        c = by_id.get(cid)
        m = c.get("margin") if c else None
        score += max(-MARGIN_CLIP, min(MARGIN_CLIP, m)) if _finite(m) else -MARGIN_CLIP
        if c and c.get("verdict") == "holds":
            score += HOLDS_BONUS
    return score


def point_vector(result):
    """Per point of every set (in name order): (success rate, mean overhead)."""
    out = []
    for name in sorted(result["sets"]):
        for p in result["sets"][name]["points"]:
            out.append((p["success_rate"], p["overhead_mean"]))
    return out


def synthetic_distance(result, reference):
    """Root mean square difference of the per-point success rates and mean overheads; an
    overhead present on one side only counts NAN_MISMATCH, absent on both sides 0."""
    a, b = point_vector(result), point_vector(reference)
    if len(a) != len(b) or not a:
        raise StudyError("synthetic target: the candidate and the target differ in points")
    total = 0.0
    for (sa, oa), (sb, ob) in zip(a, b):
        total += (sa - sb) ** 2
        if _finite(oa) and _finite(ob):
            total += (oa - ob) ** 2
        elif _finite(oa) != _finite(ob):
            total += NAN_MISMATCH**2
    return math.sqrt(total / (2 * len(a)))


class Target:
    """What a candidate is scored against: the paper's calibration claims, or a synthetic
    target made from the study's [truth] values at the same runs and seed."""

    def __init__(self, study):
        self.study = study
        self._references = {}

    def reference(self, runs, seed):
        """The synthetic target's statistics at (runs, seed), computed once."""
        if (runs, seed) not in self._references:
            truth = candidate_settings(self.study, self.study.truth)
            self._references[(runs, seed)] = evaluate(self.study, truth, runs, seed,
                                                      CALIBRATION_CLAIMS)
        return self._references[(runs, seed)]

    def score(self, result, runs, seed):
        """The candidate's score (higher is better) and what to keep of it."""
        if self.study.target == "paper":
            return paper_score(result["claims"]), {}
        d = synthetic_distance(result, self.reference(runs, seed))
        return -d, {"distance": d}


def _clean(x):
    # JSON without NaN: None instead
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, dict):
        return {k: _clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_clean(v) for v in x]
    return x


def calibration_claims(result):
    """The calibration claims of a search result: id -> {verdict, margin}."""
    return {str(c["id"]): _clean({"verdict": c["verdict"], "margin": c["margin"]})
            for c in result["claims"] if c["id"] in CALIBRATION_CLAIMS}


def study_definition(study):
    """What identifies a study: resuming it with another definition is refused."""
    return json.dumps(_clean({
        "unknowns": {u.name: {"key": u.key, "choices": u.choices, "low": u.low, "high": u.high,
                              "log": u.log, "int": u.integer} for u in study.unknowns},
        "sets": study.sets, "runs": study.runs, "seed": study.seed, "fixed": study.fixed,
        "target": study.target, "truth": study.truth}), sort_keys=True)


class Progress:
    """One line per trial on a terminal (stderr): trial k/N, score, best, candidates per hour."""

    def __init__(self, enabled):
        self.enabled = enabled
        self.start = time.monotonic()
        self.evaluated = 0

    def trial(self, done, total, score, best, cached):
        if not self.enabled:
            return
        hours = (time.monotonic() - self.start) / 3600.0
        rate = f"{self.evaluated / hours:.0f} candidates/h" if hours > 0 and self.evaluated else ""
        note = " (same as an earlier trial)" if cached else ""
        sys.stderr.write(f"\rtrial {done}/{total}  score {score:+.3f}  best {best:+.3f}  "
                         f"{rate}{note}\033[K\n")
        sys.stderr.flush()


def open_study(study, out_dir):
    """The Optuna study in OUT/study.sqlite (created or loaded); trials a killed run left
    RUNNING are marked failed. Refuses a folder whose study has another definition."""
    optuna = _optuna()
    out_dir = Path(out_dir)
    storage = f"sqlite:///{(out_dir / 'study.sqlite').resolve()}"
    # why: the folder's validation.json, best.toml and report are one study's; a second study
    # in the same database would overwrite them
    others = [s.study_name for s in optuna.get_all_study_summaries(storage)
              if s.study_name != study.name]
    if others:
        raise StudyError(f"'{out_dir}' holds study '{others[0]}', not '{study.name}'; use "
                         "another --out (one study per folder)")
    opt = optuna.create_study(study_name=study.name, storage=storage, direction="maximize",
                              load_if_exists=True)
    definition = study_definition(study)
    stored = opt.user_attrs.get("definition")
    if stored is None:
        opt.set_user_attr("definition", definition)
    elif stored != definition:
        raise StudyError(f"'{out_dir}' holds study '{study.name}' made from another definition "
                         "(unknowns, sets, runs, seed, fixed settings or target changed); use "
                         "another --out or another study name")
    TrialState = optuna.trial.TrialState
    for t in opt.get_trials(deepcopy=False, states=(TrialState.RUNNING,)):
        opt._storage.set_trial_user_attr(t._trial_id, "interrupted", True)
        opt._storage.set_trial_state_values(t._trial_id, TrialState.FAIL)
    return opt


def completed(opt):
    """The study's completed trials."""
    optuna = _optuna()
    return opt.get_trials(deepcopy=False, states=(optuna.trial.TrialState.COMPLETE,))


def run_search(study, out_dir, progress=False):
    """Runs trials until the study has `study.trials` completed ones; returns the Optuna study
    and how many candidates this call evaluated. A candidate identical to an earlier trial's is
    not run again: its score is copied (evaluations are deterministic)."""
    optuna = _optuna()
    opt = open_study(study, out_dir)
    done = len(completed(opt))
    # why: seeded by the trials so far, so a resumed study samples afresh instead of repeating
    # the first session's random start-up candidates
    # (NumPy takes seeds below 2^32: larger ones wrap)
    opt.sampler = optuna.samplers.TPESampler(seed=(study.seed + len(opt.trials)) % 2**32,
                                             n_startup_trials=study.startup_trials)
    dists = distributions(study)
    target = Target(study)
    known = {json.dumps(t.params, sort_keys=True): t for t in completed(opt)}
    bar = Progress(progress)
    evaluated = failures = 0
    while done < study.trials:
        trial = opt.ask(fixed_distributions=dists)
        key = json.dumps(trial.params, sort_keys=True)
        cached = key in known
        try:
            if cached:
                earlier = known[key]
                for k, v in earlier.user_attrs.items():
                    trial.set_user_attr(k, v)
                trial.set_user_attr("same_as", earlier.number)
                score = earlier.value
            else:
                start = time.monotonic()
                result = evaluate(study, candidate_settings(study, trial.params), study.runs,
                                  study.seed, CALIBRATION_CLAIMS)
                score, extra = target.score(result, study.runs, study.seed)
                trial.set_user_attr("claims", calibration_claims(result))
                for k, v in extra.items():
                    trial.set_user_attr(k, v)
                trial.set_user_attr("elapsed", time.monotonic() - start)
                evaluated += 1
                bar.evaluated += 1
        except ValueError as e:  # the simulator refused the candidate (ConfigError)
            trial.set_user_attr("error", str(e))
            opt.tell(trial, state=optuna.trial.TrialState.FAIL)
            failures += 1
            if failures >= MAX_FAILURES:
                raise StudyError(f"{failures} candidates in a row were refused; last: {e}") from e
            continue
        except BaseException:
            trial.set_user_attr("interrupted", True)
            opt.tell(trial, state=optuna.trial.TrialState.FAIL)
            raise
        failures = 0
        opt.tell(trial, score)
        done += 1
        known.setdefault(key, opt._storage.get_trial(trial._trial_id))
        bar.trial(done, study.trials, score, opt.best_value, cached)
    return opt, evaluated


def top_candidates(opt, k):
    """The k best completed trials with distinct parameters, best first."""
    seen, out = set(), []
    for t in sorted(completed(opt), key=lambda t: (-t.value, t.number)):
        key = json.dumps(t.params, sort_keys=True)
        if key in seen:
            continue
        seen.add(key)
        out.append(t)
        if len(out) == k:
            break
    return out


def claim_role(cid):
    """"calibration" or "held-out"."""
    return "calibration" if cid in CALIBRATION_CLAIMS else "held-out"


def _holds(claims):
    """The calibration and held-out claims that hold, counted."""
    return {"calibration_holds": sum(c["verdict"] == "holds" for c in claims
                                     if c["id"] in CALIBRATION_CLAIMS),
            "held_out_holds": sum(c["verdict"] == "holds" for c in claims
                                  if c["id"] in HELD_OUT_CLAIMS)}


def validate(study, opt, out_dir, progress=False):
    """Reruns the best `validation.top` candidates at `validation.runs` per value with the fresh
    `validation.seed` and evaluates every claim (the held-out ones only here); the best reading
    is the one with the highest score at validation (held-out claims never choose it). Writes
    OUT/validation.json and returns its content; a validation of the same trials and settings
    already there is reused."""
    v = study.validation
    out_path = Path(out_dir) / "validation.json"
    chosen = top_candidates(opt, v.top)
    if not chosen:
        raise StudyError("no completed trial to validate")
    plan = {"trials": [t.number for t in chosen], "runs": v.runs, "seed": v.seed,
            "definition": study_definition(study)}
    if v.confirm_runs:
        plan["confirm_runs"] = v.confirm_runs
    if out_path.exists():
        try:
            old = json.loads(read_input(out_path, "validation file"))
            if isinstance(old, dict) and old.get("plan") == plan:
                return old
        except (BadPath, ValueError):
            pass  # validated again, and replaced
    target = Target(study)
    candidates = []
    for i, t in enumerate(chosen):
        if progress:
            sys.stderr.write(f"validating candidate {i + 1}/{len(chosen)} (trial {t.number}) at "
                             f"{v.runs} runs per value\n")
        settings = candidate_settings(study, t.params)
        start = time.monotonic()
        result = evaluate(study, settings, v.runs, v.seed, [])
        score, extra = target.score(result, v.runs, v.seed)
        claims = [dict(c, role=claim_role(c["id"])) for c in result["claims"]]
        candidate = {
            "trial": t.number, "params": t.params, "settings": settings,
            "search_score": t.value, "score": score, **extra,
            "claims": claims, **_holds(claims),
            "sets": result["sets"], "runs": result["runs"],
            "elapsed": time.monotonic() - start}
        if v.confirm_runs:
            # the same candidate at more runs and the same fresh seed: its verdicts beside
            if progress:
                sys.stderr.write(f"confirming candidate {i + 1}/{len(chosen)} (trial {t.number}) "
                                 f"at {v.confirm_runs} runs per value\n")
            more = evaluate(study, settings, v.confirm_runs, v.seed, [])
            more_claims = [dict(c, role=claim_role(c["id"])) for c in more["claims"]]
            candidate["confirm"] = {"runs": v.confirm_runs, "claims": more_claims,
                                    **_holds(more_claims)}
        candidates.append(_clean(candidate))
    best = max(range(len(candidates)),
               key=lambda i: (candidates[i]["score"], candidates[i]["search_score"], -i))
    doc = {"plan": plan, "study": str(study.path), "target": study.target,
           "validation": {"top": v.top, "runs": v.runs, "seed": v.seed,
                          "confirm_runs": v.confirm_runs},
           "candidates": candidates, "best": best}
    write_whole(out_path, json.dumps(doc, indent=1))
    return doc


def toml_value(value):
    """A value as TOML writes it."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    return json.dumps(str(value))


def best_toml(study, validation):
    """The best validated candidate as a partial scenario file (one table per section)."""
    best = validation["candidates"][validation["best"]]
    tables = {}
    for key, value in best["settings"].items():
        section, _, rest = key.partition(".")
        tables.setdefault(section, []).append((rest, value))
    lines = [f"# The best reading of calibration study '{study.name}' ({study.path.name}):",
             f"# trial {best['trial']}, validated at {validation['validation']['runs']} runs per "
             f"value with seed {validation['validation']['seed']}.",
             "# A partial scenario: apply it on top of a set's scenario (e.g. as a preset)."]
    for section, rows in tables.items():
        lines.append("")
        lines.append(f"[{section}]")
        for rest, value in rows:
            lines.append(f"{rest} = {toml_value(value)}")
    return "\n".join(lines) + "\n"
