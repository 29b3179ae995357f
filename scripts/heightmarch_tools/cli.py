"""The one top-level handler of every entry point: whatever stops a tool reaches the user as one
line, never a traceback, and whatever it prints reaches the terminal printable (stdout and stderr
pass every line through escape.terminal: a benchmark's or a map's name with ESC ] or ESC [ 2J
is shown, never obeyed).

    sys.exit(cli.run("report", "report"))    # heightmarch_tools.report's main(), imported under the handler

- errors.Unusable: "PROG: message", exit 2;
- errors.CannotWrite, OSError (a full disk, a closed pipe): "PROG: message", exit 1;
- Ctrl-C (SIGINT), SIGTERM, SIGHUP: "PROG: interrupted (SIGTERM)", exit 128 + the signal; the
  signals are raised as an exception, so `finally` blocks and context managers (temporary files,
  locks, worktrees) clean up on the way out. Once the tool's work is committed (committed(): a run
  recorded into the history), a signal no longer undoes it: "PROG: SIGTERM came after the run was
  recorded in H: it is complete and recorded", exit 0, so that a caller who reruns what exited
  non-zero never records a run twice;
- any other exception (a bug): "PROG: internal error: ..." with the file and line it came from,
  exit 1; HEIGHTMARCH_TRACEBACK=1 shows the whole traceback instead.
"""
import argparse
import importlib
import os
import signal
import sys
import traceback

from .errors import CannotWrite, Unusable
from .escape import terminal, terminal_line

SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class Interrupted(BaseException):
    """A signal asked the tool to stop (BaseException: no `except Exception` swallows it)."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def _raise_interrupted(signum, _frame):
    raise Interrupted(signum)


_committed = None  # what committed() said: the work is done and kept; None before


def committed(what):
    """From here on the tool's work is done and kept (what: "the run was recorded in H"): a signal
    that ends the tool now exits 0 with a line that it came after. Call it with the signals held
    (processes.signals_held) from before the write that commits, so no signal falls between the
    two."""
    global _committed
    _committed = what


class PrintableStream:
    """A text stream whose lines go out through escape.terminal (line breaks kept)."""

    def __init__(self, stream):
        self.stream = stream

    def write(self, text):
        self.stream.write("\n".join(terminal(line) for line in text.split("\n")))
        return len(text)

    def __getattr__(self, name):  # flush, fileno, isatty, encoding, ...
        return getattr(self.stream, name)


def say(prog, message):
    """One line on stderr, printable and of bounded length (a long echoed value cut in its middle)."""
    try:
        sys.stdout.flush()  # what was printed before comes first
    except (OSError, ValueError):
        pass
    print("%s: %s" % (prog, terminal_line(message)), file=sys.stderr)


class Parser(argparse.ArgumentParser):
    """Usage errors as Unusable: one line, exit 2."""

    def error(self, message):
        raise Unusable(message)


def run(prog, main, *args):
    """The exit status of main(*args), or of the function a "module:function" string names in
    this package (main() by default; imported once the handler is in place: Ctrl-C while
    matplotlib loads is one line too), every way it can stop turned into one line and a status."""
    for s in SIGNALS:
        signal.signal(s, _raise_interrupted)
    streams = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = PrintableStream(sys.stdout), PrintableStream(sys.stderr)
    try:
        return _run(prog, main, *args)
    finally:
        # The tool has ended: a signal from here to the exit changes nothing (its status stands;
        # Interrupted raised now would reach the user as a traceback).
        for s in SIGNALS:
            signal.signal(s, signal.SIG_IGN)
        sys.stdout, sys.stderr = streams


def _run(prog, main, *args):
    global _committed
    _committed = None
    try:
        if isinstance(main, str):
            module, _, function = main.partition(":")
            main = getattr(importlib.import_module("." + module, __package__), function or "main")
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
        if _committed:
            say(prog, "%s came after %s: it is complete and recorded" % (signal.Signals(signum).name, _committed))
            return 0
        say(prog, "interrupted (%s)" % signal.Signals(signum).name)
        return 128 + signum
    except Exception as e:
        if os.environ.get("HEIGHTMARCH_TRACEBACK"):
            raise
        where = traceback.extract_tb(e.__traceback__)[-1]
        say(prog, "internal error: %s: %s (%s:%d; HEIGHTMARCH_TRACEBACK=1 shows the traceback)" % (
            type(e).__name__, e, os.path.basename(where.filename), where.lineno))
        return 1
