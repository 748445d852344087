"""The calibration study (python -m plumetrace.calibrate): it recovers a known truth, resumes
without repeating trials, scores only the calibration claims and refuses bad study files."""

import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from conftest import plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()

from plumetrace import calibrate  # noqa: E402
from plumetrace.calibrate import search  # noqa: E402
from plumetrace.calibrate.study import CALIBRATION_CLAIMS, HELD_OUT_CLAIMS  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SETS = ROOT / "studies" / "lochmatter2008" / "sets"
SCENARIO = ROOT / "scenarios" / "lochmatter2008.toml"

UNKNOWNS = """
[[unknown]]
name = "amount"
key = "plume.amount"
title = "Amount per filament"
printed = 8.3e9
choices = [8.3e9, 1.0]
changes = "the detection map"
[[unknown.evidence]]
value = 1.0
source = "plugin (old copy)"
says = "the amount is never copied into a new filament"

[[unknown]]
name = "success_radius"
key = "supervisor.success_radius"
title = "Success radius"
printed = 0.185
low = 0.1
high = 0.5
"""


def write(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def write_set_d(tmp_path):
    """Set D reduced to three spiral gaps of 4 runs each, as FOLDER/sets/D.toml: a trial of a
    study on it runs in seconds."""
    return write(tmp_path / "sets" / "D.toml", f"""
name = "D"
title = "Surge-spiral: spiral gap (three values)"
scenario = "{SCENARIO}"
runs = 4
seed = 5
[set]
controller.algorithm = "surge-spiral"
[[axis]]
key = "surge_spiral.d_gap"
values = [0.111, 0.222, 0.333]
fixed = 0.222
""")


def study_file(tmp_path, body, unknowns=UNKNOWNS):
    write(tmp_path / "unknowns.toml", unknowns)
    return write(tmp_path / "study.toml", 'unknowns = "unknowns.toml"\n' + body)


# --- recovery of a known truth ------------------------------------------------------------------


def test_recovers_a_known_truth_within_tolerance(tmp_path):
    # a reduced problem: surge-spiral at three spiral gaps, 4 runs each, a 400 s time limit; the
    # target is what amount 1 and success radius 0.3 give at the search's own seed, so the truth
    # reproduces it exactly (distance 0) and any other reading does not
    write_set_d(tmp_path)
    study = study_file(tmp_path, """
sets_dir = "sets"
sets = ["D"]
runs = 4
seed = 3
trials = 30
startup_trials = 5
threads = 2
target = "synthetic"
[truth]
amount = 1.0
success_radius = 0.3
[fixed]
supervisor.timeout = 400.0
[validation]
top = 2
runs = 4
seed = 9
""")
    out = tmp_path / "out"
    assert calibrate.main([str(study), "--out", str(out), "--quiet"]) == 0
    best = tomllib.loads((out / "best.toml").read_text())
    # tolerance: the amount exactly (a choice), the radius within 0.03 m (a tenth of it)
    assert best["plume"]["amount"] == 1.0
    assert abs(best["supervisor"]["success_radius"] - 0.3) < 0.03
    assert best["supervisor"]["timeout"] == 400.0
    # best.toml is a partial scenario the simulator reads
    s = pt.Scenario(out / "best.toml")
    assert s["plume.amount"] == 1.0
    validation = json.loads((out / "validation.json").read_text())
    assert len(validation["candidates"]) == 2
    assert validation["validation"]["seed"] == 9
    page = (out / "calibration.html").read_text()
    assert "Calibration of 2 unknowns on a synthetic target" in page
    assert "data:image/png;base64," in page


# --- a stand-in for the simulator: fast, deterministic claims from the parameters --------------

class FakeEvaluation:
    """Claims whose margins follow the candidate's success radius; records every call."""

    def __init__(self, held_out_margin=0.0, interrupt_at=None):
        self.calls = []
        self.held_out_margin = held_out_margin
        self.interrupt_at = interrupt_at

    def __call__(self, study, settings, runs, seed, claims):
        self.calls.append({"settings": dict(settings), "runs": runs, "seed": seed,
                           "claims": list(claims)})
        if self.interrupt_at is not None and len(self.calls) == self.interrupt_at:
            raise KeyboardInterrupt
        r = settings["supervisor.success_radius"]
        amount = settings["plume.amount"]
        out = []
        for cid in range(1, 12):
            if cid in CALIBRATION_CLAIMS:
                m = 2.0 - 10 * abs(r - 0.3) - (1.0 if amount > 1 else 0.0) + 0.1 * cid
            else:
                m = self.held_out_margin + cid
            out.append({"id": cid, "text": f"claim {cid}", "margin": m, "parts": [],
                        "verdict": "holds" if m > 0 else "does not hold", "evidence": ""})
        if claims:
            out = [c for c in out if c["id"] in claims]
        return {"claims": out, "sets": {}, "runs": 1, "elapsed": 0.0}


PAPER_STUDY = """
runs = 2
seed = 11
threads = 1
[validation]
top = 2
runs = 3
seed = 12
"""


def paper_study(tmp_path):
    return study_file(tmp_path, f'sets_dir = "{SETS}"\n' + PAPER_STUDY)


def trials_of(out):
    import optuna

    s = optuna.load_study(study_name="calibration", storage=f"sqlite:///{out / 'study.sqlite'}")
    return s.get_trials(deepcopy=True)


def test_an_interrupted_study_resumes_without_repeating_trials(tmp_path, monkeypatch):
    import optuna

    study = paper_study(tmp_path)
    out = tmp_path / "out"
    fake = FakeEvaluation()
    monkeypatch.setattr(search, "evaluate", fake)
    assert calibrate.main([str(study), "--out", str(out), "--trials", "5", "--quiet"]) == 0
    first = [(t.number, t.params, t.value) for t in trials_of(out)]
    assert len(first) == 5
    searched = [c for c in fake.calls if c["seed"] == 11]
    assert len(searched) == 5

    # a kill in the middle of a trial leaves it RUNNING
    s = optuna.load_study(study_name="calibration", storage=f"sqlite:///{out / 'study.sqlite'}")
    s.ask(fixed_distributions=search.distributions(calibrate.load_study(study)))
    # and a Ctrl-C during an evaluation
    fake = FakeEvaluation(interrupt_at=2)
    monkeypatch.setattr(search, "evaluate", fake)
    assert calibrate.main([str(study), "--out", str(out), "--trials", "8", "--quiet"]) == 130

    fake = FakeEvaluation()
    monkeypatch.setattr(search, "evaluate", fake)
    assert calibrate.main([str(study), "--out", str(out), "--trials", "8", "--quiet"]) == 0
    trials = trials_of(out)
    done = [t for t in trials if t.state == optuna.trial.TrialState.COMPLETE]
    assert len(done) == 8
    # the first five are untouched; the killed and interrupted trials are failed, not rerun
    assert [(t.number, t.params, t.value) for t in trials[:5]] == first
    failed = [t for t in trials if t.state == optuna.trial.TrialState.FAIL]
    assert len(failed) == 2 and failed[0].user_attrs.get("interrupted") is True
    # 8 - 5 - 1 (the one finished before the Ctrl-C) = 2 evaluations now, plus validation
    assert len([c for c in fake.calls if c["seed"] == 11]) == 2

    # a finished study run again evaluates nothing new and reuses its validation
    fake = FakeEvaluation()
    monkeypatch.setattr(search, "evaluate", fake)
    assert calibrate.main([str(study), "--out", str(out), "--trials", "8", "--quiet"]) == 0
    assert fake.calls == []


def test_resuming_with_another_definition_is_refused(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(search, "evaluate", FakeEvaluation())
    study = paper_study(tmp_path)
    out = tmp_path / "out"
    assert calibrate.main([str(study), "--out", str(out), "--trials", "2", "--quiet"]) == 0
    study.write_text(study.read_text().replace("runs = 2", "runs = 3", 1))
    assert calibrate.main([str(study), "--out", str(out), "--trials", "3", "--quiet"]) == 2
    assert "another definition" in capsys.readouterr().err


# --- the score ---------------------------------------------------------------------------------

def claims(margins, verdicts):
    return [{"id": i, "margin": margins[i], "verdict": verdicts[i]} for i in margins]


def test_score_formula_clips_margins_and_adds_a_bonus_per_holding_claim():
    margins = {1: 0.5, 2: float("nan"), 10: 5.0}
    verdicts = {1: "holds", 2: "unclear", 10: "holds"}
    # (0.5 + 1) + (-3) + (3 + 1)
    assert search.paper_score(claims(margins, verdicts)) == pytest.approx(2.5)
    assert search.paper_score([]) == -9.0


def test_score_ignores_the_held_out_claims():
    base = {1: 0.2, 2: -0.4, 10: 1.5}
    verdicts = {1: "holds", 2: "does not hold", 10: "holds"}
    ref = search.paper_score(claims(base, verdicts))
    for held_margin, held_verdict in [(3.0, "holds"), (-3.0, "does not hold"), (None, "unclear")]:
        margins = {**base, **{i: held_margin for i in HELD_OUT_CLAIMS}}
        v = {**verdicts, **{i: held_verdict for i in HELD_OUT_CLAIMS}}
        assert search.paper_score(claims(margins, v)) == ref


def test_search_never_asks_for_held_out_claims_and_their_changes_do_not_move_it(tmp_path,
                                                                             monkeypatch):
    values = []
    for held_out in (-5.0, 5.0):
        fake = FakeEvaluation(held_out_margin=held_out)
        monkeypatch.setattr(search, "evaluate", fake)
        out = tmp_path / f"out{held_out}"
        assert calibrate.main([str(paper_study(tmp_path)), "--out", str(out), "--trials", "4",
                               "--quiet"]) == 0
        search_calls = [c for c in fake.calls if c["seed"] == 11]
        assert all(c["claims"] == CALIBRATION_CLAIMS for c in search_calls)
        trials = trials_of(out)
        for t in trials:
            assert sorted(t.user_attrs["claims"]) == ["1", "10", "2"]
        values.append([(t.params, t.value) for t in trials])
        # validation: the fresh seed, its runs, every claim
        val = [c for c in fake.calls if c["seed"] == 12]
        assert len(val) == 2 and all(c["runs"] == 3 and c["claims"] == [] for c in val)
        doc = json.loads((out / "validation.json").read_text())
        roles = {c["id"]: c["role"] for c in doc["candidates"][0]["claims"]}
        assert [i for i, r in roles.items() if r == "held-out"] == HELD_OUT_CLAIMS
    assert values[0] == values[1]


def test_confirm_runs_validate_the_same_candidates_again_at_more_runs_with_the_same_seed(
        tmp_path, monkeypatch):
    fake = FakeEvaluation()
    monkeypatch.setattr(search, "evaluate", fake)
    study = study_file(tmp_path, f'sets_dir = "{SETS}"\n' + PAPER_STUDY + "confirm_runs = 7\n")
    out = tmp_path / "out"
    assert calibrate.main([str(study), "--out", str(out), "--trials", "4", "--quiet"]) == 0
    val = [c for c in fake.calls if c["seed"] == 12]
    # each of the two validated candidates at 3 runs, then at 7, with every claim
    assert [c["runs"] for c in val] == [3, 7, 3, 7]
    assert all(c["claims"] == [] for c in val)
    assert val[0]["settings"] == val[1]["settings"] != val[2]["settings"] == val[3]["settings"]
    doc = json.loads((out / "validation.json").read_text())
    assert doc["validation"]["confirm_runs"] == 7 and doc["plan"]["confirm_runs"] == 7
    for cand in doc["candidates"]:
        confirm = cand["confirm"]
        assert confirm["runs"] == 7 and len(confirm["claims"]) == 11
        assert confirm["held_out_holds"] == sum(c["verdict"] == "holds" for c in confirm["claims"]
                                                if c["role"] == "held-out")
    page = (out / "calibration.html").read_text()
    assert "Claims at 7 runs per value (the same seed 12)" in page
    # run again: the validation is reused, nothing is evaluated
    calls = len(fake.calls)
    assert calibrate.main([str(study), "--out", str(out), "--trials", "4", "--quiet"]) == 0
    assert len(fake.calls) == calls


# --- bad study files ---------------------------------------------------------------------------

@pytest.mark.parametrize("body, unknowns, says", [
    ("runs = 10\nbogus = 1\n", UNKNOWNS, "unknown key 'bogus'"),
    ("[validation]\nsamples = 3\n", UNKNOWNS, "unknown key 'validation.samples'"),
    ("runs = 0\n", UNKNOWNS, "'runs': bad range"),
    ("seed = 4\n[validation]\nseed = 4\n", UNKNOWNS, "'validation.seed' must differ"),
    ("[validation]\nruns = 5\nconfirm_runs = 5\n", UNKNOWNS,
     "'validation.confirm_runs' (5) must be more than 'validation.runs' (5)"),
    ('search = ["amount", "wind"]\n', UNKNOWNS, "unknown 'wind'"),
    ('target = "paper-ish"\n', UNKNOWNS, "'target'"),
    ("", UNKNOWNS.replace("low = 0.1", "low = 0.7"), "success_radius: bad range"),
    ("", UNKNOWNS.replace('key = "plume.amount"', 'key = "plume.amout"'), "plume.amout"),
    ("[fixed]\nsupervisor.timeout = -1.0\n", UNKNOWNS, "supervisor.timeout"),
])
def test_a_bad_study_file_is_refused_naming_the_key(tmp_path, capsys, body, unknowns, says):
    study = study_file(tmp_path, f'sets_dir = "{SETS}"\n' + body, unknowns)
    assert calibrate.main([str(study), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("plumetrace.calibrate: error: ") and says in err
    assert not (tmp_path / "out").exists()


def test_the_command_exits_with_status_2_on_a_bad_study_file(tmp_path):
    study = study_file(tmp_path, "colour = 1\n")
    # the package these tests import, with its C++ module (another test file may have put the
    # source tree, without it, first on sys.path)
    env = dict(os.environ, PYTHONPATH=str(Path(pt.__file__).resolve().parents[1]))
    r = subprocess.run([sys.executable, "-m", "plumetrace.calibrate", str(study), "--quiet"],
                       capture_output=True, text=True, env=env, cwd=tmp_path)
    assert r.returncode == 2
    assert "unknown key 'colour'" in r.stderr


# --- a search restricted to evidenced values ----------------------------------------------------

def test_evidenced_only_offers_each_unknown_its_evidenced_values_alone(tmp_path):
    unknowns = UNKNOWNS + """[[unknown.evidence]]
value = 0.185
source = "paper"
says = "printed"
[[unknown.evidence]]
value = 0.115
source = "robot"
says = "body plus half a wheel base"
[[unknown.evidence]]
value = 0.185
source = "plugin"
says = "the same value again"
"""
    study = study_file(tmp_path, f'sets_dir = "{SETS}"\nevidenced_only = true\n', unknowns)
    s = calibrate.load_study(study)
    by_name = {u.name: u for u in s.unknowns}
    # a range becomes the list of evidenced values, once each, in the file's order
    assert by_name["success_radius"].choices == [0.185, 0.115]
    assert by_name["success_radius"].low is None and by_name["success_radius"].high is None
    # the printed 8.3e9 has no evidence entry here, so only 1 is offered
    assert by_name["amount"].choices == [1.0]
    # the unrestricted study keeps every candidate
    plain = calibrate.load_study(study_file(tmp_path, f'sets_dir = "{SETS}"\n', unknowns))
    assert {u.name: u.choices for u in plain.unknowns}["amount"] == [8.3e9, 1.0]


@pytest.mark.parametrize("body, says", [
    ("evidenced_only = true\n", "unknown 'success_radius' has no [[unknown.evidence]]"),
    ('evidenced_only = "yes"\n', "'evidenced_only' must be true or false"),
])
def test_evidenced_only_refuses_what_it_cannot_restrict(tmp_path, body, says):
    study = study_file(tmp_path, f'sets_dir = "{SETS}"\n' + body)
    with pytest.raises(calibrate.StudyError) as e:
        calibrate.load_study(study)
    assert says in str(e.value)
