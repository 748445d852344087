"""Files as every plumetrace Python module opens them, with the guarantees of the command line
(docs/reliability.md): inputs are regular files opened without blocking and bounded in size, an
output folder is checked before anything is computed, outputs appear whole or not at all, and
one process at a time works in a folder.

Pure Python (no C++ module), so that modules which run without it use it too. Errors are one
line naming the option or file: ``BadPath`` (a ValueError: exit status 2, bad input) and
``FileIoError`` (an OSError: exit status 3, the system could not open, read, write or lock).
"""

import errno
import fcntl
import os
import stat
import tempfile
from pathlib import Path

__all__ = ["BadPath", "FileIoError", "FolderBusy", "MAX_INPUT_BYTES", "MAX_RESULTS_BYTES",
           "exit_status", "folder_lock", "output_folder", "read_input", "read_toml", "write_whole"]

# The largest input file read (a study, sweep or unknowns file): 16 MiB, the C++ reader's
# kMaxInputBytes (include/plumetrace/core/files.hpp; a test compares them). why: an input is read
# whole, then parsed into a tree several times its size; no file of this project comes near
MAX_INPUT_BYTES = 16 * 1024 * 1024
# The largest results file a report reads (results.json, summary.json: 2 GiB, the C++
# kMaxTraceBytes). why: results.json holds every run, some 300 bytes each, so a campaign at the
# run limit (1e7) is gigabytes; the bound keeps only a wrong file out
MAX_RESULTS_BYTES = 2 * 1024 * 1024 * 1024

# what an OSError's errno means for the user, where the system's own words say less
_CAUSES = {
    errno.ENOSPC: "the disk is full",
    errno.EDQUOT: "the disk quota is exhausted",
    errno.EFBIG: "the file size limit is reached",
    errno.EROFS: "the file system is read-only",
}


class BadPath(ValueError):
    """A path that cannot be used as given (empty, a folder where a file is wanted, a FIFO, too
    large); bad input, exit status 2. The message names the option or file."""


class FileIoError(OSError):
    """The system could not open, read, write or lock a file (rights, a read-only or full disk);
    exit status 3. The message names the option or file."""


class FolderBusy(FileIoError):
    """Another process works in the folder (holds its lock); exit status 3."""


def _umask():
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _cause(error):
    return _CAUSES.get(error.errno) or error.strerror or str(error)


def read_input(path, what, max_bytes=MAX_INPUT_BYTES):
    """The bytes of the input file `path` (`what` names it: "study file"), read as the C++ reader
    reads every input (read_regular_file): opened without blocking, checked to be a regular file
    on the open descriptor, at most `max_bytes` long. Raises BadPath
    "cannot read WHAT 'PATH': WHY", WHY being "a folder, not a file", "not a regular file", the
    size, or the system's reason.

    why: a FIFO named as an input would block open() and read() for ever, a device would be read
    without end, and a check of the type by name could be raced by a rename (issue 13, F8)."""
    def refuse(why):
        shown = os.fspath(path).replace("\0", "\\0")
        return BadPath(f"cannot read {what} '{shown}': {why}")

    # why: the operating system reads a path up to its first NUL
    if "\0" in os.fspath(path):
        raise refuse("the path holds a NUL character")
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)
    except OSError as e:
        raise refuse(_cause(e)) from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise refuse("a folder, not a file" if stat.S_ISDIR(st.st_mode) else
                         "not a regular file")
        chunks, size = [], 0
        while True:
            chunk = os.read(fd, 1 << 16)
            if not chunk:
                return b"".join(chunks)
            size += len(chunk)
            # why: counted while reading, so a file that grows after fstat is bounded too
            if size > max_bytes:
                raise refuse(f"larger than {max_bytes} bytes, the most an input file may have "
                             f"(it has {os.fstat(fd).st_size})")
            chunks.append(chunk)
    except OSError as e:
        raise refuse(_cause(e)) from None
    finally:
        os.close(fd)


def exit_status(error):
    """The exit status of a command that stops on `error`, as the C++ command's (docs/
    reliability.md, "Exit codes"): 3 when the system could not open, read or write (OSError,
    FileIoError), 2 for bad input (BadPath, a malformed file)."""
    return 3 if isinstance(error, OSError) else 2


def read_toml(path, what):
    """The TOML file `path` as a dict, read by read_input; raises BadPath naming `what` and the
    file when it cannot be read, is not UTF-8 or is not TOML."""
    import tomllib

    try:
        return tomllib.loads(read_input(path, what).decode("utf-8"))
    except UnicodeDecodeError as e:
        raise BadPath(f"{what} '{path}': not UTF-8 text ({e.reason} at byte {e.start})") from None
    except tomllib.TOMLDecodeError as e:
        raise BadPath(f"{what} '{path}': invalid TOML: {e}") from None


def output_folder(path, option):
    """The output folder `path` given by `option` ("--out"), created with its parents and checked
    to be a folder this process can write in (a file is made in it and removed); returns it as a
    Path. Raises BadPath for an empty path and FileIoError for a folder that cannot be made or
    written (a file of that name, rights, a read-only or full disk, /proc)."""
    text = os.fspath(path) if path is not None else ""
    if not text:
        raise BadPath(f"{option}: an empty path; name a folder")
    if "\0" in text:
        raise BadPath(f"{option}: {text!r} holds a NUL character")
    folder = Path(text)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        pass  # a file of that name: said below
    except OSError as e:
        raise FileIoError(f"{option}: cannot make the folder '{folder}': {_cause(e)}") from None
    if not folder.is_dir():
        # bad input, as for the C++ command (make_output_folder): the path names a file
        raise BadPath(f"{option}: '{folder}' is a file, not a folder")
    try:
        fd, probe = tempfile.mkstemp(prefix=".write-test.", dir=folder)
        os.close(fd)
        os.unlink(probe)
    except OSError as e:
        raise FileIoError(f"{option}: cannot write in '{folder}': {_cause(e)}") from None
    return folder


class folder_lock:
    """Holds an exclusive lock on `folder` (flock on its file `name`) while in the `with` block,
    so that one process at a time works in it; a second is refused at once with FolderBusy
    naming the folder and the option. The lock file stays (removing it would let a third process
    lock another file of the same name); the lock itself ends with the process, even a killed
    one."""

    def __init__(self, folder, option, name=".lock"):
        self.folder, self.option, self.path = Path(folder), option, Path(folder) / name
        self.fd = None

    def __enter__(self):
        try:
            self.fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        except OSError as e:
            raise FileIoError(f"{self.option}: cannot make the lock file '{self.path}': "
                              f"{_cause(e)}") from None
        try:
            fcntl.flock(self.fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as e:
            os.close(self.fd)
            self.fd = None
            if e.errno in (errno.EWOULDBLOCK, errno.EAGAIN):
                raise FolderBusy(f"{self.option}: '{self.folder}' is in use by another process "
                                 "(it holds the folder's lock); wait for it to finish or use "
                                 "another folder") from None
            raise FileIoError(f"{self.option}: cannot lock '{self.path}': {_cause(e)}") from None
        return self

    def __exit__(self, *exc):
        if self.fd is not None:
            os.close(self.fd)  # closing the descriptor releases the lock
            self.fd = None
        return False


def write_whole(path, data):
    """Writes `data` (str or bytes) to `path` whole or not at all: into a temporary file of a name
    unique to this writer in the same folder, flushed, then renamed over `path`. Raises
    FileIoError naming `path` and the cause (a full disk, the file size limit, a read-only file
    system, rights); the temporary file is removed then.

    why: a reader, or a process killed while writing, never sees half a file, and two writers
    never share one temporary name (issue 22, G19)."""
    path = Path(path)
    if isinstance(data, str):
        data = data.encode("utf-8")
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o666 & ~_umask())  # as open() would have made it
        os.replace(tmp, path)
        tmp = None
    except OSError as e:
        raise FileIoError(f"cannot write '{path}': {_cause(e)}") from None
    finally:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass
    return path
