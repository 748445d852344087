"""Controllers written in Python run in the same loop and sweep as the built-in ones."""

import importlib.util
import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()

ROOT = Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("python_surge_cast", ROOT / "examples" / "python_surge_cast.py")
example = importlib.util.module_from_spec(spec)
spec.loader.exec_module(example)


def test_python_surge_cast_equals_the_built_in_run_for_run():
    for trial in range(6):
        for sigma in (0.0, 0.5):
            mine = pt.run(algorithm="py-surge-cast", seed=13, trial=trial, wind_sensor__sigma_a=sigma)
            builtin = pt.run(algorithm="surge-cast", seed=13, trial=trial, wind_sensor__sigma_a=sigma)
            for key in ("outcome", "time_s", "d_t", "d_u", "losses", "odor_fraction", "steps",
                        "wind_samples"):
                assert mine[key] == builtin[key], (trial, sigma, key)
            assert mine["trajectory"]["state"] == builtin["trajectory"]["state"]
            assert np.array_equal(mine["trajectory"]["x"], builtin["trajectory"]["x"])


def test_python_surge_cast_sweeps_its_own_key_like_the_built_in(tmp_path):
    def sweep_file(algorithm, table):
        path = tmp_path / f"{table}.toml"
        path.write_text(f"""
name = "sc"
scenario = "{ROOT / 'scenarios' / 'lochmatter2008.toml'}"
runs = 3
seed = 99
[set]
controller.algorithm = "{algorithm}"
robot.start_x = 6.0
wind_sensor.sigma_a = 0.3  # noise enough that the robot loses the plume and casts
[[axis]]
key = "{table}.d_cast"
values = [0.135, 0.27, 0.54]
""")
        return path

    mine = pt.sweep(sweep_file("py-surge-cast", "py_surge_cast"), threads=2).to_numpy()
    builtin = pt.sweep(sweep_file("surge-cast", "surge_cast"), threads=2).to_numpy()
    assert list(mine["py_surge_cast.d_cast"]) == list(builtin["surge_cast.d_cast"])
    for key in ("outcome", "d_t", "d_u", "time_s", "losses", "steps"):
        assert np.array_equal(mine[key], builtin[key]), key
    # the values make a difference, so the equality shows each point ran with its own
    assert len({tuple(mine["d_t"][mine["point"] == p]) for p in range(3)}) > 1


def _same_columns(a, b):
    """Whether two sweeps' rows are the same, bit for bit: columns, dtypes and bytes."""
    assert a.keys() == b.keys()
    for key in a.keys():
        x, y = np.asarray(a[key]), np.asarray(b[key])
        assert x.dtype == y.dtype and x.shape == y.shape, key
        if x.dtype == object:
            assert list(x) == list(y), key
        else:
            assert x.tobytes() == y.tobytes(), key


def test_a_python_controller_sweep_in_worker_processes_equals_one_process_bit_for_bit(tmp_path):
    # a registered Python controller beside a built-in one on the same plumes, a team whose
    # second robot runs it, and a factory: two worker processes give the rows of one process
    base = pt.Scenario(robot__start_x=4.0, supervisor__timeout=30.0)
    axes = {"controller.algorithm": ["py-surge-cast", "surge-cast"],
            "wind_sensor.sigma_a": [0.0, 0.3]}
    one, two = (pt.sweep(axes, runs=2, base=base, threads=n) for n in (1, 2))
    _same_columns(one, two)
    assert set(one["outcome"]) == {"success", "timeout"}
    team = base.copy()
    team.update({"team.count": 2, "member.1.controller.algorithm": "py-surge-cast"})
    _same_columns(pt.sweep({"wind_sensor.sigma_a": [0.3]}, runs=2, base=team, threads=1),
                  pt.sweep({"wind_sensor.sigma_a": [0.3]}, runs=2, base=team, threads=2))
    # a factory's controllers are built in the workers, two of them, and not here
    built = tmp_path / "built.txt"

    def factory(scenario, rng):
        with open(built, "a") as f:
            f.write(f"{os.getpid()}\n")
        return example.SurgeCast({"d_cast": 0.27, "d_lost": 0.614}, rng)

    axis = {"wind_sensor.sigma_a": [0.0, 0.3]}
    rows = {n: pt.sweep(axis, runs=2, base=base, threads=n, controller=factory) for n in (2, 1)}
    _same_columns(rows[1], rows[2])
    pids = [int(p) for p in built.read_text().split()]
    assert len(pids) == 8 and pids[4:] == [os.getpid()] * 4
    assert len(set(pids[:4])) == 2 and os.getpid() not in pids[:4]
    # processes=False keeps them here
    built.unlink()
    _same_columns(rows[1], pt.sweep(axis, runs=2, base=base, threads=2, controller=factory,
                                    processes=False))
    assert set(built.read_text().split()) == {str(os.getpid())}

# a controller of one's own with keys of its own: it zigzags upwind, legs of `leg` metres, and
# gives up after `turns` legs
def _zigzag_class(seen):
    from plumetrace.controllers import Controller

    class Zig(Controller):
        params = {
            "leg": pt.Param(0.5, min=0.1, max=5.0, help="path length of each leg (m)"),
            "turns": pt.Param(1000, min=1, help="legs before it gives up"),
            "first": pt.Param("left", choices=["left", "right"], help="side of the first leg"),
        }

        def __init__(self, params, rng):
            super().__init__(params, rng)
            seen.append(dict(params))
            self.side = 1 if params.first == "left" else -1
            self.start = 0.0
            self.legs = 0
            self.heading = None

        def step(self, obs, wind):
            if self.heading is None or obs.odometer - self.start >= self.params.leg:
                if self.heading is not None:
                    self.side, self.legs = -self.side, self.legs + 1
                if self.legs >= self.params.turns:
                    return self.abandon()
                self.heading = self.measure_upwind(wind, obs) + self.side * 0.7
                self.start = obs.odometer
            return self.go(self.heading)

    return Zig


def test_a_registered_python_controller_has_config_keys_of_its_own(tmp_path):
    seen = []
    pt.register_controller("zigzag", _zigzag_class(seen))
    assert "zigzag" in pt.algorithms()
    s = pt.Scenario(controller__algorithm="zigzag")
    toml = s.to_toml()
    assert "[zigzag]\nleg = 0.5  # path length of each leg (m)\n" in toml
    assert "turns = 1000  # legs before it gives up\n" in toml
    assert "first = \"left\"" in toml
    s.zigzag.leg = 1.25
    assert s["zigzag.leg"] == 1.25
    # checked against the declared range and type, naming the key
    with pytest.raises(pt.ConfigError, match=r"zigzag\.leg: must be a number >= 0\.1 and <= 5"):
        s["zigzag.leg"] = 7.0
    with pytest.raises(pt.ConfigError, match=r"zigzag\.first: must be one of 'left', 'right'"):
        s["zigzag.first"] = "up"
    with pytest.raises(pt.ConfigError, match=r"unknown config key 'zigzag\.legs'.*zigzag\.leg"):
        s["zigzag.legs"] = 1.0
    # a run sees its values; the result names the controller
    r = pt.run(s, seed=3, trial=1, trace=False, zigzag__turns=4, zigzag__first="right")
    assert seen[-1] == {"leg": 1.25, "turns": 4, "first": "right"}
    assert r["algorithm"] == "zigzag" and r["outcome"] == "gave_up"
    assert r["d_t"] == pytest.approx(4 * 1.25, abs=0.02)
    # a sweep axis over its key: each value a point of its own, resolved and run with it
    sweep = tmp_path / "zig.toml"
    sweep.write_text("""
name = "zig"
runs = 2
seed = 5
[set]
controller.algorithm = "zigzag"
zigzag.turns = 3
[[axis]]
key = "zigzag.leg"
values = [0.5, 1.5]
""")
    seen.clear()
    rows = pt.sweep(sweep, threads=1).to_numpy()
    assert list(rows["zigzag.leg"]) == [0.5, 0.5, 1.5, 1.5]
    assert sorted(v["leg"] for v in seen) == [0.5, 0.5, 1.5, 1.5]
    assert list(rows["d_t"] > 3 * rows["zigzag.leg"] - 0.01) == [True] * 4
    # the resolved configs of the two points differ (their hashes identify the points)
    a = pt.Scenario(controller__algorithm="zigzag", zigzag__leg=0.5).to_toml()
    b = pt.Scenario(controller__algorithm="zigzag", zigzag__leg=1.5).to_toml()
    assert a != b and a.replace("leg = 0.5", "leg = 1.5") == b


def test_registering_again_replaces_and_bad_registrations_name_the_problem():
    from plumetrace.controllers import Controller

    class One(Controller):
        params = {"size": pt.Param(2, min=1, max=9, help="a size")}

        def step(self, obs, wind):
            return self.abandon()

    pt.register_controller("again", One)
    assert pt.Scenario()["again.size"] == 2
    pt.register_controller("again", One, params={"width": pt.Param(0.3, help="a width")})
    assert pt.Scenario()["again.width"] == 0.3
    with pytest.raises(pt.ConfigError, match="unknown config key 'again.size'"):
        pt.Scenario()["again.size"]
    assert pt.algorithms().count("again") == 1
    # names: a built-in's, a table of the scenario, not a name at all
    for name, message in [("surge-cast", "taken by a controller of the library"),
                          ("robot", "'robot' is a table of the scenario"),
                          ("controller", "is a table of the scenario"),
                          ("member", "'member' is a table of the scenario"),
                          ("meander", "is a table of the scenario"),
                          ("first-order", "is a table of the scenario"),
                          ("two words", "letters, digits"), ("", "letters, digits")]:
        with pytest.raises(pt.ConfigError, match=message):
            pt.register_controller(name, One)
    # declarations: a default outside its range, a key that is no Param, a bad key name
    with pytest.raises(ValueError, match=r"Param: the default 0 is not within"):
        pt.Param(0, min=1)
    with pytest.raises(TypeError, match=r"bad\.size: declare it with plumetrace\.Param"):
        pt.register_controller("bad", One, params={"size": 3})
    with pytest.raises(pt.ConfigError, match=r"bad\.two words: a key's name"):
        pt.register_controller("bad", One, params={"two words": pt.Param(1.0)})
    with pytest.raises(ValueError, match="not one of"):
        pt.Param("up", choices=["left", "right"])
    assert "bad" not in pt.algorithms()


def test_no_controller_is_registered_while_runs_are_in_flight(tmp_path):
    from plumetrace.controllers import Controller

    class Registers(Controller):
        def step(self, obs, wind):
            pt.register_controller("late", Registers)
            return self.abandon()

    pt.register_controller("registers", Registers)
    with pytest.raises(RuntimeError, match="runs are in progress"):
        pt.run(algorithm="registers", trace=False)
    assert "late" not in pt.algorithms()
    # once the run is over, registering works again (and leaves a harmless "registers")
    pt.register_controller("registers", _zigzag_class([]))


def test_a_controller_sees_measurements_only():
    seen = []

    from plumetrace.controllers import Controller

    class Probe(Controller):
        def __init__(self, scenario, rng):
            pass

        def step(self, obs, wind):
            seen.append((obs.time, obs.odor, obs.odometry.x, obs.odometry.y, obs.odometry.heading))
            return self.go(0.0) if len(seen) < 50 else self.abandon()

    r = pt.run(controller=Probe, seed=1, trace=False)
    assert r["outcome"] == "gave_up" and r["steps"] == 50
    # odometry starts at the release pose: (0, 0) heading 0, whatever the arena frame
    assert seen[0][2:] == (0.0, 0.0, 0.0)


def test_the_examples_run(tmp_path):
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "python_surge_cast.py")],
                         check=True, capture_output=True, text=True).stdout
    assert out.count("identical to the built-in: True") == 3
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "python_env_and_plots.py"),
                          str(tmp_path)], check=True, capture_output=True, text=True).stdout
    assert out.count("episode") == 3
    assert (tmp_path / "trajectory.png").stat().st_size > 10000
    assert (tmp_path / "sweep.png").stat().st_size > 10000


def _page_data(path):
    html = Path(path).read_text()
    start = html.index('<script id="plumetrace-data" type="application/json">')
    start = html.index(">", start) + 1
    return json.loads(html[start:html.index("</script>", start)])


def test_runs_from_python_open_in_the_viewer(tmp_path):
    # a built-in run: the same page as `plumetrace run --view`, byte for byte
    mine = tmp_path / "casting.html"
    pt.run(algorithm="casting", seed=3, trial=1, view=mine, robot__start_x=6.0)
    cli = tmp_path / "cli.html"
    subprocess.run([os.environ["PLUMETRACE_CLI"], "run", "--algorithm", "casting", "--seed", "3",
                    "--trial", "1", "--set", "robot.start_x=6", "--view", str(cli)],
                   check=True, capture_output=True)
    assert mine.read_bytes() == cli.read_bytes()

    # a Python controller's run: its states and its name reach the page and the figure
    r = pt.run(algorithm="py-surge-cast", seed=13, trial=0, view=tmp_path / "mine.html")
    data = _page_data(tmp_path / "mine.html")
    assert data["result"]["algorithm"] == "py-surge-cast"
    assert data["steps"] == r["steps"] + 1
    assert set(data["states"]) == set(r["trajectory"]["state"])
    pt.run(algorithm="py-surge-cast", view=tmp_path / "mine.svg")
    assert (tmp_path / "mine.svg").read_text().startswith("<svg")

    with pytest.raises(ValueError, match="view 'x.png'"):
        pt.run(view="x.png")


# -- G11: every field of a Param, of any type, is taken or refused naming it -------------------

class _Abandons:
    def __init__(self, params, rng):
        self.params = params

    def step(self, obs, wind):
        return pt.controllers.Command.abandon()


class _BadRepr:
    def __repr__(self):
        raise RuntimeError("no repr")


# (field, value): values no Param takes, each refused with the field named
_REFUSED = [
    ("default", "abc"), ("default", None), ("default", True), ("default", np.bool_(False)),
    ("default", 2**70), ("default", -2**31 - 1), ("default", math.nan), ("default", math.inf),
    ("default", 1 + 2j), ("default", [1.0]), ("default", _BadRepr()),
    ("min", "abc"), ("min", True), ("min", math.nan), ("min", [0.0]), ("min", 10**400),
    ("min", 1 + 0j), ("min", _BadRepr()),
    ("max", "1"), ("max", np.bool_(True)), ("max", -math.inf), ("max", {"a": 1}),
    ("min_open", 1), ("min_open", None), ("min_open", "yes"), ("max_open", 0.0),
    ("help", None), ("help", 3), ("help", "two\nlines"), ("help", "\ud800"), ("help", b"x"),
    ("choices", "ab"), ("choices", {"a", "b"}), ("choices", 3),
]


@pytest.mark.parametrize("field, value", _REFUSED,
                         ids=[f"{f}-{type(v).__name__}-{i}" for i, (f, v) in enumerate(_REFUSED)])
def test_param_fields_of_a_wrong_type_or_value_are_refused_naming_the_field(field, value):
    with pytest.raises((TypeError, ValueError)) as caught:
        pt.Param(**{"default": 1.5, field: value})
    message = str(caught.value)
    assert type(caught.value) in (TypeError, ValueError)
    assert message.startswith("Param: ") and re.search(rf"\b{field}\b", message), message


def test_param_of_the_report_is_refused_naming_the_key_and_min_at_registration():
    # the finding: pybind's "Unable to cast Python instance to C++ type" at registration
    with pytest.raises(TypeError, match=r"^Param: min 'abc' \(str\) is not a number$"):
        pt.Param(1.0, min="abc")
    with pytest.raises(ValueError, match=r"^Param: default 1180591620717411303424 is out of"):
        pt.Param(2**70)
    # a field changed after the Param was made is caught when the key is registered
    for field, value, error in [("min", "abc", TypeError), ("default", 2**70, ValueError),
                                ("max_open", "no", TypeError), ("help", "a\x00b", ValueError),
                                ("choices", "x", TypeError)]:
        p = pt.Param(3) if field == "default" else pt.Param(1.0)
        setattr(p, field, value)
        with pytest.raises(error, match=rf"^oddkeys\.leg: (the )?{field}"):
            pt.register_controller("oddkeys", _Abandons, params={"leg": p})
    assert "oddkeys" not in pt.algorithms()


@pytest.mark.parametrize("kwargs, value", [
    ({"default": np.float32(0.25), "min": np.int64(0), "max": 1}, 0.25),
    ({"default": np.int64(3), "min": np.int32(1), "max": 9}, 3),
    ({"default": 0.5, "min": 0, "max": 2**40, "min_open": np.bool_(True)}, 0.5),
    ({"default": -2**31, "max": 2**31 - 1}, -2**31),
    ({"default": "b", "choices": ("a", "b"), "help": "\u00e9t\u00e9"}, "b"),
    ({"default": 1.0, "min": -math.inf, "max": math.inf}, 1.0),
])
def test_params_of_numpy_scalars_and_edge_values_register_and_run(kwargs, value):
    seen = []

    def factory(params, rng):
        seen.append(params.k)
        return _Abandons(params, rng)

    pt.register_controller("edgekeys", factory, params={"k": pt.Param(**kwargs)})
    assert pt.Scenario()["edgekeys.k"] == value
    r = pt.run(algorithm="edgekeys", trace=False)
    assert r["outcome"] == "gave_up" and seen == [value] and type(seen[0]) is type(value)


def test_register_controller_refuses_names_and_keys_that_are_not_text():
    for name, error in [(7, TypeError), (None, TypeError), ("a\nb", ValueError),
                        ("\ud800", ValueError)]:
        with pytest.raises(error, match="register_controller"):
            pt.register_controller(name, _Abandons)
    with pytest.raises(TypeError, match=r"register_controller\('k'\): the key 1 \(int\)"):
        pt.register_controller("k", _Abandons, params={1: pt.Param(1.0)})
    with pytest.raises(TypeError, match=r"k\.leg: declare it with plumetrace\.Param"):
        pt.register_controller("k", _Abandons, params={"leg": 1.0})
    assert "k" not in pt.algorithms()


def test_the_core_refuses_a_key_description_it_cannot_read_naming_the_key_and_field():
    # what Param._spec hands the core, made by hand: the core names the field, not pybind
    spec = {"name": "k", "kind": "number", "default": 0.5, "min": None, "max": None,
            "min_open": False, "max_open": False, "help": "", "choices": []}
    for field, value, kind in [("default", "x", "number"), ("min", "abc", "number"),
                               ("max", 2**70, "integer"), ("default", 1.5, "integer"),
                               ("min_open", "yes", "number"), ("choices", "ab", "choice")]:
        bad = dict(spec, kind=kind, **{field: value})
        if kind == "integer":
            bad["default"] = 1 if field != "default" else value
        if kind == "choice":
            bad["default"] = "a"
        with pytest.raises((TypeError, ValueError), match=rf"^direct\.k: {field}") as caught:
            pt._core.register_controller("direct", [bad], _Abandons)
        assert "Unable to cast" not in str(caught.value)
    assert "direct" not in pt.algorithms()
