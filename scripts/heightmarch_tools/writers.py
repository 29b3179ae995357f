"""Files written whole and files shared between processes.

- atomic_write: a temporary file beside the target, world-readable, then renamed over it: a
  reader, or a run interrupted at any point, sees the old file or the new one, never half of one.
- locked: an exclusive flock on PATH.lock (never a link) for a read-modify-write of PATH that two
  processes may do at once (two suites recording into one history): the second waits for the
  first, at most LOCK_WAIT seconds.
- subdirectory: a directory of the run's own (plots/) to write into, never a link that would send
  its files elsewhere.
"""
import contextlib
import errno
import fcntl
import os
import stat
import tempfile
import time

from .errors import CannotWrite, Unusable
from .escape import terminal

LOCK_WAIT = 600.0  # seconds: a report holds the history's lock for seconds, a stuck holder is named
LOCK_POLL = 0.05


def atomic_write(path, text):
    """Writes text (str or bytes) to path through a temporary file and a rename; CannotWrite
    (a full disk, a read-only directory) leaves path as it was and no temporary behind."""
    directory = os.path.dirname(os.path.abspath(path))
    try:
        fd, temporary = tempfile.mkstemp(dir=directory, prefix=".tmp-")
    except OSError as e:
        raise CannotWrite("%s: cannot write: %s" % (terminal(path), e.strerror))
    try:
        with os.fdopen(fd, "wb" if isinstance(text, bytes) else "w", encoding=None if isinstance(text, bytes) else "utf-8") as f:
            f.write(text)
        os.chmod(temporary, 0o644)
        os.replace(temporary, path)
    except BaseException as e:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        if isinstance(e, OSError):
            raise CannotWrite("%s: cannot write: %s" % (terminal(path), e.strerror or e)) from None
        raise


def subdirectory(run_dir, name):
    """RUN_DIR/name, made where missing; Unusable where it is a link or not a directory (a run
    directory from elsewhere with plots/ linked to another directory: its files would land there)."""
    path = os.path.join(run_dir, name)
    try:
        os.mkdir(path)
    except FileExistsError:
        pass
    except OSError as e:
        raise CannotWrite("%s: cannot make it: %s" % (terminal(path), e.strerror))
    mode = os.lstat(path).st_mode
    if not stat.S_ISDIR(mode):
        raise Unusable("%s: is %s, not a directory of the run's own to write into" % (
            terminal(path), "a link" if stat.S_ISLNK(mode) else "not a directory"))
    return path


@contextlib.contextmanager
def locked(path, wait=LOCK_WAIT):
    """Holds an exclusive lock on path + ".lock" for the body of a with statement."""
    lock_path = path + ".lock"
    try:
        fd = os.open(lock_path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC, 0o644)
    except OSError as e:
        why = "a link, refused" if e.errno == errno.ELOOP else e.strerror
        raise CannotWrite("%s: cannot lock it (%s: %s)" % (terminal(path), terminal(lock_path), why))
    try:
        deadline = time.monotonic() + wait
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except BlockingIOError:
                if time.monotonic() >= deadline:
                    raise Unusable("%s: another process has held its lock (%s) for %.0f s" % (
                        terminal(path), terminal(lock_path), wait))
                time.sleep(LOCK_POLL)
        yield
    finally:
        os.close(fd)  # releases the lock
