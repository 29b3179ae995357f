"""cli: whatever stops a tool is one line and a status, never a traceback."""
import os
import signal
import subprocess
import sys

import pytest

from heightmarch_tools import cli
from heightmarch_tools.errors import CannotWrite, Unusable

SCRIPTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts")


@pytest.fixture(autouse=True)
def default_signals():
    """cli.run takes SIGINT, SIGTERM and SIGHUP over; pytest's own handling comes back after each test."""
    yield
    for s in cli.SIGNALS:
        signal.signal(s, signal.default_int_handler if s == signal.SIGINT else signal.SIG_DFL)


def raises(exception):
    def main():
        raise exception
    return main


def test_statuses_and_one_line(capsys):
    assert cli.run("tool", raises(Unusable("x.json: row 3: threads: is -1"))) == 2
    assert cli.run("tool", raises(CannotWrite("report.md: cannot write: No space left on device"))) == 1
    assert cli.run("tool", raises(KeyboardInterrupt())) == 130
    assert cli.run("tool", raises(Unusable("\x1b]0;PWN\x07"))) == 2
    err = capsys.readouterr().err.splitlines()
    assert err == ["tool: x.json: row 3: threads: is -1", "tool: report.md: cannot write: No space left on device",
                   "tool: interrupted (SIGINT)", "tool: \\x1b]0;PWN\\x07"]


def test_sigterm_is_one_line_and_cleans_up(tmp_path):
    marker = tmp_path / "cleaned"
    code = ("import sys, time\nfrom heightmarch_tools import cli\n"
            "def main():\n    try:\n        print('ready', flush=True)\n        time.sleep(30)\n"
            "    finally:\n        open(%r, 'w').close()\nsys.exit(cli.run('tool', main))\n" % str(marker))
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env=dict(os.environ, PYTHONPATH=SCRIPTS))
    assert child.stdout.readline() == "ready\n"
    child.send_signal(signal.SIGTERM)
    _, err = child.communicate(timeout=30)
    assert child.returncode == 128 + signal.SIGTERM and err == "tool: interrupted (SIGTERM)\n" and marker.exists()


def test_a_bug_is_one_line_naming_where(capsys):
    assert cli.run("tool", raises(ValueError("bad"))) == 1
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("tool: internal error: ValueError: bad (test_cli.py:")


def test_what_a_tool_prints_is_printable(capsys):
    def main():
        print("BM_Trace/heightfield:\x1b]0;PWN\x07/isa:avx2\tq")
        return 0
    assert cli.run("tool", main) == 0
    assert capsys.readouterr().out == "BM_Trace/heightfield:\\x1b]0;PWN\\x07/isa:avx2\\x09q\n"


def test_a_signal_once_the_tool_has_ended_leaves_its_status():
    """A signal between the tool's end and the interpreter's exit changes nothing: no traceback,
    the status the tool ended with."""
    code = ("import os, signal, sys\nfrom heightmarch_tools import cli\n"
            "status = cli.run('tool', lambda: 3)\nos.kill(os.getpid(), signal.SIGTERM)\nsys.exit(status)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=30,
                          env=dict(os.environ, PYTHONPATH=SCRIPTS))
    assert done.returncode == 3 and done.stderr == ""
