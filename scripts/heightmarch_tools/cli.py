"""The one top-level handler of every entry point: whatever stops a tool reaches the user as one
line, never a traceback.

    sys.exit(cli.run("report", "report"))    # heightmarch_tools.report's main(), imported under the handler

- errors.Unusable: "PROG: message", exit 2;
- errors.CannotWrite, OSError (a full disk, a closed pipe): "PROG: message", exit 1;
- Ctrl-C (SIGINT), SIGTERM, SIGHUP: "PROG: interrupted (SIGTERM)", exit 128 + the signal; the
  signals are raised as an exception, so `finally` blocks and context managers (temporary files,
  locks, worktrees) clean up on the way out.
"""
import argparse
import importlib
import signal
import sys

from .errors import CannotWrite, Unusable
from .escape import terminal

SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class Interrupted(BaseException):
    """A signal asked the tool to stop (BaseException: no `except Exception` swallows it)."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def _raise_interrupted(signum, _frame):
    raise Interrupted(signum)


def say(prog, message):
    """One line on stderr, printable."""
    try:
        sys.stdout.flush()  # what was printed before comes first
    except (OSError, ValueError):
        pass
    print("%s: %s" % (prog, terminal(message)), file=sys.stderr)


class Parser(argparse.ArgumentParser):
    """Usage errors as Unusable: one line, exit 2."""

    def error(self, message):
        raise Unusable(message)


def run(prog, main, *args):
    """The exit status of main(*args), or of the main() of this package's module named main
    (imported once the handler is in place: Ctrl-C while matplotlib loads is one line too),
    every way it can stop turned into one line and a status."""
    for s in SIGNALS:
        signal.signal(s, _raise_interrupted)
    try:
        if isinstance(main, str):
            main = importlib.import_module("." + main, __package__).main
        return main(*args)
    except Unusable as e:
        say(prog, str(e))
        return 2
    except CannotWrite as e:
        say(prog, str(e))
        return 1
    except BrokenPipeError:
        return 1  # the reader went away: nothing more to say to it
    except OSError as e:
        say(prog, "%s%s" % (e.strerror or e, ": %s" % e.filename if e.filename else ""))
        return 1
    except (Interrupted, KeyboardInterrupt) as e:
        signum = e.signum if isinstance(e, Interrupted) else signal.SIGINT
        for s in SIGNALS:  # a second signal while cleaning up ends it at once
            signal.signal(s, signal.SIG_DFL)
        say(prog, "interrupted (%s)" % signal.Signals(signum).name)
        return 128 + signum
