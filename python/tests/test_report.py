"""Tests for plumetrace.report: a report built from a small synthetic summary.json."""

import html
import json
import math
import os
import random
import re
import shutil
import struct
import subprocess
import sys
from pathlib import Path

import pytest

PYTHON_DIR = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(PYTHON_DIR))

from plumetrace import report  # noqa: E402
from plumetrace.report import data, figures, page  # noqa: E402
from plumetrace.studies.lochmatter2008 import report_sections  # noqa: E402

SETS = [
    ("A", "casting", "casting.beta_deg", "upwind angle beta (deg)", [5, 15, 25, 35]),
    ("B", "casting", "casting.d_lost", "plume lost distance d_lost (m)", [0.1535, 0.307, 0.614]),
    ("C", "casting", "wind_sensor.sigma_a", "wind sensor noise sigma_a (m/s)", [0.0, 0.1, 0.8]),
    ("D", "surge-spiral", "surge_spiral.d_gap", "spiral gap d_gap (m)", [0.111, 0.222, 0.333]),
    ("E", "surge-spiral", "surge_spiral.d_lost", "plume lost distance d_lost (m)", [0.307, 0.614]),
    ("F", "surge-spiral", "wind_sensor.sigma_a", "wind sensor noise sigma_a (m/s)", [0.1, 0.5]),
    ("G", "surge-cast", "surge_cast.d_cast", "cast distance d_cast (m)", [0.0675, 0.27, 0.405]),
    ("H", "surge-cast", "surge_cast.d_lost", "plume lost distance d_lost (m)", [0.307, 0.614]),
    ("I", "surge-cast", "wind_sensor.sigma_a", "wind sensor noise sigma_a (m/s)", [0.1, 0.8]),
]
FIXED = {"A": 25, "B": 0.614, "C": 0.1, "D": 0.222, "E": 0.614, "F": 0.1, "G": 0.27,
         "H": 0.614, "I": 0.1}
VERDICTS = ["holds", "does not hold", "unclear"]
CLAIM_TEXTS = [f"Claim number {i} <b>&amp; beta > 20 deg</b>" for i in range(1, 12)]
VARIANTS = ["success_radius=0.185", "success_radius=0.3", "preset=paper-literal"]
RUNS = 20


def _point(rng, runs, successes, value=None):
    """One point with the summary.json fields; no overhead statistics without a success."""
    rest = runs - successes
    walls = rest // 2
    p = {"runs": runs, "successes": successes, "walls": walls, "timeouts": 0,
         "gave_up": rest - walls, "success_rate": successes / runs,
         "success_lo": max(0.0, successes / runs - 0.15),
         "success_hi": min(1.0, successes / runs + 0.15),
         "mean_time": 150.0 + rng.random() * 50 if successes else None,
         "config_hash": f"{rng.getrandbits(64):016x}"}
    if value is not None:
        p["value"] = value
    if successes == 0:
        p["overhead"] = {"n": 0, "mean": None, "lo": None, "hi": None, "median": None,
                         "q1": None, "q3": None}
    elif successes == 1:
        m = 1.1 + rng.random()
        p["overhead"] = {"n": 1, "mean": m, "lo": None, "hi": None, "median": m, "q1": m, "q3": m}
    else:
        m = 1.1 + rng.random()
        p["overhead"] = {"n": successes, "mean": m, "lo": m - 0.05, "hi": m + 0.05,
                         "boot_lo": m - 0.03, "boot_hi": m + 0.04,
                         "median": m - 0.01, "q1": m - 0.04, "q3": m + 0.04}
    return p


READINGS = [("default", True, None, {}),
            ("plugin-published", False, "plugin-published.toml",
             {"plume.amount": 1.0, "plume.preset": "lochmatter2008"})]


def _failures(walls=9, timeouts=2, gave_up=1, upwind_wall=8):
    """Failure statistics of three algorithms; `upwind_wall` of the 12 ends lie at x < 1 at a
    wall, the others 3 m downwind of the source."""
    algorithms, placed = [], 0
    for alg, set_name, (w, t, g) in zip(("casting", "surge-spiral", "surge-cast"), "ADG",
                                        ((walls - 2, timeouts, 0), (1, 0, gave_up), (1, 0, 0))):
        ends = []
        for k, outcome in enumerate(["wall"] * w + ["timeout"] * t + ["gave_up"] * g):
            upwind = placed < upwind_wall and outcome == "wall"
            placed += upwind
            ends.append({"trial": k, "outcome": outcome, "x": 0.07 if upwind else 4.0,
                         "y": 0.3, "closest_m": 0.35})
        failed = w + t + g
        algorithms.append({"algorithm": alg, "set": set_name, "runs": 20, "failed": failed,
                           "walls": w, "timeouts": t, "gave_up": g, "examined": failed,
                           "source_x": 1.0, "source_y": 0.0, "ends": ends,
                           "closest_median_m": 0.35, "end_distance_median_m": 1.0})
    return {"examined_max": 25, "algorithms": algorithms}


def _trajectory(algorithm, set_name, states):
    n = 200
    xs = [15.5 - 14.5 * i / (n - 1) for i in range(n)]
    ys = [0.4 * math.sin(i / 8.0) for i in range(n)]
    return {"algorithm": algorithm, "set": set_name, "trial": 7, "seed": 20080101, "x": xs,
            "y": ys, "state": [states[(i // 25) % len(states)] for i in range(n)],
            "odor": [int(abs(y) < 0.3) for y in ys], "outcome": "success", "overhead": 1.3}


def _failed_trajectory(algorithm, set_name):
    t = _trajectory(algorithm, set_name, ["surge", "spiral"])
    t.update(outcome="wall", overhead=1.01, closest_m=0.35, trial=3)
    return t


def _plume_stats(lengths, in_odor=4, lost=6, reacquired=6):
    """A reading's plume statistics (docs/plume-statistics.md) with these centreline gaps."""
    lengths = sorted(lengths)

    def line(key, value, gaps):
        n = len(gaps)
        return {key: value, "paths": 4, "paths_with_odor": 4, "samples": 17100,
                "detections": 17100 - 20 * n, "detected_fraction": 1 - 20 * n / 17100,
                "gaps": n, "median": gaps[n // 2] if n else None,
                "p90": gaps[int(0.9 * (n - 1))] if n else None,
                "longest": gaps[-1] if n else None,
                "longer_than_d_lost": sum(g >= 0.614 for g in gaps),
                "fraction_longer": sum(g >= 0.614 for g in gaps) / n if n else None,
                "lengths": gaps}
    along = [dict(line("offset", 0.0, lengths), leading_median=0.08),
             dict(line("offset", 0.1, lengths[:3]), leading_median=0.1)]
    del along[1]["lengths"]
    across = [dict(line("distance", 2.0, [0.01, 0.02]), band_median=0.18, band_max=0.23,
                   band_widths=[0.18, 0.17, 0.23, 0.2])]
    return {"trials": 4, "seed": 20080101, "d_lost": 0.614, "speed": 0.106, "turns": 10,
            "along": along, "across": across,
            "release": {"trials": 4, "in_odor": in_odor, "within_d_lost": 4},
            "spirals": {"surges": 8, "lost": lost, "within_one_turn": reacquired,
                        "reacquired": reacquired, "walls": lost - reacquired, "out_of_turns": 0,
                        "distance_median": 0.13, "distances": [0.13] * reacquired}}


def make_summary():
    """A synthetic summary.json following the schema in docs/report.md."""
    rng = random.Random(1)
    sets = []
    for name, alg, key, label, values in SETS:
        points = []
        for i, v in enumerate(values):
            # C's last value and G's first have no successful run; one point has exactly one
            successes = 0 if (name, i) in (("C", 2), ("G", 0)) else (
                1 if (name, i) == ("I", 1) else rng.randint(2, RUNS))
            points.append(_point(rng, RUNS, successes, v))
        sets.append({"name": name, "title": f"{alg}: {label}", "algorithm": alg, "key": key,
                     "label": label, "values": values, "fixed_index": values.index(FIXED[name]),
                     "points": points})
    claims = [{"id": i + 1, "text": CLAIM_TEXTS[i], "verdict": VERDICTS[i % 3],
               "evidence": f"evidence {i + 1}: 12/20 vs 3/20"} for i in range(11)]
    rows = [dict(_point(rng, RUNS, rng.randint(0, RUNS)), algorithm=a, variant=v)
            for a in ("casting", "surge-spiral", "surge-cast") for v in VARIANTS]
    xs = [0.25 + 0.5 * i for i in range(32)]
    ys = [-1.75 + 0.5 * j for j in range(8)]
    fraction = [[max(0.0, 1.0 - abs(y) / 0.6) if x > 1 else 0.0 for x in xs] for y in ys]
    readings = []
    for k, (name, main, file, settings) in enumerate(READINGS):
        verdicts = [VERDICTS[(i + k) % 3] for i in range(11)]
        readings.append({
            "name": name, "main": main, "file": file, "settings": settings,
            "held": verdicts.count("holds"), "not_held": verdicts.count("does not hold"),
            "unclear": verdicts.count("unclear"),
            "claims": [{"id": i + 1, "text": CLAIM_TEXTS[i], "verdict": v, "margin": 0.1,
                        "evidence": f"evidence {i + 1}: 12/20 vs 3/20 -> yes"}
                       for i, v in enumerate(verdicts)],
            "fixed": [dict(_point(rng, RUNS, rng.randint(2, RUNS)), algorithm=a, set=s)
                      for a, s in (("casting", "A"), ("surge-spiral", "D"), ("surge-cast", "G"))],
            "detection_map": {"x": xs, "y": ys, "fraction": fraction},
            "success_radius": 0.185})
        readings[-1]["plume_stats"] = (
            _plume_stats([0.003 * (i + 1) for i in range(40)], in_odor=0) if main
            else _plume_stats([], lost=5, reacquired=4))
        if name == "default":
            # the built-in value of a key the other reading sets; "plume.preset" left out to
            # show a summary without it
            readings[-1]["values"] = {"plume.amount": 0.75}
    return {
        "plumetrace_summary": 1, "version": "0.1.0",
        "generated_by": "plumetrace reproduce --runs 20 --out out/test",
        "preset": "default", "seed": 20080101, "runs_per_point": RUNS,
        "total_runs": RUNS * sum(len(s[4]) for s in SETS), "elapsed_s": 12.5, "threads": 2,
        "sets": sets, "claims": claims,
        "sensitivity": {"variants": VARIANTS, "rows": rows},
        "trajectories": [_trajectory("casting", "A", ["upwind", "crosswind"]),
                         _trajectory("surge-spiral", "D", ["surge", "spiral"]),
                         _failed_trajectory("surge-spiral", "D")],
        "readings": readings, "failures": _failures(),
        "trajectories_missing": ["surge-cast"],
        "detection_map": {"x": xs, "y": ys, "fraction": fraction},
        "arena": {"x_min": 0, "x_max": 16, "y_min": -2, "y_max": 2},
        "source": {"x": 1, "y": 0, "radius": 0.12, "success_radius": 0.185},
        "config_toml": "[plume]\nnoise_mode = \"velocity\"\n# <not a tag> & more\n",
        "sweeps": [{"name": s[0], "file": f"studies/lochmatter2008/sets/{s[0]}.toml",
                    "definition": {"key": s[2], "values": s[4]}} for s in SETS],
    }


def make_sensitivity():
    rows = []
    for noise in ("velocity", "per_step", "wiener"):
        for kernel in ("gaussian", "printed"):
            for radius in (0.185, 0.6):
                verdicts = [VERDICTS[(len(rows) + j) % 3] for j in range(11)]
                rows.append({"noise_mode": noise, "kernel": kernel, "success_radius": radius,
                             "verdicts": verdicts, "held": verdicts.count("holds")})
    return {"plumetrace_sensitivity": 1, "version": "0.1.0", "runs_per_point": 10,
            "elapsed_s": 1500.0,
            "claims": [{"id": i + 1, "text": CLAIM_TEXTS[i]} for i in range(11)], "rows": rows}


def write_json(path, data):
    path.write_text(json.dumps(data), encoding="utf-8")


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """A report built once from the synthetic summary plus a sensitivity.json."""
    out = tmp_path_factory.mktemp("report")
    write_json(out / "summary.json", make_summary())
    write_json(out / "sensitivity.json", make_sensitivity())
    written = report.build_report(out)
    return out, written


def expected_figures(with_sensitivity=True):
    names = [f"set_{s[0]}.png" for s in SETS] + ["trajectories.png", "sensitivity.png",
                                                  "failures.png", "readings_success.png",
                                                  "readings_map.png", "plume_gaps.png"]
    return names + (["sensitivity_claims.png"] if with_sensitivity else [])


def png_size(path):
    """(width, height) from a PNG's IHDR chunk; fails if the file is not a PNG."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    assert data[12:16] == b"IHDR"
    assert data[-8:-4] == b"IEND"
    return struct.unpack(">II", data[16:24])


def run_cli(out_dir):
    env = dict(os.environ, PYTHONPATH=str(PYTHON_DIR))
    return subprocess.run([sys.executable, "-m", "plumetrace.report", str(out_dir)],
                          capture_output=True, text=True, env=env, timeout=120)


def test_build_writes_every_figure_as_a_valid_png(built):
    out, written = built
    for name in expected_figures():
        path = out / "figures" / name
        assert path.exists(), name
        width, height = png_size(path)
        assert width > 200 and height > 100
        assert path in written
    assert out / "report.html" in written and out / "report.md" in written


def test_html_embeds_every_figure_and_needs_no_network(built):
    out, _ = built
    text = (out / "report.html").read_text(encoding="utf-8")
    images = re.findall(r'<img src="data:image/png;base64,([A-Za-z0-9+/=]+)"', text)
    assert len(images) == len(expected_figures())
    for name in expected_figures():
        encoded = __import__("base64").b64encode((out / "figures" / name).read_bytes()).decode()
        assert encoded in images, name
    assert not re.search(r"""(src|href)=["']?(https?:)?//""", text)
    assert "<script" not in text and "<link" not in text


def test_html_claims_table_shows_each_claim_with_its_coloured_verdict(built):
    out, _ = built
    text = (out / "report.html").read_text(encoding="utf-8")
    claims_html = text[text.index('id="claims"'):text.index('id="sensitivity"')]
    css_class = {"holds": "holds", "does not hold": "fails", "unclear": "unclear"}
    for i, claim_text in enumerate(CLAIM_TEXTS):
        verdict = VERDICTS[i % 3]
        assert html.escape(claim_text) in claims_html
        assert re.search(rf'<td class="verdict {css_class[verdict]}">[^<]*{verdict}</td>',
                         claims_html), verdict
        assert f"evidence {i + 1}: 12/20 vs 3/20" in claims_html


def test_html_escapes_inserted_text(built):
    out, _ = built
    text = (out / "report.html").read_text(encoding="utf-8")
    assert "<b>&amp; beta" not in text
    assert "&lt;b&gt;&amp;amp; beta &gt; 20 deg&lt;/b&gt;" in text
    assert "# &lt;not a tag&gt; &amp; more" in text


def test_html_has_every_section_and_set(built):
    out, _ = built
    text = (out / "report.html").read_text(encoding="utf-8")
    for anchor in ["sets", "trajectories", "claims", "sensitivity", "sensitivity-claims",
                   "reproducibility"] + [f"set-{s[0]}" for s in SETS]:
        assert f'id="{anchor}"' in text, anchor
    for field in ("plumetrace reproduce --runs 20 --out out/test", "plugin-published",
                  "20080101"):
        assert field in text
    assert "surge-cast: no successful run" not in text  # only in the figure, not as html
    assert "No successful run at the fixed values for: surge-cast" in text


def test_markdown_references_every_figure(built):
    out, _ = built
    text = (out / "report.md").read_text(encoding="utf-8")
    for name in expected_figures():
        assert f"](figures/{name})" in text, name
    for anchor in ("claims", "sensitivity", "sensitivity-claims", "reproducibility"):
        assert f'<a id="{anchor}"></a>' in text
    for i in range(11):
        assert VERDICTS[i % 3] in text
    assert "```toml\n[plume]" in text


def test_set_table_marks_fixed_value_and_missing_overhead(built):
    out, _ = built
    text = (out / "report.html").read_text(encoding="utf-8")
    set_c = text[text.index('id="set-C"'):text.index('id="set-D"')]
    assert '<tr class="fixed"><td class="num">0.1 (fixed)</td>' in set_c
    assert "no successful run" in set_c
    assert "No overhead bar where no run succeeded" in set_c


def test_sensitivity_claims_section_only_with_sensitivity_json(tmp_path):
    write_json(tmp_path / "summary.json", make_summary())
    report.build_report(tmp_path)
    html_text = (tmp_path / "report.html").read_text(encoding="utf-8")
    md_text = (tmp_path / "report.md").read_text(encoding="utf-8")
    assert 'id="sensitivity-claims"' not in html_text
    assert "sensitivity-claims" not in md_text
    assert "sensitivity_claims.png" not in md_text
    assert 'id="sensitivity"' in html_text  # the summary's own sensitivity block stays

    write_json(tmp_path / "sensitivity.json", make_sensitivity())
    report.build_report(tmp_path)
    html_text = (tmp_path / "report.html").read_text(encoding="utf-8")
    md_text = (tmp_path / "report.md").read_text(encoding="utf-8")
    assert 'id="sensitivity-claims"' in html_text
    assert "10 runs per point" in html_text
    matrix = html_text[html_text.index('id="sensitivity-claims"'):]
    assert matrix.count('class="cell holds"') == sum(
        r["verdicts"].count("holds") for r in make_sensitivity()["rows"])
    assert "](figures/sensitivity_claims.png)" in md_text


def test_minimal_summary_without_optional_blocks_builds(tmp_path):
    summary = make_summary()
    for key in ("claims", "sensitivity", "trajectories", "trajectories_missing",
                "detection_map", "arena", "source", "config_toml", "sweeps", "elapsed_s",
                "readings", "failures"):
        del summary[key]
    write_json(tmp_path / "summary.json", summary)
    written = report.build_report(tmp_path)
    assert (tmp_path / "figures" / "trajectories.png").exists()
    assert not (tmp_path / "figures" / "sensitivity.png").exists()
    text = (tmp_path / "report.html").read_text(encoding="utf-8")
    assert "This summary has no claims." in text
    assert "This summary has no sensitivity block." in text
    assert len(written) == 2 + len(SETS) + 1


def test_cli_builds_report_and_exits_zero(tmp_path):
    write_json(tmp_path / "summary.json", make_summary())
    result = run_cli(tmp_path)
    assert result.returncode == 0, result.stderr
    assert "report.html" in result.stdout
    assert (tmp_path / "report.html").exists() and (tmp_path / "report.md").exists()


@pytest.mark.parametrize("content, message", [
    ("{not json", "not valid JSON"),
    ("[1, 2]", "expected a JSON object"),
    ('{"sets": []}', "not a plumetrace summary"),
    ('{"plumetrace_summary": 2, "sets": []}', "not supported"),
    ('{"plumetrace_summary": 1, "sets": [{"name": "A", "points": [{"value": 1, "runs": "x", '
     '"successes": 0}]}]}', "sets[0].points[0].runs"),
])
def test_malformed_summary_exits_nonzero_naming_the_file(tmp_path, content, message):
    (tmp_path / "summary.json").write_text(content, encoding="utf-8")
    result = run_cli(tmp_path)
    assert result.returncode != 0
    assert str(tmp_path / "summary.json") in result.stderr
    assert message in result.stderr
    assert not (tmp_path / "report.html").exists()


def test_missing_summary_exits_nonzero_naming_the_file(tmp_path):
    result = run_cli(tmp_path)
    assert result.returncode != 0
    assert str(tmp_path / "summary.json") in result.stderr
    assert "not found" in result.stderr


def test_a_fifo_summary_is_refused_without_blocking(tmp_path):
    # read as every input is (plumetrace._files.read_input); it blocked for ever in open()
    os.mkfifo(tmp_path / "summary.json")
    result = run_cli(tmp_path)
    assert result.returncode != 0
    assert f"'{tmp_path / 'summary.json'}': not a regular file" in result.stderr


def test_malformed_sensitivity_names_that_file(tmp_path):
    write_json(tmp_path / "summary.json", make_summary())
    (tmp_path / "sensitivity.json").write_text('{"plumetrace_sensitivity": 1}', encoding="utf-8")
    with pytest.raises(report.ReportError, match=re.escape(str(tmp_path / "sensitivity.json"))):
        report.build_report(tmp_path)


def test_a_failed_write_leaves_the_previous_file_whole(tmp_path, monkeypatch):
    path = tmp_path / "report.md"
    path.write_text("old", encoding="utf-8")

    def fail(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr(data.os, "replace", fail)
    with pytest.raises(OSError):
        data.write_whole(path, "new")
    assert path.read_text(encoding="utf-8") == "old"
    assert list(tmp_path.iterdir()) == [path]


def test_success_interval_is_the_one_the_summary_gives():
    # why: the C++ writes every point's Wilson interval; the report shows it, never recomputes it
    p = {"runs": 50, "successes": 12, "success_lo": 0.1430, "success_hi": 0.3741}
    point = report.Point.from_json(p)
    assert (point.rate_lo, point.rate_hi) == (0.1430, 0.3741)
    assert data.fmt_rate(point) == "24% [14, 37]"
    del p["success_lo"], p["success_hi"]
    assert data.fmt_rate(report.Point.from_json(p)) == "24%"


def test_title_says_what_was_done_and_the_report_opens_with_the_verdict(built):
    out, _ = built
    text = (out / "report.html").read_text(encoding="utf-8")
    held = [VERDICTS[i % 3] for i in range(11)].count("holds")
    title = (f"Lochmatter &amp; Martinoli (2008), nine experiment sets re-run: {held} of 11 "
             "claims hold under the default reading")
    assert f"<h1>{title}</h1>" in text
    assert "reproduced" not in text.lower().split("<body>")[1][:400]
    first = re.search(r'<h2 id="([^"]+)"', text).group(1)
    assert first == "verdict"
    verdict = text[text.index('id="verdict"'):text.index('id="readings"')]
    # each reading's counts, with the main one marked
    for name, main, _, _ in READINGS:
        assert name + (" (main)" if main else "") in verdict


def test_verdict_table_quotes_the_paper_beside_a_column_per_reading(built):
    out, _ = built
    text = (out / "report.html").read_text(encoding="utf-8")
    verdict = text[text.index('id="verdict"'):text.index('id="readings"')]
    assert "virtually all 1350 runs succeeded" in verdict
    assert "only configurations with \u03b2 &gt; 20\u00b0 resulted in acceptable" in verdict
    header = re.search(r"<thead><tr><th>id</th><th>the paper says</th>(.*?)</tr></thead>",
                       verdict).group(1)
    assert re.findall(r"<th>([^<]*)</th>", header) == [
        "default", "plugin-published", "what the data say (default)"]
    # 11 claims x 2 readings verdict cells, coloured by verdict
    assert len(re.findall(r'<td class="cell (holds|fails|unclear)"', verdict)) == 22
    # the deciding figure without its "-> yes" tail
    assert "evidence 1: 12/20 vs 3/20</td>" in verdict


def test_failure_sentence_follows_the_numbers():
    summary = {"failures": _failures(), "source": {"x": 1.0, "y": 0.0}}
    sentence = report.failure_sentence(summary)
    # 8 of the 12 failed runs end at a wall upwind of the source
    assert sentence.startswith("Most failed runs (8 of 12) ended at a wall upwind of the source")
    assert "12 of 60 runs at the paper's fixed values fail (20%)" in sentence
    assert "9 at a wall, 2 by timeout, 1 giving up" in sentence
    assert "0.35 m" in sentence
    # other numbers, another sentence: most failed runs now end far downwind
    summary["failures"] = _failures(upwind_wall=2)
    other = report.failure_sentence(summary)
    assert other.startswith("Most failed runs (10 of 12) ended more than 1 m downwind of the "
                            "source")
    summary["failures"] = {"algorithms": [dict(a, failed=0, walls=0, timeouts=0, gave_up=0,
                                               ends=[]) for a in _failures()["algorithms"]]}
    assert report.failure_sentence(summary) == ("None of the 60 runs at the paper's fixed values "
                                                "failed.")
    assert report.failure_sentence({}) is None


def test_failed_runs_are_shown_next_to_successful_ones(built):
    out, _ = built
    panels = report_sections._trajectory_panels(make_summary())
    assert [(a, k, t is not None) for a, k, t in panels] == [
        ("casting", "success", True), ("casting", "failure", False),
        ("surge-spiral", "success", True), ("surge-spiral", "failure", True),
        ("surge-cast", "success", False), ("surge-cast", "failure", False)]
    text = (out / "report.html").read_text(encoding="utf-8")
    section = text[text.index('id="trajectories"'):text.index('id="claims"')]
    assert '<td class="fails">wall</td>' in section
    assert '<td class="holds">success</td>' in section


def test_overheads_show_the_bootstrap_interval_when_the_summary_has_it():
    p = {"runs": 10, "successes": 5, "overhead": {"n": 5, "mean": 1.02, "lo": 0.97, "hi": 1.07,
                                                  "boot_lo": 1.0, "boot_hi": 1.05}}
    point = report.Point.from_json(p)
    assert (point.oh_lo, point.oh_hi) == (1.0, 1.05)
    assert report.fmt_overhead(point) == "1.02 [1.00, 1.05]"
    # an older summary: its lo and hi are a t interval, which may reach below 1; none is shown
    del p["overhead"]["boot_lo"], p["overhead"]["boot_hi"]
    older = report.Point.from_json(p)
    assert (older.oh_lo, older.oh_hi) == (None, None)
    assert report.fmt_overhead(older) == "1.02"


def test_docs_links_resolve_after_the_report_folder_moves(built, tmp_path):
    out, _ = built
    moved = tmp_path / "elsewhere" / "deeper" / "report"
    shutil.copytree(out, moved)
    for name, pattern in (("report.html", r'<a href="([^"#][^"]*)">'),
                          ("report.md", r"\]\(([^)#\s]+)\)")):
        hrefs = set(re.findall(pattern, (moved / name).read_text(encoding="utf-8")))
        hrefs = {h for h in hrefs if not h.startswith("figures/")}
        assert {"docs/fidelity.md", "docs/model.md", "docs/claims.md"} <= hrefs, name
        for href in hrefs:
            assert not href.startswith("/") and "://" not in href, href
            target = (moved / href).resolve()
            assert target.is_file() and target.is_relative_to(moved.resolve()), href
            assert target.read_bytes() == (page.DOCS_ROOT / href[5:]).read_bytes()
    # the pages they cite link each other within the copy, as in docs/
    for doc in (moved / "docs").glob("*.md"):
        for link in re.findall(r"\]\(([^)#\s:]+\.md)(?:#[^)]*)?\)", doc.read_text()):
            assert (doc.parent / link).is_file(), (doc.name, link)


def test_a_document_the_package_lacks_is_named_not_linked(tmp_path, monkeypatch):
    monkeypatch.setattr(report.page, "DOCS_ROOT", tmp_path / "nowhere")
    assert page._doc_link(tmp_path, "docs/model.md") == ("code", "docs/model.md")
    written = page.write_pages(tmp_path, "t", [page.Para(
        ["see ", page._doc_link(tmp_path, "docs/model.md")])], [])
    assert "<code>docs/model.md</code>" in written[0].read_text()
    assert not (tmp_path / "docs").exists()


def test_readings_section_compares_settings_rates_and_maps(built):
    out, _ = built
    text = (out / "report.html").read_text(encoding="utf-8")
    section = text[text.index('id="readings"'):text.index('id="sets"')]
    assert "plume.amount" in section and "(default)" in section
    # the default column shows the value its runs used where the summary has it
    row = section[section.index("plume.amount"):]
    row = row[:row.index("</tr>")]
    assert "0.75" in row and "(default)" not in row
    assert section.count("/20 = ") == 3 * len(READINGS)
    assert "Wilson 95%" in section and "bootstrap 95%" in section


def test_plume_section_says_which_readings_plumes_contradict_which_sentence(built):
    out, _ = built
    text = (out / "report.md").read_text(encoding="utf-8")
    section = text[text.index("## The plume against the paper's words"):text.index('id="sets"')]
    # the default plume: gaps all shorter than the sets' smallest d_lost, no odor at release
    assert section.splitlines()[0].endswith("the default reading's plume contradicts 2 of 4 "
                                            "sentences")
    assert ("\u201cfiltered through d_lost\u201d is contradicted by the plume of default and "
            "plugin-published") in section
    assert "\u201creleased in the odor\u201d is contradicted by the plume of default;" in section
    assert ("\u201ca spiral will always reacquire the plume\u201d is contradicted by the plume "
            "of plugin-published") in section
    assert "figures/plume_gaps.png" in section
    for sentence in report_sections.PLUME_SENTENCES:
        assert sentence[2] in section


def test_plume_verdicts_follow_the_rules_of_the_plume_statistics_page():
    v = report_sections.plume_verdicts
    smallest = 0.1535
    # rules 1 and 2 count per run (4 traverses): 12 gaps lie above one a run, 4 straddle it,
    # none lies below
    assert v(_plume_stats([0.01] * 12), smallest)["intermittent"][0] == "consistent"
    assert v(_plume_stats([0.01] * 4), smallest)["intermittent"][0] == "unclear"
    steady = v(_plume_stats([]), smallest)
    assert steady["intermittent"][0] == "contradicted"
    assert steady["d_lost"][0] == "contradicted"
    # rule 2 counts the gaps at least the sets' smallest d_lost, at the boundary
    assert v(_plume_stats([0.1535] * 12), smallest)["d_lost"][0] == "consistent"
    below = v(_plume_stats([0.1534] * 12), smallest)["d_lost"]
    assert below[0] == "contradicted" and "0.00 [0.00, 0.92] per run" in below[1]
    # rule 3: one run without odor at release contradicts "in each run"
    assert v(_plume_stats([0.2], in_odor=3), smallest)["released"][0] == "contradicted"
    assert v(_plume_stats([0.2], in_odor=4), smallest)["released"][0] == "consistent"
    # rule 4: every spiral finds odor, one does not, or no surge lost the plume
    assert v(_plume_stats([0.2]), smallest)["spiral"][0] == "consistent"
    failed = v(_plume_stats([0.2], lost=6, reacquired=5), smallest)["spiral"]
    assert failed[0] == "contradicted" and "1 met a wall" in failed[1]
    assert v(_plume_stats([0.2], lost=0, reacquired=0), smallest)["spiral"][0] == "not tested"
    assert report_sections.smallest_d_lost(make_summary()) == 0.1535


def test_poisson_interval_is_close_to_the_exact_one():
    # exact (Garwood) 95% intervals: k = 0: [0, 3.689]; k = 1: [0.0253, 5.572];
    # k = 10: [4.795, 18.39]; k = 100: [81.37, 121.6]
    assert data.poisson_interval(0, 1) == (0.0, pytest.approx(3.689, abs=1e-3))
    for k, lo, hi in ((10, 4.795, 18.39), (100, 81.37, 121.6)):
        got = data.poisson_interval(k, 2.0)
        assert got[0] == pytest.approx(lo / 2, rel=0.01)
        assert got[1] == pytest.approx(hi / 2, rel=0.01)
    assert data.poisson_interval(1, 1)[1] == pytest.approx(5.572, rel=0.01)


def test_summary_with_bad_plume_statistics_names_the_path(tmp_path):
    summary = make_summary()
    summary["readings"][0]["plume_stats"]["along"][0]["longest"] = "x"
    write_json(tmp_path / "summary.json", summary)
    with pytest.raises(report.ReportError, match=r"readings\[0\]\.plume_stats\.along\[0\]\.longest"):
        report.build_report(tmp_path)


def test_summary_with_a_bad_reading_names_its_path(tmp_path):
    summary = make_summary()
    summary["readings"][1]["fixed"][0]["runs"] = "x"
    write_json(tmp_path / "summary.json", summary)
    with pytest.raises(report.ReportError, match=r"readings\[1\]\.fixed\[0\]\.runs"):
        report.build_report(tmp_path)


def test_trajectory_axis_states_the_summary_wind():
    assert figures._wind_text({"wind": {"vx": 0.9, "vy": 0.0}}) == "(wind 0.9 m/s along +x)"
    assert figures._wind_text({"wind": {"vx": 1.0, "vy": 0.2}}) == "(wind 1, 0.2 m/s)"
    assert figures._wind_text({}) == "(wind along +x)"


def test_elapsed_line_says_how_many_runs_came_from_the_store():
    assert "read from the results store" not in data._elapsed_text(
        {"elapsed_s": 55.0, "computed_runs": 100, "total_runs": 100})
    text = data._elapsed_text({"elapsed_s": 0.0, "computed_runs": 0, "total_runs": 20850})
    assert "0 runs computed by this command" in text and "20850 read from the results store" in text


def test_the_regenerate_lines_are_the_commands_the_readme_gives(built):
    out, _ = built
    md = (out / "report.md").read_text()
    page_html = (out / "report.html").read_text()
    # the command that made the report, then the one that redraws it alone from summary.json
    redraw = page.report_command(out)
    assert redraw == f"python3 -m plumetrace.report {out}"
    assert f"plumetrace reproduce --runs 20 --out out/test\n{redraw}\n" in md
    assert html.escape(f"plumetrace reproduce --runs 20 --out out/test\n{redraw}") in page_html
    assert "PYTHONPATH" not in md
    # the README gives the same command for its output folder, in a shell block
    readme = (PYTHON_DIR.parent / "README.md").read_text()
    blocks = re.findall(r"```sh\n(.*?)```", readme, re.S)
    assert any(page.report_command("out") in b.splitlines() for b in blocks)
    # a folder name with a space stays one word
    assert page.report_command("my out") == "python3 -m plumetrace.report 'my out'"


def test_what_would_change_names_the_deciding_part_and_where_the_claim_holds():
    # issue 23, item 7: one sentence per claim that does not hold under the main reading
    def claim(cid, verdict, evidence):
        return {"id": cid, "verdict": verdict, "evidence": evidence}

    summary = {
        "readings": [
            {"name": "default", "main": True, "values": {"plume.amount": 1.0, "wind.vx": 0.9},
             "claims": [claim(1, "holds", "x -> yes"),
                        claim(5, "does not hold", "change +0.8% [-0.4%, +2.0%] -> no"),
                        claim(7, "unclear", "raises -> yes; drop 0.07 [0.04, 0.11] -> unclear")]},
            {"name": "other", "values": {"plume.amount": 8.3e9, "wind.vx": 0.9},
             "claims": [claim(5, "holds", "-> yes"), claim(7, "unclear", "-> unclear")]}],
        "axis_readings": [
            {"name": "sets", "claims": [claim(7, "unclear", "")]},
            {"name": "narrow", "title": "a narrower axis", "claims": [claim(7, "holds", "")]}]}
    changes = dict(report_sections.what_would_change(summary))
    assert set(changes) == {5, 7}  # claim 1 holds: nothing to say
    assert changes[5].startswith("it does not hold on change +0.8% [-0.4%, +2.0%] -> no.")
    assert "the other reading (plume.amount differ)" in changes[5]
    assert "narrow" not in changes[5]
    assert changes[7].startswith("it is unclear on drop 0.07 [0.04, 0.11] -> unclear.")
    assert "raises" not in changes[7]  # a supported part decides nothing
    assert changes[7].endswith("It holds under the narrow axes (a narrower axis).")


def test_what_would_change_words_structured_parts_and_claim_2s_assumed_level():
    # parts with figures (summary.json's `parts`) are worded from their numbers; claim 2's
    # verdict is said to hinge on the assumed level 0.80, with the levels the data would allow
    def part(support, text, est, lo, hi, threshold):
        return {"support": support, "text": text, "estimate": est, "lo": lo, "hi": hi,
                "threshold": threshold}

    def summary(best_hi):
        claim2 = {"id": 2, "verdict": "unclear", "evidence": "", "parts": [
            part("yes", "success lower at small beta: ...", 0.08, 0.003, 0.16, 0.0),
            part("unclear", "beta > 20 acceptable: A ...", 0.788, 0.733, 0.834, 0.8),
            part("unclear", "no beta <= 20 acceptable: best ...", 0.70, 0.60, best_hi, 0.8)]}
        claim5 = {"id": 5, "verdict": "unclear", "evidence": "", "parts": [
            part("unclear", "overhead lower at small d_gap: D ...", 0.008, -0.004, 0.02, 0.0)]}
        return {"readings": [{"name": "default", "main": True, "claims": [claim2, claim5]}]}

    changes = dict(report_sections.what_would_change(summary(0.944)))
    assert changes[5].startswith("it is unclear on overhead lower at small d_gap: +0.008 "
                                 "[-0.004, +0.020] against 0 -> unclear.")
    assert changes[2].startswith("it is unclear on beta > 20 acceptable: 0.788 [0.733, 0.834] "
                                 "against 0.8 -> unclear; no beta <= 20 acceptable: 0.700 "
                                 "[0.600, 0.944] against 0.8 -> unclear.")
    assert "success lower" not in changes[2]
    assert changes[2].endswith("beta > 20 is acceptable at any level up to 0.733, and no "
                               "beta <= 20 at any level above 0.944, so no level makes both "
                               "hold.")
    changes = dict(report_sections.what_would_change(summary(0.70)))
    assert changes[2].endswith("so a level between 0.700 and 0.733 would make both hold.")
