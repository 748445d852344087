"""Worker processes for sweeps and benchmarks whose controller is written in Python.

A Python controller takes the interpreter's lock (the GIL) for each of its decisions, so the C++
threads of one process decide one at a time. The bindings (python/bindings.cpp,
``process_runner``) instead hand a campaign's plume groups to the workers of a ProcessPool, each
a fork of the calling process: it holds the campaign, the registered controllers and the
controller factory already, and decides in its own interpreter. Jobs and results travel as the
bytes of the MPI runner's format (a group's tasks in, its rows out), so the rows are those of
one process, bit for bit; the caller sorts and stores them as it does its threads' rows.

Why fork and not spawn: a spawned worker starts a fresh interpreter, which has none of the
controllers registered in this one, nor a controller factory that pickle cannot carry (a
lambda, a class defined in ``__main__`` or a notebook); a forked one has them all, costs
milliseconds to start, and shares the parent's memory until it writes (docs/python.md).
"""

import collections
import multiprocessing
import pickle
import signal
import sys
import time
import traceback
from multiprocessing.connection import wait

__all__ = ["ProcessPool", "RemoteTraceback", "WorkerError", "can_fork"]

# seconds that groups already running may take to finish once the pool is stopped (Ctrl-C), as
# the MPI coordinator waits for the ranks' last rows; then their workers are ended
STOP_GRACE = 0.5

# the first byte of a worker's message: rows (encode_rows), or an error (pickled)
_ROWS, _ERROR = b"R", b"E"


def can_fork():
    """Whether this platform forks processes (Linux, macOS; not Windows): without it, every run
    stays in the calling process."""
    return "fork" in multiprocessing.get_all_start_methods()


class RemoteTraceback(Exception):
    """The traceback of an exception raised in a worker process, as its text: the cause
    (``__cause__``) of the exception raised in the caller, so that printing it shows where the
    controller failed."""

    def __init__(self, text):
        super().__init__(text)
        self.text = text

    def __str__(self):
        return f'\n"""\n{self.text}"""'


class WorkerError(RuntimeError):
    """An exception of a worker process that cannot travel to the caller as itself (its class
    does not pickle, or a worker died): its type, message and worker in words."""


class ProcessPool:
    """`processes` workers forked from this process, each calling ``work(job) -> bytes`` on the
    jobs (bytes) handed out one at a time, in order, to whichever worker is free. ``take``
    gathers what they send; ``finish`` raises the first error; ``close`` ends them all. A
    worker's first error stops the handing out (the running jobs finish, as a sweep's threads
    do). Ctrl-C here, or ``take(stop=True)``, stops it too, and the jobs still running
    STOP_GRACE s later are given up; a worker ignores Ctrl-C, which this process handles."""

    def __init__(self, work, jobs, processes):
        self._queue = collections.deque(jobs)
        self._error = None        # (exception, traceback text or None), the first one
        self._stopped = False
        self._deadline = None     # when groups still running are given up, once stopped
        self._busy = {}           # connection -> process, with a job in hand
        self._workers = []        # (process, connection), every one started
        context = multiprocessing.get_context("fork")
        # why: a worker inherits what this process has not written yet, and would write it again
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (AttributeError, OSError, ValueError):  # none, or closed
                pass
        try:
            for _ in range(processes):
                mine, theirs = context.Pipe()
                # why: a worker closes the ends of this process it inherited, so that each one
                # sees the end of its pipe (EOF) when this process is gone
                ours = [c for _, c in self._workers] + [mine]
                process = context.Process(target=_serve, args=(theirs, work, ours), daemon=True,
                                          name=f"plumetrace-worker-{len(self._workers) + 1}")
                process.start()
                theirs.close()
                self._workers.append((process, mine))
                self._hand_out(mine, process)
        except BaseException:
            self.close()
            raise

    def take(self, timeout, stop=False):
        """Waits up to `timeout` s for rows. Returns (rows, idle): the bytes every worker sent
        since the last call, and whether the pool has ended (nothing to hand out, or stopped,
        and no job running). `stop` hands out nothing more."""
        if stop:
            self._stop(STOP_GRACE)
        rows = []
        try:
            self._gather(rows, timeout)
        except BaseException as e:  # noqa: BLE001 -- Ctrl-C, or what else a signal handler raises
            # why: raised once the running jobs have sent their rows (finish), so that a sweep
            # keeps the runs finished before, as its threads do
            self._record(e, None)
            self._stop(STOP_GRACE)
        return rows, not self._busy

    def finish(self):
        """Raises the first error: a worker's exception, as itself with the worker's traceback
        as its cause (RemoteTraceback), or Ctrl-C received here."""
        if self._error is None:
            return
        error, text = self._error
        self._error = None
        if text is None:
            raise error
        raise error from RemoteTraceback(text)

    def close(self):
        """Ends every worker (those still running are terminated) and reaps it: no process is
        left behind, whatever ended the work."""
        for process, connection in self._workers:
            try:
                if process.is_alive() and connection in self._busy:
                    process.terminate()
                else:
                    connection.send_bytes(b"")
            except (OSError, ValueError):
                pass
        for process, connection in self._workers:
            _reap(process)
            connection.close()
        self._workers, self._busy = [], {}

    def _hand_out(self, connection, process):
        if self._stopped or not self._queue:
            return
        connection.send_bytes(self._queue.popleft())
        self._busy[connection] = process

    def _stop(self, grace=None):
        """Hands out nothing more; with `grace`, ends the jobs still running after it (s)."""
        self._stopped = True
        if grace is not None:
            deadline = time.monotonic() + grace
            self._deadline = deadline if self._deadline is None else min(self._deadline, deadline)

    def _gather(self, rows, timeout):
        until = time.monotonic() + timeout
        while self._busy:
            left = until - time.monotonic()
            if self._deadline is not None:
                left = min(left, self._deadline - time.monotonic())
            if left <= 0:
                break
            for connection in wait(list(self._busy), left):
                process = self._busy.pop(connection)
                try:
                    message = connection.recv_bytes()
                except (EOFError, OSError):
                    process.join(1.0)
                    self._record(WorkerError(f"{process.name} ended without a word ("
                                             f"{_ending(process)})"), None)
                    self._stop()
                    continue
                if message[:1] == _ROWS:
                    rows.append(message[1:])
                    self._hand_out(connection, process)
                else:
                    self._record(*_error_of(message[1:], process.name))
                    self._stop()
            if not self._busy:
                break
        if self._deadline is not None and time.monotonic() >= self._deadline:
            # the groups still running after the grace: their workers are ended, their runs lost
            for connection, process in list(self._busy.items()):
                process.terminate()
                del self._busy[connection]

    def _record(self, error, text):
        if self._error is None:
            self._error = (error, text)


def _serve(connection, work, inherited):
    """A worker: runs `work` on each job received and sends back its result, until told to
    stop (an empty job), its pipe ends, or `work` raises, whose exception it sends back."""
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # forked from a thread that is not the main one: no signal arrives there
        pass
    for c in inherited:
        c.close()
    while True:
        try:
            job = connection.recv_bytes()
        except (EOFError, OSError):
            return
        if not job:
            return
        try:
            out = work(job)
        except BaseException as e:  # noqa: BLE001 -- every error goes back to the caller
            _send(connection, _ERROR + _error_bytes(e))
            return
        if not _send(connection, _ROWS + out):
            return


def _send(connection, message):
    try:
        connection.send_bytes(message)
        return True
    except (OSError, ValueError):  # the caller is gone
        return False


def _error_bytes(error):
    """An exception as it travels: itself (pickled) when it pickles, its type and message, and
    its traceback as text."""
    text = "".join(traceback.format_exception(error))
    kind = f"{type(error).__module__}.{type(error).__qualname__}"
    try:
        itself = pickle.dumps(error)
    except Exception:  # noqa: BLE001 -- an exception that does not pickle goes as words
        itself = None
    return pickle.dumps((itself, kind, str(error), text))


def _error_of(message, worker):
    """(exception, traceback text) from _error_bytes' message."""
    itself, kind, words, text = pickle.loads(message)
    if itself is not None:
        try:
            error = pickle.loads(itself)
            if isinstance(error, BaseException):
                return error, text
        except Exception:  # noqa: BLE001 -- a class that does not unpickle goes as words
            pass
    return WorkerError(f"{kind}: {words} (raised in {worker})"), text


def _ending(process):
    code = process.exitcode
    if code is None:
        return "still running"
    if code < 0:
        try:
            return f"killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"killed by signal {-code}"
    return f"exit status {code}"


def _reap(process):
    """Waits for `process` to end, terminating and then killing it if it lingers; Ctrl-C while
    waiting does not leave it unreaped."""
    while True:
        try:
            process.join(2.0)
            if process.is_alive():
                process.kill()
                process.join()
            return
        except KeyboardInterrupt:
            process.kill()
