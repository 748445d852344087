"""The report's inputs: summary.json and sensitivity.json read and checked (their format is in
docs/report.md), the views of them that the figures and tables use, and number formatting."""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional, Sequence, Union

SUMMARY_NAME = "summary.json"
SENSITIVITY_NAME = "sensitivity.json"
SUMMARY_FORMAT = 1
SENSITIVITY_FORMAT = 1

DASH = "\u2013"

# Verdict -> (css class, background colour, symbol for the claims matrix), for tables and figures.
VERDICT_STYLE = {
    "holds": ("holds", "#c8e6c9", "\u2713"),
    "does not hold": ("fails", "#ffcdd2", "\u2717"),
    "unclear": ("unclear", "#ffe0a3", "?"),
}
OTHER_VERDICT = ("other", "#e0e0e0", "\u2013")


class ReportError(Exception):
    """A missing or malformed input file; the message starts with the file's path."""


def load_inputs(out_dir: Path) -> tuple:
    """(summary, sensitivity or None) from out_dir, both checked.

    Raises ReportError (whose message names the file) if summary.json is missing or malformed,
    or if sensitivity.json exists but is malformed.
    """
    summary = _check_summary(_load_json(out_dir / SUMMARY_NAME), out_dir / SUMMARY_NAME)
    sens_path = out_dir / SENSITIVITY_NAME
    sens = _check_sensitivity(_load_json(sens_path), sens_path) if sens_path.exists() else None
    return summary, sens


def write_whole(path: Path, content: Union[bytes, str]) -> Path:
    """Writes path whole, as the C++ OutputFile does: into a temporary name of this writer's
    own, then renamed over PATH (plumetrace._files.write_whole).

    why: a reader, or a process killed mid-write, never sees half a report or a figure, and two
    processes drawing one report at once both finish (issue 22, G19)."""
    from .._files import write_whole as whole

    return whole(path, content)


def _load_json(path: Path) -> Any:
    """Parses one JSON file, raising ReportError with the path on any problem. It is read as
    every input is (plumetrace._files.read_input: a regular file, without blocking, bounded)."""
    from .._files import MAX_RESULTS_BYTES, BadPath, read_input

    if not os.path.lexists(path):
        raise ReportError(f"{path}: file not found")
    try:
        text = read_input(path, "report input", MAX_RESULTS_BYTES).decode("utf-8")
    except BadPath as err:
        raise ReportError(str(err)) from None
    except UnicodeDecodeError as err:
        raise ReportError(f"{path}: cannot read: {err}") from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as err:
        raise ReportError(
            f"{path}: not valid JSON: {err.msg} at line {err.lineno}, column {err.colno}"
        ) from None


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


class _Checker:
    """Checks the shape of a parsed file; every failure names the file and the JSON path."""

    def __init__(self, path: Path):
        self.path = path

    def fail(self, where: str, msg: str) -> None:
        raise ReportError(f"{self.path}: {where}: {msg}")

    def obj(self, v: Any, where: str) -> dict:
        if not isinstance(v, dict):
            self.fail(where, f"expected an object, got {_json_type(v)}")
        return v

    def lst(self, v: Any, where: str) -> list:
        if not isinstance(v, list):
            self.fail(where, f"expected an array, got {_json_type(v)}")
        return v

    def num(self, v: Any, where: str, nullable: bool = True) -> None:
        if v is None and nullable:
            return
        if not _is_number(v):
            expected = "a number or null" if nullable else "a number"
            self.fail(where, f"expected {expected}, got {_json_type(v)}")

    def text(self, v: Any, where: str, nullable: bool = False) -> None:
        if v is None and nullable:
            return
        if not isinstance(v, str):
            self.fail(where, f"expected a string, got {_json_type(v)}")

    def numbers(self, v: Any, where: str) -> list:
        for i, x in enumerate(self.lst(v, where)):
            self.num(x, f"{where}[{i}]")
        return v


def _json_type(v: Any) -> str:
    if v is None:
        return "null"
    if isinstance(v, bool):
        return "a boolean"
    if _is_number(v):
        return f"the number {v!r}"
    if isinstance(v, str):
        return f"the string {v!r}" if len(v) < 40 else "a string"
    if isinstance(v, list):
        return "an array"
    if isinstance(v, dict):
        return "an object"
    return type(v).__name__


_POINT_NUMBERS = ("runs", "successes", "walls", "timeouts", "gave_up", "success_rate",
                  "success_lo", "success_hi", "mean_time", "mean_losses")
_OVERHEAD_NUMBERS = ("n", "mean", "lo", "hi", "boot_lo", "boot_hi", "median", "q1", "q3")


def _check_point(c: _Checker, p: Any, where: str, need_value: bool) -> None:
    c.obj(p, where)
    if need_value:
        if "value" not in p:
            c.fail(where, 'missing "value"')
        c.num(p["value"], f"{where}.value")
    for key in ("runs", "successes"):
        if key not in p:
            c.fail(where, f'missing "{key}"')
        c.num(p[key], f"{where}.{key}", nullable=False)
    for key in _POINT_NUMBERS:
        c.num(p.get(key), f"{where}.{key}")
    oh = p.get("overhead")
    if oh is not None:
        c.obj(oh, f"{where}.overhead")
        for key in _OVERHEAD_NUMBERS:
            c.num(oh.get(key), f"{where}.overhead.{key}")
    c.text(p.get("config_hash"), f"{where}.config_hash", nullable=True)


def _check_summary(data: Any, path: Path) -> dict:
    c = _Checker(path)
    if not isinstance(data, dict):
        raise ReportError(f"{path}: expected a JSON object at the top, got {_json_type(data)}")
    if "plumetrace_summary" not in data:
        raise ReportError(f'{path}: not a plumetrace summary (no "plumetrace_summary" key)')
    if data["plumetrace_summary"] != SUMMARY_FORMAT:
        raise ReportError(
            f"{path}: summary format {data['plumetrace_summary']!r} is not supported "
            f"(this report reads format {SUMMARY_FORMAT})"
        )
    for key in ("version", "generated_by", "preset", "config_toml"):
        c.text(data.get(key), key, nullable=True)
    for key in ("seed", "runs_per_point", "total_runs", "elapsed_s", "threads"):
        c.num(data.get(key), key)

    if "sets" not in data:
        raise ReportError(f'{path}: missing "sets"')
    for i, s in enumerate(c.lst(data["sets"], "sets")):
        where = f"sets[{i}]"
        c.obj(s, where)
        c.text(s.get("name"), f"{where}.name")
        for key in ("title", "algorithm", "key", "label"):
            c.text(s.get(key), f"{where}.{key}", nullable=True)
        c.num(s.get("fixed_index"), f"{where}.fixed_index")
        if "values" in s:
            c.numbers(s["values"], f"{where}.values")
        for j, p in enumerate(c.lst(s.get("points"), f"{where}.points")):
            _check_point(c, p, f"{where}.points[{j}]", need_value=True)

    for i, cl in enumerate(c.lst(data.get("claims") or [], "claims")):
        where = f"claims[{i}]"
        c.obj(cl, where)
        c.text(cl.get("text"), f"{where}.text")
        c.text(cl.get("verdict"), f"{where}.verdict")
        c.text(cl.get("evidence"), f"{where}.evidence", nullable=True)
    if data.get("rules_030") is not None:
        _check_old_rules(c, data["rules_030"], "rules_030")
    for i, a in enumerate(c.lst(data.get("axis_readings") or [], "axis_readings")):
        c.obj(a, f"axis_readings[{i}]")
        if a.get("rules_030") is not None:
            _check_old_rules(c, a["rules_030"], f"axis_readings[{i}].rules_030")

    sens = data.get("sensitivity")
    if sens is not None:
        c.obj(sens, "sensitivity")
        for i, v in enumerate(c.lst(sens.get("variants") or [], "sensitivity.variants")):
            c.text(v, f"sensitivity.variants[{i}]")
        for i, row in enumerate(c.lst(sens.get("rows") or [], "sensitivity.rows")):
            where = f"sensitivity.rows[{i}]"
            _check_point(c, row, where, need_value=False)
            c.text(row.get("algorithm"), f"{where}.algorithm")
            c.text(row.get("variant"), f"{where}.variant")

    for i, t in enumerate(c.lst(data.get("trajectories") or [], "trajectories")):
        where = f"trajectories[{i}]"
        c.obj(t, where)
        c.text(t.get("algorithm"), f"{where}.algorithm")
        xs = c.numbers(t.get("x"), f"{where}.x")
        ys = c.numbers(t.get("y"), f"{where}.y")
        if len(xs) != len(ys):
            c.fail(where, f"x has {len(xs)} entries but y has {len(ys)}")
        for key in ("state", "odor"):
            if t.get(key) is not None and len(c.lst(t[key], f"{where}.{key}")) != len(xs):
                c.fail(f"{where}.{key}", f"has {len(t[key])} entries, x has {len(xs)}")
    for i, m in enumerate(c.lst(data.get("trajectories_missing") or [], "trajectories_missing")):
        c.text(m, f"trajectories_missing[{i}]")

    if data.get("detection_map") is not None:
        _check_map(c, data["detection_map"], "detection_map")

    for key, fields in (("arena", ("x_min", "x_max", "y_min", "y_max")),
                        ("source", ("x", "y", "radius", "success_radius"))):
        if data.get(key) is not None:
            c.obj(data[key], key)
            for f in fields:
                c.num(data[key].get(f), f"{key}.{f}")

    for i, r in enumerate(c.lst(data.get("readings") or [], "readings")):
        where = f"readings[{i}]"
        c.obj(r, where)
        c.text(r.get("name"), f"{where}.name")
        c.text(r.get("file"), f"{where}.file", nullable=True)
        for key in ("held", "not_held", "unclear", "success_radius"):
            c.num(r.get(key), f"{where}.{key}")
        if r.get("settings") is not None:
            c.obj(r["settings"], f"{where}.settings")
        for j, cl in enumerate(c.lst(r.get("claims") or [], f"{where}.claims")):
            c.obj(cl, f"{where}.claims[{j}]")
            c.text(cl.get("verdict"), f"{where}.claims[{j}].verdict")
        if r.get("rules_030") is not None:
            _check_old_rules(c, r["rules_030"], f"{where}.rules_030")
        for j, p in enumerate(c.lst(r.get("fixed") or [], f"{where}.fixed")):
            _check_point(c, p, f"{where}.fixed[{j}]", need_value=False)
            c.text(p.get("algorithm"), f"{where}.fixed[{j}].algorithm")
        if r.get("detection_map") is not None:
            _check_map(c, r["detection_map"], f"{where}.detection_map")
        if r.get("plume_stats") is not None:
            _check_plume_stats(c, r["plume_stats"], f"{where}.plume_stats")

    fails = data.get("failures")
    if fails is not None:
        c.obj(fails, "failures")
        for i, a in enumerate(c.lst(fails.get("algorithms") or [], "failures.algorithms")):
            where = f"failures.algorithms[{i}]"
            c.obj(a, where)
            c.text(a.get("algorithm"), f"{where}.algorithm")
            for key in FAILURE_NUMBERS:
                c.num(a.get(key), f"{where}.{key}")

    for i, sw in enumerate(c.lst(data.get("sweeps") or [], "sweeps")):
        c.obj(sw, f"sweeps[{i}]")
    return data


FAILURE_NUMBERS = ("runs", "failed", "walls", "timeouts", "gave_up", "examined", "end_upwind",
                   "end_upwind_wall", "end_within_1m", "passed_source", "came_within_0_5m",
                   "closest_median_m", "end_distance_median_m")


def _check_old_rules(c: "_Checker", old: Any, where: str) -> None:
    """The verdicts under rules 0.3.0 beside a reading's."""
    c.obj(old, where)
    for key in ("held", "not_held", "unclear"):
        if old.get(key) is not None:
            c.num(old.get(key), f"{where}.{key}")
    for j, cl in enumerate(c.lst(old.get("claims") or [], f"{where}.claims")):
        c.obj(cl, f"{where}.claims[{j}]")
        c.text(cl.get("verdict"), f"{where}.claims[{j}].verdict")


def _check_map(c: "_Checker", dmap: Any, where: str) -> None:
    c.obj(dmap, where)
    xs = c.numbers(dmap.get("x"), f"{where}.x")
    ys = c.numbers(dmap.get("y"), f"{where}.y")
    rows = c.lst(dmap.get("fraction"), f"{where}.fraction")
    if len(rows) != len(ys):
        c.fail(f"{where}.fraction", f"has {len(rows)} rows, y has {len(ys)} entries")
    for j, row in enumerate(rows):
        if len(c.numbers(row, f"{where}.fraction[{j}]")) != len(xs):
            c.fail(f"{where}.fraction[{j}]", f"has {len(row)} entries, x has {len(xs)}")


GAP_NUMBERS = ("paths", "paths_with_odor", "samples", "detections", "detected_fraction", "gaps",
               "median", "p90", "longest", "longer_than_d_lost", "fraction_longer")
RELEASE_NUMBERS = ("trials", "in_odor", "within_d_lost")
SPIRAL_NUMBERS = ("surges", "lost", "within_one_turn", "reacquired", "walls", "out_of_turns",
                  "distance_median")


def _check_plume_stats(c: "_Checker", ps: Any, where: str) -> None:
    """A reading's plume statistics (docs/plume-statistics.md; keys in docs/report.md)."""
    c.obj(ps, where)
    for key in ("trials", "d_lost", "speed", "turns"):
        c.num(ps.get(key), f"{where}.{key}")
    for part, own in (("along", "offset"), ("across", "distance")):
        for i, line in enumerate(c.lst(ps.get(part) or [], f"{where}.{part}")):
            at = f"{where}.{part}[{i}]"
            c.obj(line, at)
            c.num(line.get(own), f"{at}.{own}", nullable=False)
            for key in GAP_NUMBERS + ("leading_median", "band_median", "band_max"):
                c.num(line.get(key), f"{at}.{key}")
            for key in ("lengths", "band_widths"):
                if line.get(key) is not None:
                    c.numbers(line[key], f"{at}.{key}")
    for part, keys in (("release", RELEASE_NUMBERS), ("spirals", SPIRAL_NUMBERS)):
        if ps.get(part) is not None:
            c.obj(ps[part], f"{where}.{part}")
            for key in keys:
                c.num(ps[part].get(key), f"{where}.{part}.{key}")


def _check_sensitivity(data: Any, path: Path) -> dict:
    c = _Checker(path)
    if not isinstance(data, dict):
        raise ReportError(f"{path}: expected a JSON object at the top, got {_json_type(data)}")
    if "plumetrace_sensitivity" not in data:
        raise ReportError(
            f'{path}: not a plumetrace sensitivity file (no "plumetrace_sensitivity" key)')
    if data["plumetrace_sensitivity"] != SENSITIVITY_FORMAT:
        raise ReportError(
            f"{path}: sensitivity format {data['plumetrace_sensitivity']!r} is not supported "
            f"(this report reads format {SENSITIVITY_FORMAT})"
        )
    c.num(data.get("runs_per_point"), "runs_per_point")
    c.num(data.get("elapsed_s"), "elapsed_s")
    claims = c.lst(data.get("claims") or [], "claims")
    for i, cl in enumerate(claims):
        c.obj(cl, f"claims[{i}]")
        c.text(cl.get("text"), f"claims[{i}].text")
    if "rows" not in data:
        raise ReportError(f'{path}: missing "rows"')
    for i, row in enumerate(c.lst(data["rows"], "rows")):
        where = f"rows[{i}]"
        c.obj(row, where)
        c.text(row.get("noise_mode"), f"{where}.noise_mode", nullable=True)
        c.text(row.get("kernel"), f"{where}.kernel", nullable=True)
        c.num(row.get("success_radius"), f"{where}.success_radius")
        verdicts = c.lst(row.get("verdicts"), f"{where}.verdicts")
        for j, v in enumerate(verdicts):
            c.text(v, f"{where}.verdicts[{j}]")
        if claims and len(verdicts) != len(claims):
            c.fail(f"{where}.verdicts", f"has {len(verdicts)} entries for {len(claims)} claims")
        c.num(row.get("held"), f"{where}.held")
    return data


def _num(v: Any) -> Optional[float]:
    """A finite float, or None for null, missing or non-finite values."""
    if not _is_number(v):
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def _int(v: Any) -> Optional[int]:
    x = _num(v)
    return None if x is None else int(round(x))


@dataclass
class Point:
    """One sweep point (or one sensitivity row) with every field made safe to use."""

    value: Optional[float]
    runs: int
    successes: int
    walls: Optional[int]
    timeouts: Optional[int]
    gave_up: Optional[int]
    rate: Optional[float]
    rate_lo: Optional[float]
    rate_hi: Optional[float]
    oh_n: int
    oh_mean: Optional[float]
    oh_lo: Optional[float]  # the percentile bootstrap 95% interval of the mean (None: unknown)
    oh_hi: Optional[float]
    oh_median: Optional[float]
    oh_q1: Optional[float]
    oh_q3: Optional[float]
    mean_time: Optional[float]
    mean_losses: Optional[float]
    config_hash: Optional[str]

    @staticmethod
    def from_json(p: dict) -> "Point":
        """A point of summary.json or results.json. The overhead's interval is the percentile
        bootstrap's (boot_lo, boot_hi), which plumetrace writes into every file; a file without
        them is older, and its lo and hi are t intervals, which can reach below 1, the least
        overhead there is: such a point shows its mean without an interval."""
        runs = _int(p.get("runs")) or 0
        successes = _int(p.get("successes")) or 0
        rate = _num(p.get("success_rate"))
        if rate is None and runs > 0:
            rate = successes / runs
        # why: the C++ writes every point's Wilson interval (stats_json); none is recomputed here
        lo, hi = _num(p.get("success_lo")), _num(p.get("success_hi"))
        oh = p.get("overhead") or {}
        oh_n = _int(oh.get("n"))
        return Point(
            value=_num(p.get("value")),
            runs=runs,
            successes=successes,
            walls=_int(p.get("walls")),
            timeouts=_int(p.get("timeouts")),
            gave_up=_int(p.get("gave_up")),
            rate=rate,
            rate_lo=lo,
            rate_hi=hi,
            oh_n=successes if oh_n is None else oh_n,
            oh_mean=_num(oh.get("mean")),
            oh_lo=_num(oh.get("boot_lo")),
            oh_hi=_num(oh.get("boot_hi")),
            oh_median=_num(oh.get("median")),
            oh_q1=_num(oh.get("q1")),
            oh_q3=_num(oh.get("q3")),
            mean_time=_num(p.get("mean_time")),
            mean_losses=_num(p.get("mean_losses")),
            config_hash=p.get("config_hash"),
        )


@dataclass
class SweepSet:
    name: str
    title: str
    algorithm: str
    key: str
    label: str
    fixed_index: Optional[int]
    points: list

    @staticmethod
    def from_json(s: dict) -> "SweepSet":
        points = [Point.from_json(p) for p in s.get("points") or []]
        fixed = _int(s.get("fixed_index"))
        if fixed is not None and not 0 <= fixed < len(points):
            fixed = None
        return SweepSet(
            name=str(s["name"]),
            title=s.get("title") or "",
            algorithm=s.get("algorithm") or "",
            key=s.get("key") or "",
            label=s.get("label") or s.get("key") or "value",
            fixed_index=fixed,
            points=points,
        )

    @property
    def fixed_value(self) -> Optional[float]:
        return None if self.fixed_index is None else self.points[self.fixed_index].value


def _readings(summary: dict) -> list:
    """The readings in the summary, the main one first; a summary without them has one, built
    from its own claims."""
    readings = list(summary.get("readings") or [])
    if not readings:
        claims = summary.get("claims") or []
        counts = _verdict_counts(claims)
        readings = [{"name": summary.get("preset") or "main", "main": True, "claims": claims,
                     "held": counts["holds"], "not_held": counts["does not hold"],
                     "unclear": counts["unclear"]}]
        if summary.get("rules_030") is not None:
            readings[0]["rules_030"] = summary["rules_030"]
    readings.sort(key=lambda r: not r.get("main"))
    return readings


def poisson_interval(k: int, exposure: float) -> tuple:
    """The 95% interval of a Poisson rate from `k` events over `exposure` units: Byar's
    approximation of the exact (Garwood) interval, within 1% of it from k = 2 on, with the exact
    upper end ln(40) at k = 0 and lower end 0."""
    z = 1.959963984540054
    if k == 0:
        return 0.0, math.log(40.0) / exposure
    lo = k * (1.0 - 1.0 / (9.0 * k) - z / (3.0 * math.sqrt(k))) ** 3
    hi = (k + 1) * (1.0 - 1.0 / (9.0 * (k + 1)) + z / (3.0 * math.sqrt(k + 1))) ** 3
    return lo / exposure, hi / exposure


def _centreline(ps: Optional[dict]) -> Optional[dict]:
    """The upwind line at offset 0 of a reading's plume statistics, or None."""
    for line in (ps or {}).get("along") or []:
        if _num(line.get("offset")) == 0.0:
            return line
    return None


def _verdict_counts(claims: list) -> dict:
    counts = {v: 0 for v in VERDICT_STYLE}
    for cl in claims:
        key = (cl.get("verdict") or "").strip().lower()
        if key in counts:
            counts[key] += 1
    return counts


def _held(reading: dict) -> tuple:
    """(holds, does not hold, unclear, claims) of a reading."""
    claims = reading.get("claims") or []
    counts = _verdict_counts(claims)
    held = _int(reading.get("held"))
    return (counts["holds"] if held is None else held, counts["does not hold"],
            counts["unclear"], len(claims))


def _old_rules(entry: dict) -> Optional[dict]:
    """The verdicts of a reading (or axis reading, or summary) under rules 0.3.0, computed beside
    the rules in force (docs/claims.md, "Two rule sets"); None in a summary without them."""
    old = entry.get("rules_030")
    return old if isinstance(old, dict) and isinstance(old.get("claims"), list) else None


def _rules_name(summary: dict) -> str:
    """The rules the summary's verdicts use: "0.4", or "0.3.0" for a summary written before
    rules had names."""
    return str(summary.get("rules") or "0.3.0")


def _fixed_points(reading: dict) -> dict:
    return {p.get("algorithm"): Point.from_json(p) for p in reading.get("fixed") or []}


def _sensitivity_grid(sens: dict, order: Sequence[str]):
    """(variants, algorithms, {(algorithm, variant): Point}) in a stable order: the algorithms
    in `order` first, then any other as the file lists them."""
    rows = sens.get("rows") or []
    variants = list(sens.get("variants") or [])
    for r in rows:
        if r["variant"] not in variants:
            variants.append(r["variant"])
    algorithms = [a for a in order if any(r["algorithm"] == a for r in rows)]
    algorithms += [a for a in dict.fromkeys(r["algorithm"] for r in rows) if a not in algorithms]
    grid = {(r["algorithm"], r["variant"]): Point.from_json(r) for r in rows}
    return variants, algorithms, grid


def fmt_value(v: Optional[float]) -> str:
    if v is None:
        return DASH
    if v == int(v) and abs(v) < 1e15:
        return str(int(v))
    return f"{v:.6g}"


def fmt_raw_int(v: Any) -> str:
    """An integer field (a seed, a trial) exactly as the file gives it, even above 2**53."""
    if isinstance(v, int) and not isinstance(v, bool):
        return str(v)
    return fmt_value(_num(v))


def fmt_pct(v: Optional[float]) -> str:
    return DASH if v is None else f"{100 * v:.0f}%"


def fmt_rate(p: Point) -> str:
    if p.rate is None:
        return DASH
    if p.rate_lo is None or p.rate_hi is None:
        return fmt_pct(p.rate)
    return f"{fmt_pct(p.rate)} [{100 * p.rate_lo:.0f}, {100 * p.rate_hi:.0f}]"


def fmt_oh(v: Optional[float]) -> str:
    return DASH if v is None else f"{v:.2f}"


def fmt_overhead(p: Point) -> str:
    if p.oh_mean is None:
        return "no successful run" if p.oh_n == 0 else DASH
    if p.oh_lo is None or p.oh_hi is None:
        return fmt_oh(p.oh_mean)
    return f"{fmt_oh(p.oh_mean)} [{fmt_oh(p.oh_lo)}, {fmt_oh(p.oh_hi)}]"


def fmt_median(p: Point) -> str:
    if p.oh_median is None:
        return DASH
    if p.oh_q1 is None or p.oh_q3 is None:
        return fmt_oh(p.oh_median)
    return f"{fmt_oh(p.oh_median)} [{fmt_oh(p.oh_q1)}, {fmt_oh(p.oh_q3)}]"


def fmt_count(v: Optional[int]) -> str:
    return DASH if v is None else str(v)


def fmt_outcomes(p: Point) -> str:
    return " / ".join(fmt_count(v) for v in (p.successes, p.walls, p.timeouts, p.gave_up))


def fmt_duration(seconds: Optional[float]) -> str:
    if seconds is None:
        return DASH
    if seconds < 60:
        return f"{seconds:.1f} s"
    minutes, sec = divmod(int(round(seconds)), 60)
    hours, minutes = divmod(minutes, 60)
    parts = f"{hours} h {minutes} min" if hours else f"{minutes} min {sec} s"
    return f"{seconds:.1f} s ({parts})"


def _elapsed_text(summary: dict) -> str:
    """The run time of the command that wrote the summary, and how many of its runs it
    computed: a report redrawn from a full store took no time to run anything."""
    text = fmt_duration(_num(summary.get("elapsed_s")))
    computed, total = _num(summary.get("computed_runs")), _num(summary.get("total_runs"))
    if computed is not None and total is not None and computed < total:
        text += (f" ({fmt_value(computed)} runs computed by this command, "
                 f"{fmt_value(total - computed)} read from the results store)")
    return text


def verdict_style(verdict: Optional[str]):
    return VERDICT_STYLE.get((verdict or "").strip().lower(), OTHER_VERDICT)
