"""Child processes that end with the tool that started them.

Each child runs in a process group of its own (a build's compilers, a benchmark's GLSL worker are
in it too). When anything breaks the wait on it, cli.Interrupted above all (a signal to the tool,
cli.run raises it), the child's whole group is ended: SIGTERM, then SIGKILL after a grace. Clean-up
that must not be cut short (ending a group, removing a worktree) runs with the signals held back
until it is done. regress and bisect use it.
"""
import contextlib
import os
import signal
import subprocess
import time

from .cli import SIGNALS

GRACE_SECONDS = 5.0  # a group told to end with SIGTERM has this long before SIGKILL


@contextlib.contextmanager
def signals_held():
    """The block runs whole: a signal that arrives meanwhile is delivered (and raised) after it."""
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def group_alive(pgid):
    try:
        os.killpg(pgid, 0)
        return True
    except (ProcessLookupError, PermissionError):  # gone, or not ours to end
        return False


def end_group(process):
    """Ends process's group (SIGTERM, then SIGKILL to what is left after GRACE_SECONDS) and reaps
    its leader."""
    with signals_held():
        for sig in (signal.SIGTERM, signal.SIGKILL):
            try:
                os.killpg(process.pid, sig)
            except (ProcessLookupError, PermissionError):
                break
            deadline = time.monotonic() + GRACE_SECONDS
            while time.monotonic() < deadline and (process.poll() is None or group_alive(process.pid)):
                time.sleep(0.05)
            if process.poll() is not None and not group_alive(process.pid):
                break
        try:
            process.wait(timeout=GRACE_SECONDS)
        except subprocess.TimeoutExpired:
            pass  # SIGKILL was sent: it goes as soon as the kernel lets it


def run(command, **kwargs):
    """subprocess.run(command, **kwargs) with the child in a process group of its own, ended with
    its group if anything breaks the wait."""
    with subprocess.Popen(command, process_group=0, **kwargs) as process:
        try:
            stdout, stderr = process.communicate()
        except BaseException:
            end_group(process)
            raise
    return subprocess.CompletedProcess(command, process.returncode, stdout, stderr)
