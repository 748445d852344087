"""The standing fault campaign of the results store (issue 13; docs/reliability.md, "Results stores").

Each case does to `plumetrace` what happens to a tool left running overnight on the only copy of
its results (kill -9, a second process on the same store, a full disk, a damaged or read-only
copy) and checks what is guaranteed: nothing lost, nothing changed silently, and a message that
names the cause. Random points are drawn from a seeded generator (PLUMETRACE_FAULT_SEED, default
13); where the process is killed depends on timing as well, so every outcome is checked, not one.

    campaign.py CASE...    CASE: kill_sweep kill_merge kill_mpi concurrent full_disk damage
                           readonly merge_onto_foreign study_escape study_foreign_report
                           concurrent_out calibrate_inputs (or all)

Environment: PLUMETRACE_CLI (the command), PLUMETRACE_MPIEXEC (mpirun; empty: no MPI build).
Exit 0 when every check holds, 1 otherwise, 77 when a case cannot run here (it says why).
"""

import json
import os
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time

CLI = os.environ.get("PLUMETRACE_CLI", "")
MPIEXEC = os.environ.get("PLUMETRACE_MPIEXEC", "")
SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# 4 points x 12 quick runs (two plumes x two algorithms); --runs makes it longer
SWEEP = os.path.join(SOURCE, "tests", "support", "two_plumes.toml")
# runs per point: 60 (240 runs, about a second, a few commits) where a kill must land mid-way,
# 30 where processes must overlap, else 12 (48 runs, a tenth of a second)
LONG, MID, SHORT = "60", "30", "12"
SEED = int(os.environ.get("PLUMETRACE_FAULT_SEED", "13"))
SKIP = 77
# why: every command is bounded, so that a hang fails the case instead of the suite's timeout
LIMIT_S = 60

# Open MPI as root in a container: shared memory only, no binding (see cluster_cli_test.cpp)
MPI_ENV = {
    "OMPI_ALLOW_RUN_AS_ROOT": "1",
    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_btl": "self,vader",
    "OMPI_MCA_btl_vader_single_copy_mechanism": "none",
    "OMPI_MCA_pml": "ob1",
}


class Skip(Exception):
    """A case that cannot run on this machine, with the reason."""


class Campaign:
    def __init__(self, work):
        self.work = work
        self.rng = random.Random(SEED)
        self.failures = []
        self.checks = 0
        self._clean = {}
        self.kept = []  # runs held by each store left by a kill, for the summary
        self.runs = SHORT
        self._count = 0

    # --- helpers -------------------------------------------------------------------------------

    def path(self, stem):
        self._count += 1
        return os.path.join(self.work, "%s-%d" % (stem, self._count))

    def check(self, ok, what):
        self.checks += 1
        if not ok:
            self.failures.append(what)
            print("FAIL: " + what, flush=True)

    def run(self, args, preexec=None, env=None, user=None):
        """Runs plumetrace ARGS; returns (exit code, 128+signal when killed; stdout; stderr)."""
        command = ([] if user is None else user) + [CLI] + args
        p = subprocess.run(command, capture_output=True, text=True, errors="backslashreplace",
                           timeout=LIMIT_S, preexec_fn=preexec, env=env)
        code = p.returncode if p.returncode >= 0 else 128 - p.returncode
        return code, p.stdout, p.stderr

    def sweep_args(self, store, out, extra=()):
        return ["sweep", SWEEP, "--runs", self.runs, "--quiet", "--store", store, "--out", out] + list(
            extra)

    def exports(self, store, user=None, out=None):
        """The exports of a store as one text, or None with the error when export refuses it."""
        out = out or self.path("exports")
        code, _, err = self.run(
            ["export", SWEEP, "--runs", self.runs, "--store", store, "--out", out], user=user)
        if code != 0:
            return None, code, err
        text = ""
        for name in ("runs.csv", "summary.csv", "results.json"):
            with open(os.path.join(out, name), "rb") as f:
                text += f.read().decode("utf-8", errors="backslashreplace")
        return text, 0, ""

    def clean(self):
        """The store and exports of an undisturbed sweep, everything else must equal."""
        if self.runs not in self._clean:
            store = self.path("clean.sqlite")
            code, _, err = self.run(self.sweep_args(store, self.path("clean-out")))
            assert code == 0, err
            text, _, err = self.exports(store)
            assert text is not None, err
            self._clean[self.runs] = (store, text)
        return self._clean[self.runs]

    def runs_lines(self, text):
        """The run rows of runs.csv within an exports text."""
        lines = text.split("\n")
        end = next(i for i, l in enumerate(lines) if l.startswith("sweep,point,") and i > 0)
        return set(lines[1:end])

    def timed(self, args, env=None):
        """Seconds an undisturbed command takes (to spread kill points over it)."""
        start = time.monotonic()
        subprocess.run([CLI] + args, capture_output=True, timeout=LIMIT_S, env=env)
        return time.monotonic() - start

    def kill_at(self, command, delay, env=None):
        """Starts COMMAND, SIGKILLs its process group after DELAY s (if still running)."""
        p = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                             env=env, start_new_session=True)
        try:
            p.wait(timeout=delay)
            return p.returncode
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait(timeout=LIMIT_S)
            return -9

    def expect_partial(self, store, what):
        """A store left by a kill: refused as empty (nothing committed yet), or every run it holds
        is a run of the clean sweep, unchanged."""
        text, code, err = self.exports(store)
        if text is None:
            self.check(code == 2 and "is empty" in err, "%s: killed store refused: %s" % (what, err))
            self.kept.append(0)
            return
        clean = self.runs_lines(self.clean()[1])
        self.check(self.runs_lines(text) <= clean, "%s: a killed store holds changed runs" % what)
        self.kept.append(len(self.runs_lines(text)))

    # --- cases ---------------------------------------------------------------------------------

    def kill_sweep(self):
        """Guarantee: a sweep killed (SIGKILL) at any point keeps every committed run unchanged,
        and the same command, run again, completes it to the clean sweep's exports byte for byte
        (here killed up to twice in a row before it may finish)."""
        self.runs = LONG
        _, clean = self.clean()
        span = self.timed(self.sweep_args(self.path("timing.sqlite"), self.path("timing-out")))
        for i in range(6):
            store, out = self.path("killed.sqlite"), self.path("killed-out")
            for k in range(1 + i % 2):
                self.kill_at([CLI] + self.sweep_args(store, out), self.rng.uniform(0, span))
                if os.path.exists(store):
                    self.expect_partial(store, "kill_sweep %d.%d" % (i, k))
            code, _, err = self.run(self.sweep_args(store, out))
            self.check(code == 0, "kill_sweep %d: the resumed sweep failed: %s" % (i, err))
            self.check(self.exports(store)[0] == clean, "kill_sweep %d: exports differ" % i)

    def shards(self):
        """The stores of the sweep's three shards (--shard i/3), computed undisturbed."""
        parts = []
        for i in (1, 2, 3):
            part = self.path("part%d.sqlite" % i)
            code, _, err = self.run(self.sweep_args(part, self.path("part-out"),
                                                    ["--shard", "%d/3" % i]))
            assert code == 0, err
            parts.append(part)
        return parts

    def kill_merge(self):
        """Guarantee: a merge killed at any point leaves its target absent, empty, or with whole
        parts' runs only; the same merge run again succeeds with the clean sweep's exports."""
        self.runs = LONG
        _, clean = self.clean()
        parts = self.shards()
        span = self.timed(["merge"] + parts + ["--store", self.path("timing.sqlite")])
        for i in range(9):
            target = self.path("merged.sqlite")
            if i % 3 == 2:  # into a target that holds one part already
                self.run(["merge", parts[0], "--store", target])
            rc = self.kill_at([CLI, "merge"] + parts + ["--store", target],
                              self.rng.uniform(0, span * 1.5))
            if os.path.exists(target) and rc == -9:
                self.expect_partial(target, "kill_merge %d" % i)
            code, _, err = self.run(["merge"] + parts + ["--store", target])
            self.check(code == 0, "kill_merge %d: the merge run again failed: %s" % (i, err))
            self.check(self.exports(target)[0] == clean, "kill_merge %d: exports differ" % i)

    def mpi_command(self, store, out):
        return [MPIEXEC, "-n", "2", "--oversubscribe", "--bind-to", "none", "--timeout", "100",
                CLI] + self.sweep_args(store, out)

    def kill_mpi(self):
        """Guarantee: an MPI sweep (mpirun -n 2) whose processes are all killed at any point
        keeps every committed run; the same job run again completes it to the clean sweep's
        exports byte for byte."""
        if not MPIEXEC or not shutil.which(MPIEXEC):
            raise Skip("this build has no MPI or mpirun is absent")
        self.runs = LONG
        _, clean = self.clean()
        env = dict(os.environ, **MPI_ENV)
        start = time.monotonic()
        subprocess.run(self.mpi_command(self.path("timing.sqlite"), self.path("timing-out")),
                       capture_output=True, timeout=LIMIT_S, env=env)
        span = time.monotonic() - start
        for i in range(4):
            store, out = self.path("mpi.sqlite"), self.path("mpi-out")
            # why: mpirun and its ranks share the session, so the whole job dies at once, as on a
            # machine that fails
            self.kill_at(self.mpi_command(store, out), self.rng.uniform(0.3 * span, span), env=env)
            if os.path.exists(store):
                self.expect_partial(store, "kill_mpi %d" % i)
            p = subprocess.run(self.mpi_command(store, out), capture_output=True, text=True,
                               timeout=LIMIT_S, env=env)
            self.check(p.returncode == 0, "kill_mpi %d: the job run again failed: %s" %
                       (i, p.stderr))
            self.check(self.exports(store)[0] == clean, "kill_mpi %d: exports differ" % i)

    def concurrent(self):
        """Guarantee: several sweeps writing one store at once all finish (exit 0), none loses
        its runs or reports a lock, and the store's exports equal the clean sweep's; an export
        reading it meanwhile sees a consistent store (or none yet)."""
        self.runs = MID
        _, clean = self.clean()
        for i in range(2):
            store = self.path("shared.sqlite")
            procs = [subprocess.Popen([CLI] + self.sweep_args(store, self.path("out"),
                                                              ["--threads", str(1 + k % 2)]),
                                      stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
                     for k in range(3)]
            time.sleep(self.rng.uniform(0, 0.3))
            if os.path.exists(store):
                self.expect_partial(store, "concurrent %d (read while written)" % i)
            for k, p in enumerate(procs):
                err = p.communicate(timeout=LIMIT_S)[1]
                self.check(p.returncode == 0, "concurrent %d: sweep %d failed: %s" % (i, k, err))
            self.check(self.exports(store)[0] == clean, "concurrent %d: exports differ" % i)

    def limited(self, limit):
        """A preexec function: a file size limit of LIMIT bytes and SIGXFSZ at its default (the
        command must ignore it itself)."""
        def apply():
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
            signal.signal(signal.SIGXFSZ, signal.SIG_DFL)
        return apply

    def expect_full(self, code, err, what):
        """A command refused by a full disk: exit 3 and a message naming the cause."""
        if code == 0:
            return
        self.check(code == 3, "%s: exit %d, not 3: %s" % (what, code, err))
        self.check("rollback" not in err and "plumetrace: error:" in err and
                   re.search(r"write failed|disk is full|file size limit|cannot write|File too "
                             r"large|No space", err) is not None,
                   "%s: the message does not name the cause: %s" % (what, err))

    def full_disk(self):
        """Guarantee: a sweep or merge whose writes fail (a full disk, here a file size limit)
        exits 3 with a message that names the cause, keeps every committed run, and the same
        command, given room, completes to the clean sweep's exports."""
        clean_store, clean = self.clean()
        size = os.path.getsize(clean_store)
        limits = sorted(self.rng.randrange(0, size + 16384) for _ in range(6)) + [4096]
        for i, limit in enumerate(limits):
            store, out = self.path("full.sqlite"), self.path("full-out")
            code, _, err = self.run(self.sweep_args(store, out), preexec=self.limited(limit))
            self.expect_full(code, err, "full_disk sweep at %d bytes" % limit)
            if os.path.exists(store) and code != 0:
                self.check(store in err or out in err,
                           "full_disk %d: the message names no file: %s" % (limit, err))
                self.expect_partial(store, "full_disk %d" % limit)
            code, _, err = self.run(self.sweep_args(store, out))
            self.check(code == 0, "full_disk %d: the sweep given room failed: %s" % (limit, err))
            self.check(self.exports(store)[0] == clean, "full_disk %d: exports differ" % limit)
        parts = self.shards()
        for limit in limits[::3]:
            target = self.path("full-merged.sqlite")
            code, _, err = self.run(["merge"] + parts + ["--store", target],
                                    preexec=self.limited(limit))
            self.expect_full(code, err, "full_disk merge at %d bytes" % limit)
            code, _, err = self.run(["merge"] + parts + ["--store", target])
            self.check(code == 0, "full_disk merge %d: run again, it failed: %s" % (limit, err))
            self.check(self.exports(target)[0] == clean, "full_disk merge %d: exports differ" %
                       limit)

    def expect_refused_or_same(self, store, what, clean):
        """A damaged store: refused (exit 2) naming the file, or read identically."""
        text, code, err = self.exports(store)
        if text is None:
            self.check(code == 2 and store in err,
                       "%s: refused with exit %d without naming the file: %s" % (what, code, err))
        else:
            self.check(text == clean, "%s: exports changed silently" % what)
        return text is None

    def damage(self):
        """Guarantee: a truncated or bit-flipped store is either refused (exit 2) with a message
        naming the file, or read identically; never a changed result. A sweep refuses it
        without writing, or (a flip in unused bytes) completes to the clean exports."""
        clean_store, clean = self.clean()
        size = os.path.getsize(clean_store)
        with open(clean_store, "rb") as f:
            original = f.read()
        cuts = list(range(1, 51)) + [4096, 8192] + [self.rng.randrange(1, size) for _ in range(6)]
        for cut in cuts:
            store = self.path("cut.sqlite")
            with open(store, "wb") as f:
                f.write(original[:size - cut])
            refused = self.expect_refused_or_same(store, "truncated by %d bytes" % cut, clean)
            self.check(refused or cut % 4096 == 0, "truncated by %d bytes: not refused" % cut)
        refused = 0
        flips = 160
        for i in range(flips):
            store = self.path("flip.sqlite")
            at = self.rng.randrange(size)
            data = bytearray(original)
            data[at] ^= 1 << self.rng.randrange(8)
            with open(store, "wb") as f:
                f.write(data)
            what = "bit flip at byte %d" % at
            refused += self.expect_refused_or_same(store, what, clean)
            if i % 8 == 0:
                code, _, err = self.run(self.sweep_args(store, self.path("flip-out")))
                if code == 0:
                    self.check(self.exports(store)[0] == clean, "%s: sweep changed results" % what)
                else:
                    self.check(code == 2 and store in err,
                               "%s: sweep failed with %d: %s" % (what, code, err))
                    with open(store, "rb") as f:
                        self.check(f.read() == data, "%s: a refused sweep wrote" % what)
        print("damage: %d of %d bit flips refused, the rest read identically" % (refused, flips))

    def readonly(self):
        """Guarantee: a store the user cannot write (file and folder read-only) is exported and
        merged as a part with the clean sweep's exports; a sweep into it exits 3 naming it and
        leaves it unchanged."""
        clean_store, clean = self.clean()
        user = None
        if os.geteuid() == 0:
            # why: chmod does not stop root; run the commands as nobody instead
            if not shutil.which("setpriv"):
                raise Skip("running as root without setpriv: cannot drop the right to write")
            user = ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"]
        folder, writable = self.path("readonly"), self.path("writable")
        os.makedirs(folder)
        os.makedirs(writable)
        store = os.path.join(folder, "results.sqlite")
        shutil.copyfile(clean_store, store)
        os.chmod(store, 0o444)
        os.chmod(folder, 0o555)
        os.chmod(writable, 0o777)
        with open(store, "rb") as f:
            before = f.read()
        text, code, err = self.exports(store, user=user, out=os.path.join(writable, "exports"))
        self.check(text == clean, "readonly: export failed (%d) or differs: %s" % (code, err))
        merged = os.path.join(writable, "merged.sqlite")
        code, _, err = self.run(["merge", store, "--store", merged], user=user)
        self.check(code == 0, "readonly: merge of a read-only part failed: %s" % err)
        self.check(self.exports(merged)[0] == clean, "readonly: merged exports differ")
        code, _, err = self.run(self.sweep_args(store, os.path.join(writable, "out")), user=user)
        self.check(code == 3 and store in err and "cannot write" in err,
                   "readonly: a sweep into it: exit %d: %s" % (code, err))
        with open(store, "rb") as f:
            self.check(f.read() == before, "readonly: the store changed")
        os.chmod(folder, 0o755)

    # --- issue 22: inputs that must neither destroy, escape nor run anything ---------------------

    def part_store(self):
        """A shard's store of the two-plume sweep, made once."""
        if not hasattr(self, "_part"):
            self._part = self.path("part.sqlite")
            code, _, err = self.run(["sweep", SWEEP, "--runs", SHORT, "--shard", "1/2", "--quiet",
                                     "--store", self._part])
            assert code == 0, err
        return self._part

    def merge_onto_foreign(self):
        """G2: merge onto a file that is not a store: refused, and the file kept byte for byte."""
        part = self.part_store()
        contents = [b"x", b"my notes\n", b"\0" * 4096, b"SQLite format 3\0" + bytes(100)]
        contents += [bytes(self.rng.randrange(256) for _ in range(self.rng.randrange(1, 9000)))
                     for _ in range(6)]
        for data in contents:
            target = self.path("notes.txt")
            with open(target, "wb") as f:
                f.write(data)
            code, _, err = self.run(["merge", part, "--store", target])
            self.check(code == 2, "merge_onto_foreign: %d bytes: exit %d: %s" % (len(data), code, err))
            kept = os.path.exists(target) and open(target, "rb").read() == data
            self.check(kept, "merge_onto_foreign: a %d-byte file was changed or deleted" % len(data))

    def study_folder(self, study):
        """A study folder holding the two-plume sweep as k.toml and `study` as study.toml."""
        folder = self.path("study")
        os.makedirs(folder)
        shutil.copyfile(SWEEP, os.path.join(folder, "k.toml"))
        with open(os.path.join(folder, "study.toml"), "w") as f:
            f.write(study)
        return folder

    def study_escape(self):
        """G3: a study's name leads nowhere but out/NAME, whatever it holds."""
        names = ["../../escaped", "a/b", ".", "..", "/abs", "a\nb", "-x", ".hidden", "ok"]
        letters = "ab./\\-_ \n"
        names += ["".join(self.rng.choice(letters) for _ in range(self.rng.randrange(1, 9)))
                  for _ in range(12)]
        for name in names:
            sandbox = self.path("sandbox")
            cwd = os.path.join(sandbox, "a", "b")
            os.makedirs(cwd)
            # why: a JSON string is a TOML basic string, escapes and all
            folder = self.study_folder('name = %s\nsets = ["k.toml"]\n' % json.dumps(name))
            p = subprocess.run([CLI, "study", folder, "--runs", "1", "--quiet"], cwd=cwd,
                               capture_output=True, text=True, timeout=LIMIT_S)
            made = sorted(os.path.relpath(os.path.join(d, f), sandbox)
                          for d, _, files in os.walk(sandbox) for f in files)
            if p.returncode == 0:
                inside = all(m.startswith(os.path.join("a", "b", "out", "")) for m in made)
                self.check(inside and re.fullmatch(r"[A-Za-z0-9_][A-Za-z0-9_.-]*", name),
                           "study_escape: %r ran and wrote %s" % (name, made))
            else:
                self.check(p.returncode == 2 and "study.toml: name" in p.stderr and not made,
                           "study_escape: %r: exit %d, wrote %s: %s" % (name, p.returncode, made,
                                                                       p.stderr))

    def study_foreign_report(self):
        """G4: no study.toml makes plumetrace run code of the current folder or of the system."""
        cwd = self.path("cwd")
        os.makedirs(os.path.join(cwd, "plumetrace"))
        marker = os.path.join(cwd, "RAN")
        for name in ("evilmod.py", "this.py", os.path.join("plumetrace", "__init__.py"),
                     os.path.join("plumetrace", "evilmod.py")):
            with open(os.path.join(cwd, name), "w") as f:
                f.write("open(%r, 'w').write('ran')\n" % marker)
        reports = ["this", "evilmod", "os", "plumetrace.evilmod", "../evilmod.py",
                   os.path.join(cwd, "evilmod.py"), "evilmod.py", "plumetrace/evilmod.py",
                   "plumetrace..x", ".plumetrace.x", "plumetrace.studies.meander"]
        for report in reports:
            folder = self.study_folder('name = "s"\nsets = ["k.toml"]\nreport = "%s"\n' % report)
            p = subprocess.run([CLI, "study", folder, "--runs", "1", "--quiet", "--out", "o"],
                               cwd=cwd, capture_output=True, text=True, timeout=LIMIT_S)
            self.check(p.returncode in (0, 2, 3),
                       "study_foreign_report: %r: exit %d: %s" % (report, p.returncode, p.stderr))
            self.check(not os.path.exists(marker),
                       "study_foreign_report: %r ran code of the current folder" % report)

    def concurrent_out(self):
        """G19: sweeps on one store and one --out at once all finish with the same exports."""
        self.runs = MID
        clean = self.clean()[1]
        for _ in range(2):
            store, out = self.path("shared.sqlite"), self.path("shared-out")
            procs = [subprocess.Popen([CLI] + self.sweep_args(store, out, ["--threads", str(t)]),
                                      stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
                     for t in (1, 2, 1)]
            for p in procs:
                _, err = p.communicate(timeout=LIMIT_S)
                self.check(p.returncode == 0, "concurrent_out: exit %d: %s" % (p.returncode, err))
            text = ""
            for name in ("runs.csv", "summary.csv", "results.json"):
                with open(os.path.join(out, name), "rb") as f:
                    text += f.read().decode("utf-8", errors="backslashreplace")
            self.check(text == clean, "concurrent_out: the shared --out's exports differ")
            left = [f for f in os.listdir(out) if f.endswith(".part")]
            self.check(not left, "concurrent_out: left behind: %s" % left)
    def calibrate_inputs(self):
        """G5-G7, G9, G12: the calibration module on hostile inputs ends in one line with status
        2 or 3 and no traceback, without blocking; a busy folder is refused at once."""
        python_dir = os.path.join(os.path.dirname(CLI), "python")
        if not os.path.isdir(os.path.join(python_dir, "plumetrace")):
            raise Skip("no Python module beside the command (a build without PLUMETRACE_BUILD_PYTHON)")
        env = dict(os.environ, PYTHONPATH=python_dir)
        calib = os.path.join(SOURCE, "studies", "lochmatter2008", "calibration.toml")
        work = self.path("calibrate")
        os.makedirs(work)

        def file(name, data):
            path = os.path.join(work, name)
            with open(path, "wb") as f:
                f.write(data)
            return path

        fifo = os.path.join(work, "fifo.toml")
        os.mkfifo(fifo)
        deep = file("deep.toml", (".".join(["k"] * 50000) + " = 1\n").encode())
        latin = file("latin.toml", "name = 'caf\xe9'\n".encode("latin-1"))
        huge = file("huge.toml", b"# " + b"x" * (17 << 20) + b"\n")
        folder = os.path.dirname(calib)
        with open(calib, "rb") as f:
            text = f.read()
        # the shipped study with its folders made absolute and a run count past the limit
        text = text.replace(b'"unknowns.toml"', ('"%s/unknowns.toml"' % folder).encode())
        text = text.replace(b'sets_dir = "sets"', ('sets_dir = "%s/sets"' % folder).encode())
        runs = file("runs.toml", text.replace(b"\nruns = 10\n", b"\nruns = 100000000\n"))
        a_file = file("a-file", b"keep\n")
        busy = os.path.join(work, "busy")
        os.makedirs(busy)
        cases = [([fifo], 2, "not a regular file"), ([work], 2, "a folder, not a file"),
                 ([deep], 2, "dotted parts"), ([latin], 2, "latin.toml"),
                 ([huge], 2, "larger than"), ([runs], 2, "runs"),
                 ([calib, "--out", ""], 2, "--out"), ([calib, "--out", a_file], 2, "a-file"),
                 ([calib, "--out", "/proc/plumetrace-calibration"], 3, "/proc"),
                 ([calib, "--out", busy], 3, "busy")]
        import fcntl
        with open(os.path.join(busy, ".lock"), "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
            for args, want, names in cases:
                out = [] if "--out" in args else ["--out", os.path.join(work, "out")]
                p = subprocess.run(["/usr/bin/python3", "-m", "plumetrace.calibrate"] + args + out
                                   + ["--quiet"], capture_output=True, text=True, env=env,
                                   cwd=work, timeout=LIMIT_S)
                lines = p.stderr.strip().splitlines()
                self.check(p.returncode == want and len(lines) == 1 and "Traceback" not in p.stderr
                           and (names in p.stderr or names == "busy"),
                           "calibrate_inputs: %s: exit %d (want %d): %s" % (
                               args, p.returncode, want, p.stderr[-300:]))
        self.check(open(a_file, "rb").read() == b"keep\n", "calibrate_inputs: --out a file changed it")

CASES = ["kill_sweep", "kill_merge", "kill_mpi", "concurrent", "full_disk", "damage", "readonly",
         "merge_onto_foreign", "study_escape", "study_foreign_report", "concurrent_out",
         "calibrate_inputs"]


def main(argv):
    names = CASES if argv == ["all"] else argv
    if not CLI or not names or any(n not in CASES for n in names):
        print(__doc__)
        return 2
    work = tempfile.mkdtemp(prefix="plumetrace-faults-")
    os.chmod(work, 0o755)  # why: the read-only case runs commands as another user
    campaign = Campaign(work)
    skipped = []
    try:
        for name in names:
            start = time.monotonic()
            campaign.runs = SHORT
            campaign.kept = []
            try:
                getattr(campaign, name)()
                if campaign.kept:
                    print("%s: %d stores left by a kill or a failed write held %s runs" %
                          (name, len(campaign.kept), sorted(campaign.kept)))
                print("%s: done in %.1f s" % (name, time.monotonic() - start), flush=True)
            except Skip as e:
                print("%s: skipped: %s" % (name, e), flush=True)
                skipped.append(name)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("%d checks, %d failed (seed %d)" % (campaign.checks, len(campaign.failures), SEED))
    if campaign.failures:
        return 1
    return SKIP if skipped and len(skipped) == len(names) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
