"""Child processes that end with the tool that started them.

Each child runs in a process group of its own (a build's compilers, a benchmark's GLSL worker are
in it too), and a signal to the tool (SIGINT, SIGTERM, SIGHUP) becomes an Interrupted exception
in its main thread: the wait on the child ends, the child's whole group is ended (SIGTERM, then
SIGKILL after a grace), and every `with` block on the way out cleans up (worktrees, temporary
files) before the tool exits with 128 + the signal's number, without a traceback.
scripts/regress and scripts/bisect use it.
"""
import os
import signal
import subprocess
import time

SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
GRACE_SECONDS = 5.0  # a group told to end with SIGTERM has this long before SIGKILL


class Interrupted(Exception):
    """A signal arrived: the tool cleans up and exits 128 + signum."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def raise_on_signals():
    """From now on the first of SIGNALS raises Interrupted; later ones are ignored, so the clean-up
    that the first started is not itself interrupted."""
    def handler(signum, frame):
        for s in SIGNALS:
            signal.signal(s, signal.SIG_IGN)
        raise Interrupted(signum)

    for s in SIGNALS:
        signal.signal(s, handler)


def group_alive(pgid):
    try:
        os.killpg(pgid, 0)
        return True
    except ProcessLookupError:
        return False
    except PermissionError:  # a member we cannot signal: not ours to end
        return False


def end_group(process):
    """Ends process's group: SIGTERM, then SIGKILL to what is left after GRACE_SECONDS; reaps the
    leader."""
    for sig in (signal.SIGTERM, signal.SIGKILL):
        try:
            os.killpg(process.pid, sig)
        except (ProcessLookupError, PermissionError):
            break
        deadline = time.monotonic() + GRACE_SECONDS
        while time.monotonic() < deadline:
            if process.poll() is not None and not group_alive(process.pid):
                break
            time.sleep(0.05)
        else:
            continue
        break
    try:
        process.wait(timeout=GRACE_SECONDS)
    except subprocess.TimeoutExpired:
        pass  # SIGKILL was sent: it is gone as soon as the kernel lets it go


def run(command, **kwargs):
    """subprocess.run(command, **kwargs) with the child in a process group of its own, which is
    ended if anything (Interrupted, an error) breaks the wait."""
    with subprocess.Popen(command, process_group=0, **kwargs) as process:
        try:
            stdout, stderr = process.communicate()
        except BaseException:
            end_group(process)
            raise
    return subprocess.CompletedProcess(command, process.returncode, stdout, stderr)
