"""The Python layer fails with Python exceptions that name the problem, never with a dead
interpreter (issue 13: F2, F4, F6, F18, F20, F21). A case that used to crash runs in a child
interpreter, so that a crash fails the test instead of ending pytest."""

import math
import os
import resource
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from conftest import plumetrace_with_core

pt = plumetrace_with_core()
from plumetrace.controllers import Command  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]

# 2 points x 3 runs of 63 steps each (no warm-up, a 2 s timeout): quick with any controller
SHORT_SWEEP = """
name = "short"
runs = 3
seed = 3

[set]
sim.warmup = 0.0
supervisor.timeout = 2.0

[[axis]]
key = "wind_sensor.sigma_a"
values = [0.0, 0.3]
"""

PRELUDE = """
import os, signal, sys, threading
import plumetrace as pt
from plumetrace.controllers import Command
SWEEP = sys.argv[1] if len(sys.argv) > 1 else None
"""


@pytest.fixture
def short_sweep(tmp_path):
    path = tmp_path / "short.toml"
    path.write_text(SHORT_SWEEP)
    return path


# why: AddressSanitizer (scripts/test-sanitized.sh) maps terabytes of shadow memory, so a child
# under an address-space limit cannot start there
under_address_limit = pytest.mark.skipif(
    os.environ.get("PLUMETRACE_SANITIZED") == "address",
    reason="an address-space limit cannot be tested under AddressSanitizer")


def run_isolated(code, *args, preexec_fn=None):
    """Runs `code` (after PRELUDE) in a child interpreter; fails on a crash (a signal), else
    returns the finished process. The timeout only stops a hang."""
    done = subprocess.run([sys.executable, "-c", PRELUDE + textwrap.dedent(code), *map(str, args)],
                          capture_output=True, text=True, timeout=300, cwd=ROOT,
                          preexec_fn=preexec_fn, env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
    assert done.returncode >= 0, (f"the interpreter died of signal {-done.returncode}:\n"
                                  f"{done.stderr[-3000:]}")
    return done


def last_line(done):
    assert done.returncode == 0, done.stderr[-3000:]
    return done.stdout.strip().splitlines()[-1]


class Still:
    """A controller that stands still."""

    def __init__(self, scenario, rng):
        pass

    def step(self, obs, wind):
        return Command.stop()


# F2: an exception in a controller during a sweep


def test_a_controller_exception_in_a_sweep_reaches_the_caller_as_itself(short_sweep):
    done = run_isolated("""
        class Failing:
            def __init__(self, scenario, rng):
                pass
            def step(self, obs, wind):
                raise LookupError("no plume here")
        try:
            pt.sweep(SWEEP, threads=2, controller=Failing)
        except LookupError as e:
            print("raised", type(e).__name__, e)
    """, short_sweep)
    assert last_line(done) == "raised LookupError no plume here"


def test_a_controller_factory_exception_in_a_sweep_reaches_the_caller(short_sweep):
    done = run_isolated("""
        def factory(scenario, rng):
            raise ZeroDivisionError("bad factory")
        try:
            pt.sweep(SWEEP, threads=2, controller=factory)
        except ZeroDivisionError as e:
            print("raised", e)
    """, short_sweep)
    assert last_line(done) == "raised bad factory"


def test_a_sweep_stopped_by_a_controller_error_hands_back_the_runs_finished_before(short_sweep):
    # one thread, no plume sharing: the runs go in campaign order, so four finish first
    done = run_isolated("""
        built = []
        class FailsFifth:
            def __init__(self, scenario, rng):
                built.append(1)
                self.fail = len(built) == 5
            def step(self, obs, wind):
                if self.fail:
                    raise RuntimeError("fifth run fails")
                return Command.stop()
        try:
            pt.sweep(SWEEP, threads=1, share_plumes=False, controller=FailsFifth)
        except RuntimeError as e:
            rows = e.partial_rows
            assert isinstance(rows, pt.SweepRows)
            print(e, list(rows["point"]), list(rows["trial"]), sorted(set(rows["outcome"])))
    """, short_sweep)
    assert last_line(done) == "fifth run fails [0, 0, 0, 1] [0, 1, 2, 0] ['timeout']"


# F4: threads


@pytest.mark.parametrize("threads", [100000, pt.MAX_THREADS + 1, -3])
def test_sweep_refuses_threads_outside_the_limit_naming_threads(short_sweep, threads):
    done = run_isolated("""
        try:
            pt.sweep(SWEEP, threads=int(sys.argv[2]), controller=None)
        except ValueError as e:
            print("refused", e)
    """, short_sweep, threads)
    assert last_line(done).startswith("refused threads must be an int from 0 to 1024")


@under_address_limit
def test_threads_the_system_cannot_start_are_a_runtime_error(tmp_path):
    # why: 1000 threads of 256 MiB stacks do not fit in 8 GiB of address space, so the system
    # refuses one of them; the runs (many, so that every thread has work) never start
    sweep = tmp_path / "many.toml"
    sweep.write_text(SHORT_SWEEP.replace("runs = 3", "runs = 1000"))

    def limits():
        resource.setrlimit(resource.RLIMIT_STACK, (256 << 20, 256 << 20))
        resource.setrlimit(resource.RLIMIT_AS, (8 << 30, 8 << 30))

    done = run_isolated("""
        try:
            pt.sweep(SWEEP, threads=1000)
            print("all threads started")
        except RuntimeError as e:
            print("refused", e)
    """, sweep, preexec_fn=limits)
    assert last_line(done).startswith("refused cannot start 1000 worker threads"), done.stdout


# F6: the wind probe after its step


def test_a_wind_probe_kept_after_the_run_raises_instead_of_reading_freed_memory():
    done = run_isolated("""
        kept = []
        class Keeper:
            def __init__(self, scenario, rng):
                pass
            def step(self, obs, wind):
                kept.append(wind)
                wind.measure_wind_body()  # valid here
                return Command.abandon()
        pt.run(controller=Keeper, trace=False)
        try:
            kept[0].measure_wind_body()
        except RuntimeError as e:
            print("refused", e)
    """)
    assert last_line(done).startswith("refused the wind probe is valid only during the step()")


def test_a_wind_probe_kept_from_an_earlier_step_raises():
    seen = []

    class Later:
        def __init__(self, scenario, rng):
            self.kept = None

        def step(self, obs, wind):
            if self.kept is None:
                self.kept = wind
                return Command.stop()
            try:
                self.kept.measure_wind_body()
            except RuntimeError as e:
                seen.append(str(e))
            return Command.abandon()

    r = pt.run(controller=Later, trace=False)
    assert r["wind_samples"] == 0
    assert len(seen) == 1 and "only during the step() call that received it" in seen[0]


# F18: values accepted silently


@pytest.mark.parametrize("value", [True, False])
def test_a_bool_is_refused_for_a_number_key(value):
    s = pt.Scenario()
    with pytest.raises(pt.ConfigError, match=r"sim\.dt"):
        s.sim.dt = value
    with pytest.raises(pt.ConfigError, match=r"wind\.vx"):
        pt.run(wind__vx=value, trace=False)
    assert s.sim.dt == 0.032


@pytest.mark.parametrize("seed, error", [(1.7, TypeError), (True, TypeError), ("1", TypeError),
                                          (-1, ValueError), (2**64, ValueError)])
def test_run_refuses_a_seed_that_is_not_a_whole_number_in_range(seed, error):
    with pytest.raises(error, match="seed"):
        pt.run(seed=seed, trace=False)


def test_an_env_refuses_a_seed_that_is_not_a_whole_number():
    from plumetrace.env import PlumeEnv

    with pytest.raises(TypeError, match="seed"):
        PlumeEnv(seed=1.7)
    with pytest.raises(ValueError, match="seed"):
        PlumeEnv().reset(seed=-1)


@pytest.mark.parametrize("action", [[], [0.1, 0.2], "north", None, math.nan])
def test_an_env_action_that_is_not_one_finite_heading_is_refused_naming_it(action):
    from plumetrace.env import PlumeEnv

    env = PlumeEnv(sim__warmup=0.0)
    env.reset(seed=1)
    with pytest.raises((TypeError, ValueError), match="action|finite"):
        env.step(action)
    env.step(0.0)  # the episode goes on


def test_a_config_key_with_a_nul_character_is_refused_naming_it():
    with pytest.raises(pt.ConfigError, match=r"config key 'sim\\x00dt' contains a NUL"):
        pt.Scenario().update({"sim\x00dt": 0.1})


@pytest.mark.parametrize("name, value, error", [("runs", -5, ValueError), ("runs", 2.0, TypeError),
                                                 ("threads", -3, ValueError),
                                                 ("threads", 1.5, TypeError),
                                                 ("share_plumes", "no", TypeError)])
def test_sweep_refuses_bad_arguments_naming_them(short_sweep, name, value, error):
    with pytest.raises(error, match=name):
        pt.sweep(short_sweep, **{name: value})


@under_address_limit
def test_a_sweep_larger_than_a_python_sweep_holds_is_refused_naming_runs(short_sweep):
    # why: in a child with 4 GiB of address space, since taking it would fill the memory
    def limits():
        resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))

    done = run_isolated("""
        try:
            pt.sweep(SWEEP, runs=100000001)
        except pt.ConfigError as e:
            print(e)
    """, short_sweep, preexec_fn=limits)
    assert last_line(done).startswith("runs: 2 points x 100000001 runs = 200000002 runs, more "
                                      "than the 10000000 a Python sweep holds in memory")


@pytest.mark.parametrize("make", [lambda: Command.go(math.nan), lambda: Command.turn_to(math.inf),
                                  lambda: Command.curve(-math.inf)])
def test_a_controller_commanding_a_non_finite_value_is_refused_at_its_line(make):
    class NotANumber:
        def __init__(self, scenario, rng):
            pass

        def step(self, obs, wind):
            return make()

    with pytest.raises(ValueError, match=r"must be a finite number, got (nan|inf|-inf)") as e:
        pt.run(controller=NotANumber, trace=False)
    # the traceback names the controller's step
    assert any(entry.name == "step" for entry in e.traceback)


# F20: a wrong return type


@pytest.mark.parametrize("value, name", [(None, "NoneType"), (0.5, "float"), ((1, 2), "tuple")])
def test_a_controller_returning_the_wrong_type_gets_a_type_error_naming_it(value, name):
    class Wrong:
        def __init__(self, scenario, rng):
            pass

        def step(self, obs, wind):
            return value

    with pytest.raises(TypeError) as e:
        pt.run(controller=Wrong, trace=False)
    assert str(e.value) == f"controller.step must return a Command, got {name}"


def test_a_controller_returning_the_wrong_type_in_a_sweep_gets_the_same_type_error(short_sweep):
    done = run_isolated("""
        class Wrong:
            def __init__(self, scenario, rng):
                pass
            def step(self, obs, wind):
                return None
        try:
            pt.sweep(SWEEP, threads=2, controller=Wrong)
        except TypeError as e:
            print("refused", e)
    """, short_sweep)
    assert last_line(done) == "refused controller.step must return a Command, got NoneType"


def test_bad_losses_and_factories_are_type_errors_naming_them():
    class BadLosses(Still):
        losses = "two"

    with pytest.raises(TypeError, match="controller.losses must be an int, got str"):
        pt.run(controller=BadLosses, trace=False)
    with pytest.raises(TypeError, match="must return an object with a step"):
        pt.run(controller=lambda scenario, rng: None, trace=False)
    with pytest.raises(TypeError, match="controller must be a factory"):
        pt.run(controller=Still(None, None), trace=False)


# F21: Ctrl-C


def test_ctrl_c_stops_a_sweep_with_keyboard_interrupt_and_keeps_the_finished_runs(short_sweep):
    # the first controller built sends SIGINT; every run then waits until the handler has run
    # (up to 10 s): with the signal seen during the sweep, no run starts after it. The threads of
    # one process (processes=False): a worker process would send the signal to itself
    done = run_isolated("""
        # why: the handler runs on the main thread with the GIL; a long switch interval keeps it
        # there until the sweep has set its stop flag, so no worker starts a run in between
        sys.setswitchinterval(100.0)
        handled = threading.Event()
        def on_sigint(signum, frame):
            handled.set()
            raise KeyboardInterrupt
        signal.signal(signal.SIGINT, on_sigint)
        built = []
        class Slow:
            def __init__(self, scenario, rng):
                built.append(1)
                if len(built) == 1:
                    os.kill(os.getpid(), signal.SIGINT)
            def step(self, obs, wind):
                handled.wait(10)
                return Command.abandon()
        try:
            pt.sweep(SWEEP, runs=4, threads=2, share_plumes=False, controller=Slow,
                     processes=False)
            print("finished")
        except KeyboardInterrupt as e:
            rows = e.partial_rows
            print("interrupted", len(built), len(rows), sorted(set(rows["outcome"])))
    """, short_sweep)
    words = last_line(done).split(maxsplit=3)
    assert words[0] == "interrupted", done.stdout
    built, kept = int(words[1]), int(words[2])
    assert 1 <= built <= 2  # of 8 runs, only those the two threads started before the signal
    assert kept <= built and words[3] in ("[]", "['gave_up']")


def test_ctrl_c_stops_worker_processes_and_reaps_them(short_sweep, tmp_path):
    # two workers each start a run that never ends; once both have started, Ctrl-C here: the
    # sweep raises KeyboardInterrupt after its grace and leaves no worker process behind
    done = run_isolated("""
        import multiprocessing, time
        started = sys.argv[2]
        class Stuck:
            def __init__(self, scenario, rng):
                with open(started, "a") as f:
                    f.write(f"{os.getpid()}\\n")
            def step(self, obs, wind):
                time.sleep(3600)
        def interrupt():
            while len(open(started).read().split()) < 2:
                time.sleep(0.02)
            os.kill(os.getpid(), signal.SIGINT)
        open(started, "w").close()
        threading.Thread(target=interrupt, daemon=True).start()
        t = time.monotonic()
        try:
            pt.sweep(SWEEP, threads=2, share_plumes=False, controller=Stuck)
        except KeyboardInterrupt as e:
            print("interrupted", len(e.partial_rows), f"{time.monotonic() - t:.0f}")
        pids = [int(p) for p in open(started).read().split()]
        def gone(pid):
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                return True
            return False
        try:
            os.waitpid(-1, os.WNOHANG)
            children = "children left"
        except ChildProcessError:
            children = "no child"
        print(len(set(pids)), all(map(gone, pids)), children, multiprocessing.active_children())
    """, short_sweep, tmp_path / "started.txt")
    lines = done.stdout.strip().splitlines()
    assert done.returncode == 0, done.stderr[-3000:]
    assert lines[-2].startswith("interrupted 0 "), lines
    assert int(lines[-2].split()[2]) < 60  # the stuck runs were ended, not waited for
    assert lines[-1] == "2 True no child []"


# worker processes (a controller written in Python, threads > 1): a worker's error reaches the
# caller


def test_a_worker_process_error_reaches_the_caller_with_the_controller_traceback(short_sweep):
    done = run_isolated("""
        from plumetrace._workers import RemoteTraceback, WorkerError
        class Odd(Exception):  # does not unpickle (two arguments, one given to Exception)
            def __init__(self, what, where):
                super().__init__(f"{what} at {where}")
        def lookup(obs):
            raise LookupError("no plume here")
        class Fails:
            error = "lookup"
            def __init__(self, scenario, rng):
                pass
            def step(self, obs, wind):
                if self.error == "lookup":
                    lookup(obs)
                if self.error == "odd":
                    raise Odd("odd", "here")
                os._exit(3)
        for error in ("lookup", "odd", "exit"):
            Fails.error = error
            try:
                pt.sweep(SWEEP, threads=2, controller=Fails)
            except (LookupError, WorkerError) as e:
                cause = e.__cause__
                # the function the worker's traceback ends in
                where = cause.text.strip().splitlines()[-2] if cause is not None else "-"
                print(type(e).__name__, "|", e, "|", isinstance(cause, RemoteTraceback),
                      "|", where.split(", ")[-1], "|", type(e.partial_rows).__name__)
    """, short_sweep)
    assert done.returncode == 0, done.stderr[-3000:]
    lookup, odd, died = done.stdout.strip().splitlines()[-3:]
    # the exception itself, its cause the worker's traceback down to the controller's line
    assert lookup == "LookupError | no plume here | True | in lookup | SweepRows"
    # one that cannot travel as itself: its type and words, and the same traceback
    assert odd.startswith("WorkerError | __main__.Odd: odd at here (raised in plumetrace-worker-")
    assert odd.endswith("| True | in step | SweepRows")
    # a worker that dies says so
    assert died.startswith("WorkerError | plumetrace-worker-")
    assert "ended without a word (exit status 3) | False | - | SweepRows" in died
