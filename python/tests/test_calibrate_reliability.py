"""What `python3 -m plumetrace.calibrate` guarantees on bad input and in a hostile environment
(issue 22, findings G5, G6, G7, G9, G12; docs/calibration.md, "Exit status, limits and the lock"):
one line naming the file, key or option, exit 2 for bad input, 3 for I/O, 130 for Ctrl-C and
SIGTERM; no traceback, no hang, nothing computed lost. Each test runs the command as a user does,
in a process of its own, unless it needs the search's stand-in."""

import errno
import os
import signal
import sqlite3
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()

from plumetrace import _core, _files, calibrate  # noqa: E402
from plumetrace.calibrate import search  # noqa: E402
from test_calibrate import (SETS, FakeEvaluation, paper_study, study_file, write,  # noqa: E402
                            write_set_d)

# the package these tests import, with its C++ module (another test file may put the source
# tree, without it, first on sys.path)
ENV = dict(os.environ, PYTHONPATH=str(Path(pt.__file__).resolve().parents[1]))


def calibrate_command(args, cwd, timeout=120, **kwargs):
    """Runs the command in a process of its own; returns the finished process."""
    return subprocess.run([sys.executable, "-m", "plumetrace.calibrate", *map(str, args)],
                          capture_output=True, text=True, env=ENV, cwd=cwd, timeout=timeout,
                          **kwargs)


def assert_one_line_error(r, status, *says):
    assert r.returncode == status, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("plumetrace.calibrate: error: "), r.stderr
    for text in says:
        assert text in lines[0], lines[0]


def small_study(tmp_path, body="", validation=""):
    """A study of set D reduced to three spiral gaps, one unknown: a trial runs in seconds.
    `body` holds more top-level keys, `validation` keys of [validation]."""
    write_set_d(tmp_path)
    write(tmp_path / "unknowns.toml",
          '[[unknown]]\nname = "radius"\nkey = "supervisor.success_radius"\nlow = 0.1\n'
          'high = 0.5\n')
    threads = "" if "threads" in body else "threads = 1\n"
    return write(tmp_path / "study.toml", 'unknowns = "unknowns.toml"\nsets_dir = "sets"\n'
                 f'sets = ["D"]\nseed = 3\n{threads}{body}\n'
                 '[fixed]\nsupervisor.timeout = 400.0\n'
                 f'[validation]\n{validation}')


# --- G5: input files and output folders -------------------------------------------------------

def test_a_folder_or_non_utf8_study_file_is_refused_naming_it_with_status_2(tmp_path):
    (tmp_path / "folder.toml").mkdir()
    (tmp_path / "latin1.toml").write_bytes(b'name = "caf\xe9"\n')
    r = calibrate_command(["folder.toml"], tmp_path)
    assert_one_line_error(r, 2, "folder.toml", "a folder, not a file")
    r = calibrate_command(["latin1.toml"], tmp_path)
    assert_one_line_error(r, 2, "latin1.toml", "utf-8")
    assert not (tmp_path / "out").exists()


def test_an_out_that_cannot_be_a_writable_folder_exits_2_or_3_naming_it(tmp_path):
    study = small_study(tmp_path)
    (tmp_path / "a-file").write_text("keep me\n")
    # a file named as the folder is bad input (2), as for the command (make_output_folder)
    r = calibrate_command([study, "--out", "a-file", "--quiet"], tmp_path)
    assert_one_line_error(r, 2, "--out", "'a-file' is a file, not a folder")
    for out, says in [("a-file/below", "a-file/below"),
                      ("/proc/plumetrace-calibration", "/proc/plumetrace-calibration"),
                      ("/proc/self", "cannot write in '/proc/self'")]:
        r = calibrate_command([study, "--out", out, "--quiet"], tmp_path)
        assert_one_line_error(r, 3, "--out", says)
    assert (tmp_path / "a-file").read_text() == "keep me\n"


def test_a_read_only_out_exits_3_naming_it(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(stat.S_IRUSR | stat.S_IXUSR)
    if os.access(ro, os.W_OK):
        pytest.skip("this user (root) writes in a read-only folder; /proc stands for it above")
    r = calibrate_command([small_study(tmp_path), "--out", ro / "out", "--quiet"], tmp_path)
    assert_one_line_error(r, 3, "--out", str(ro / "out"))


def test_a_full_disk_exits_3_naming_the_study_database(tmp_path):
    # a file size limit of 16 KiB stands for a full disk; Python ignores SIGXFSZ, so the write
    # fails with EFBIG, as `plumetrace` under `ulimit -f` (tests/cli_reliability_test.cpp)
    import resource

    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (16384, resource.RLIM_INFINITY))

    r = calibrate_command([small_study(tmp_path), "--out", "out", "--quiet"], tmp_path,
                          preexec_fn=limit)
    assert_one_line_error(r, 3, "out/study.sqlite", "file size limit")


def test_outputs_are_written_whole_or_not_at_all(tmp_path):
    # a write cut short by the file size limit leaves the earlier file as it was, and no part
    target = tmp_path / "best.toml"
    target.write_text("the earlier reading\n")
    code = ("import resource, sys\n"
            "from plumetrace import _files\n"
            "resource.setrlimit(resource.RLIMIT_FSIZE, (4096, resource.RLIM_INFINITY))\n"
            "try:\n"
            f"    _files.write_whole({str(target)!r}, 'x' * 100000)\n"
            "except _files.FileIoError as e:\n"
            "    print(e); sys.exit(3)\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=ENV)
    assert r.returncode == 3, r.stderr
    assert str(target) in r.stdout and "file size limit" in r.stdout
    assert target.read_text() == "the earlier reading\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["best.toml"]


def test_a_full_disk_at_the_report_exits_3_and_leaves_no_half_file(tmp_path, monkeypatch,
                                                                   capsys):
    # the search finished and is stored; the disk fills while validation.json is written
    monkeypatch.setattr(search, "evaluate", FakeEvaluation())

    def full(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(_files.os, "fsync", full)
    out = tmp_path / "out"
    assert calibrate.main([str(paper_study(tmp_path)), "--out", str(out), "--trials", "2",
                           "--quiet"]) == 3
    err = capsys.readouterr().err.strip()
    assert err == f"plumetrace.calibrate: error: cannot write '{out / 'validation.json'}': " \
                  "the disk is full"
    assert sorted(p.name for p in out.iterdir()) == [".lock", "study.sqlite"]
    assert len(search.completed(search.open_study(calibrate.load_study(
        paper_study(tmp_path)), out))) == 2


def test_a_busy_study_folder_is_refused_at_once_naming_it(tmp_path):
    study = small_study(tmp_path, "trials = 1\nruns = 1\n", "top = 1\nruns = 1\n")
    out = tmp_path / "out"
    out.mkdir()
    with _files.folder_lock(out, "--out"):  # another calibration works in it
        start = time.monotonic()
        r = calibrate_command([study, "--out", out, "--quiet"], tmp_path)
        assert_one_line_error(r, 3, "--out", str(out), "in use by another process")
        assert time.monotonic() - start < 60  # at once: not after the other's end
    assert not (out / "study.sqlite").exists()


def test_a_second_study_in_the_same_out_is_refused_naming_both(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(search, "evaluate", FakeEvaluation())
    first = paper_study(tmp_path)
    out = tmp_path / "out"
    assert calibrate.main([str(first), "--out", str(out), "--trials", "2", "--quiet"]) == 0
    before = (out / "best.toml").read_text()
    second = write(tmp_path / "second.toml", 'name = "other"\n' + first.read_text())
    assert calibrate.main([str(second), "--out", str(out), "--trials", "2", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "holds study 'calibration', not 'other'" in err
    assert (out / "best.toml").read_text() == before


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_ctrl_c_and_sigterm_end_a_running_study_with_status_130_keeping_its_trials(tmp_path, sig):
    study = small_study(tmp_path, "runs = 30\ntrials = 50\n")
    out = tmp_path / "out"
    p = subprocess.Popen([sys.executable, "-m", "plumetrace.calibrate", str(study), "--out",
                          str(out), "--quiet"], stderr=subprocess.PIPE, text=True, env=ENV,
                         cwd=tmp_path)
    try:
        # a trial is RUNNING from Optuna's ask to its tell: the C++ evaluation is computing
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not running_trials(out / "study.sqlite"):
            time.sleep(0.05)
        assert running_trials(out / "study.sqlite"), "the study never started a trial"
        # past Optuna's sampling (milliseconds), into the evaluation (some 90 runs)
        # why: 0.3 s, not 1 s: a trial takes 1.05-1.13 s on a 2-core machine with AVX-512, where
        # a signal a second in could come after the trial had completed
        time.sleep(0.3)
        p.send_signal(sig)
        _, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
    assert p.returncode == 130, err
    assert err.strip().splitlines() == [
        f"plumetrace.calibrate: interrupted; the finished trials are in {out / 'study.sqlite'}: "
        "run the same command again to continue"]
    # the interrupted trial is marked failed (and interrupted), not left running
    assert trial_states(out / "study.sqlite") == ["FAIL"]


def trial_states(db):
    with sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=1) as c:
        return [r[0] for r in c.execute("SELECT state FROM trials ORDER BY number")]


def running_trials(db):
    if not db.exists():
        return 0
    try:
        return trial_states(db).count("RUNNING")
    except sqlite3.Error:  # the schema is not there yet
        return 0


# --- G6, G7: inputs that hang or take gigabytes ------------------------------------------------

def test_fifo_study_files_are_refused_without_blocking(tmp_path):
    os.mkfifo(tmp_path / "f.toml")
    r = calibrate_command(["f.toml", "--out", "o"], tmp_path, timeout=60)
    assert_one_line_error(r, 2, "f.toml", "not a regular file")
    # an unknowns file too
    write(tmp_path / "s.toml", 'unknowns = "f.toml"\n')
    r = calibrate_command(["s.toml", "--out", "o"], tmp_path, timeout=60)
    assert_one_line_error(r, 2, "f.toml", "not a regular file")


def test_deeply_dotted_keys_are_refused_before_parsing(tmp_path):
    # 50000 parts took 9.8 GB and 44 s; the depth is counted on the text (kMaxKeyDepth)
    deep = ".".join(["k"] * 50000) + " = 1\n"
    write(tmp_path / "deep.toml", deep)
    r = calibrate_command(["deep.toml"], tmp_path, timeout=60)
    assert_one_line_error(r, 2, "deep.toml:1", "dotted parts")
    write(tmp_path / "unknowns.toml", deep)
    write(tmp_path / "s.toml", 'unknowns = "unknowns.toml"\n')
    r = calibrate_command(["s.toml"], tmp_path, timeout=60)
    assert_one_line_error(r, 2, "unknowns.toml:1", "dotted parts")


# --- G9, G12: keys checked before the study database exists ------------------------------------

@pytest.mark.parametrize("body, validation, says", [
    ("runs = 100000000\n", "", "'runs': bad range: must be at most 10000000"),
    # 3 points x 4000000 runs: each within the limit, their product not
    ("runs = 4000000\n", "", "'runs': 4000000 runs per value over the 3 points of sets D make "
                             "12000000 runs, more than the 10000000"),
    ("", "runs = 4000000\n", "'validation.runs': 4000000 runs per value"),
    ("threads = 5000\n", "", "'threads': bad range: must be 0 (all cores) to 1024"),
    ("trials = 1000000000000\n", "", "'trials': bad range: must be at most 100000"),
])
def test_runs_and_threads_are_checked_before_the_study_database_exists(tmp_path, body,
                                                                        validation, says):
    # they were checked inside each trial: 10 trials failed, and the database they left refused
    # the corrected study as "another definition"
    study = small_study(tmp_path, body, validation)
    r = calibrate_command([study, "--out", "out", "--quiet"], tmp_path, timeout=60)
    assert_one_line_error(r, 2, "study.toml", says)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("option, value, says", [
    ("--trials", "100001", "--trials: bad range: must be 1 to 100000"),
    ("--threads", "1025", "--threads: bad range: must be 0 (all cores) to 1024"),
    ("--threads", "-1", "--threads: bad range"),
])
def test_trials_and_threads_options_are_checked_before_the_study_database_exists(
        tmp_path, option, value, says):
    r = calibrate_command([small_study(tmp_path), "--out", "out", option, value, "--quiet"],
                          tmp_path)
    assert_one_line_error(r, 2, says)
    assert not (tmp_path / "out").exists()


def test_an_empty_out_or_an_unknown_searched_twice_is_refused_naming_it(tmp_path):
    study = small_study(tmp_path)
    r = calibrate_command([study, "--out", "", "--quiet"], tmp_path)
    assert_one_line_error(r, 2, "--out: an empty path")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sets", "study.toml", "unknowns.toml"]
    study = small_study(tmp_path, 'search = ["radius", "radius"]\n')
    r = calibrate_command([study, "--out", "out", "--quiet"], tmp_path)
    assert_one_line_error(r, 2, "study.toml", "'search' names unknown 'radius' twice")


def test_a_set_named_twice_is_refused_naming_it(tmp_path):
    study = study_file(tmp_path, f'sets_dir = "{SETS}"\nsets = ["A", "B", "A"]\n')
    with pytest.raises(calibrate.StudyError, match="'sets' names set 'A' twice"):
        calibrate.load_study(study)


# --- one input reader: C++ and Python classify hostile inputs alike ----------------------------

def cpp_reading(path):
    """How the C++ reader (parse_toml_file, through the calibration study reader) takes a path:
    the reason it cannot read it, or None where it read it."""
    prefix = f"cannot read study file '{str(path).replace(chr(0), chr(92) + '0')}': "
    try:
        _core.read_calibration_study(str(path))
    except ValueError as e:
        return str(e)[len(prefix):] if str(e).startswith(prefix) else None
    return None


def python_reading(path, max_bytes=_files.MAX_INPUT_BYTES):
    prefix = f"cannot read study file '{str(path).replace(chr(0), chr(92) + '0')}': "
    try:
        _files.read_input(path, "study file", max_bytes)
    except _files.BadPath as e:
        assert str(e).startswith(prefix), e
        return str(e)[len(prefix):]
    return None


def test_the_cpp_and_python_input_readers_classify_hostile_inputs_alike(tmp_path):
    os.mkfifo(tmp_path / "fifo.toml")
    (tmp_path / "folder.toml").mkdir()
    (tmp_path / "a-file").write_text("x = 1\n")
    unreadable = tmp_path / "unreadable.toml"
    unreadable.write_text("x = 1\n")
    unreadable.chmod(0)
    cases = {
        "fifo": tmp_path / "fifo.toml",
        "folder": tmp_path / "folder.toml",
        "device": Path("/dev/null"),
        "missing": tmp_path / "missing.toml",
        "below a file": tmp_path / "a-file" / "x.toml",
        "unreadable": unreadable,  # readable where the tests run as root: both read it then
        "regular": tmp_path / "a-file",
        "NUL in the path": Path(str(tmp_path / "a-file") + "\0junk"),
    }
    seen = {}
    for name, path in cases.items():
        seen[name] = (cpp_reading(path), python_reading(path))
        assert seen[name][0] == seen[name][1], (name, seen[name])
    assert seen["fifo"][0] == "not a regular file" and seen["device"][0] == "not a regular file"
    assert seen["folder"][0] == "a folder, not a file"
    assert seen["missing"][0] == "No such file or directory"
    assert seen["below a file"][0] == "Not a directory"
    assert seen["regular"] == (None, None)
    assert seen["NUL in the path"][0] == "the path holds a NUL character"


def test_the_cpp_and_python_input_readers_bound_the_size_alike(tmp_path):
    limit = getattr(_core, "MAX_INPUT_BYTES", None)
    if limit is None:
        pytest.skip("the C++ reader has no size bound to compare with yet (kMaxInputBytes)")
    assert limit == _files.MAX_INPUT_BYTES
    big = tmp_path / "big.toml"
    with open(big, "wb") as f:
        f.truncate(limit + 1)
    assert cpp_reading(big) is not None and python_reading(big) is not None
    assert python_reading(big, max_bytes=limit + 1) is None
