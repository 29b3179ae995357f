#!/usr/bin/python3
"""A hostile set run from outside, as a user or an attacker meets the tool: issue 32's six classes
against `heightmarch report`, `recommend`, `glsl`, `suite`, the Python package's commands and the
scripts, each case a command with the outcome it must have.

Usage: hostile_inputs.py BUILD_DIR [-k SUBSTRING] [-v]

Every case runs in a session of its own under a time limit and must:
- exit with its expected status (a hang is a failure: the case is killed at its limit);
- print no traceback and no byte a terminal acts on (ESC, other controls but tab and newline);
- when it fails, say so in one line on stderr (one ended by a signal may print nothing);
- leave no process of its session running (a worker, a report, a child of a script);
- write nothing outside the paths it may write (the sandbox is compared before and after: a file
  made, changed or removed elsewhere fails it) and leave no temporary file (.tmp-*) anywhere;
- pass its own check, where it has one (a history that kept its rows, a CSV with no formula).

A case that depends on what the machine lacks (no tmpfs mount, no EGL) says so and is skipped.
The base run is one quick suite (POM, the matrix, no GLSL: about 2 s of CPU); the cases cost
about 40 s of CPU in all (most of it the report's Python start-up, about 0.6 s each).
"""
import argparse
import json
import os
import resource
import shutil
import signal
import stat
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
PYTHON = "/usr/bin/python3"


def acts_on_terminal(c):
    """A character a terminal obeys or cannot show: C0 controls (but tab and newline), DEL, C1
    controls, bidirectional overrides, a byte of no UTF-8 character."""
    code = ord(c)
    return ((code < 32 and c not in "\t\n") or 0x7F <= code < 0xA0 or 0x202A <= code <= 0x202E
            or 0x2066 <= code <= 0x2069 or 0xDC80 <= code <= 0xDCFF)


class Skip(Exception):
    pass


class Sandbox:
    """A temporary tree the cases work in, with `outside/` holding files no case may touch."""

    def __init__(self):
        self.root = tempfile.mkdtemp(prefix="hostile-")
        self.outside = self.path("outside")
        os.makedirs(self.outside)
        with open(os.path.join(self.outside, "victim.txt"), "w") as f:
            f.write("keep me\n")
        self.mounts, self.holders = [], []  # tmpfs mounted, processes started by the cases' setup

    def close(self):
        for p in self.holders:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
        for m in self.mounts:
            subprocess.run(["umount", m])
        shutil.rmtree(self.root, ignore_errors=True)

    def path(self, *parts):
        return os.path.join(self.root, *parts)

    def snapshot(self):
        out = {}
        for top, dirs, files in os.walk(self.root):
            for name in dirs + files:
                p = os.path.join(top, name)
                try:
                    st = os.lstat(p)
                except FileNotFoundError:
                    continue
                kind = stat.S_IFMT(st.st_mode)  # a directory by its existence: its entries are the files
                out[p] = (kind, st.st_ino) if kind == stat.S_IFDIR else (kind, st.st_size, st.st_mtime_ns, st.st_ino)
        return out


def session_processes(sid):
    """The pids of live processes (not zombies) of a session."""
    pids = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % entry) as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[3]) == sid and fields[0] != "Z":  # fields: state, ppid, pgrp, session
            pids.append(int(entry))
    return pids


class Result:
    def __init__(self, rc, out, err, seconds, leftover):
        self.rc, self.out, self.err, self.seconds, self.leftover = rc, out, err, seconds, leftover


def run(argv, env=None, cwd=None, timeout=20, signals=(), stdin=subprocess.DEVNULL, stdout=subprocess.PIPE):
    """Runs argv in a session of its own; signals: [(after seconds or a callable that waits, signal)]
    sent to it (the process, not its group: as a user's kill PID). Kills the session at the timeout."""
    environment = dict(os.environ, **(env or {}))
    for k, v in (env or {}).items():
        if v is None:
            del environment[k]
    start = time.monotonic()
    p = subprocess.Popen(argv, env=environment, cwd=cwd, stdin=stdin, stdout=stdout, stderr=subprocess.PIPE,
                         start_new_session=True)
    timed_out = False
    try:
        for when, signum in signals:
            if callable(when):
                when(p)
            else:
                time.sleep(max(0.0, start + when - time.monotonic()))
            if p.poll() is None:
                p.send_signal(signum)
        out, err = p.communicate(timeout=max(0.1, start + timeout - time.monotonic()))
    except subprocess.TimeoutExpired:
        timed_out = True
        os.killpg(p.pid, signal.SIGKILL)
        out, err = p.communicate()
    seconds = time.monotonic() - start
    # the session's processes still running a moment after it exited (a parent-death signal takes a
    # moment to land)
    deadline = time.monotonic() + 3.0
    leftover = session_processes(p.pid)
    while leftover and time.monotonic() < deadline:
        time.sleep(0.05)
        leftover = session_processes(p.pid)
    for pid in leftover:
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
    return Result(None if timed_out else p.returncode, out or b"", err or b"", seconds, leftover)


class Case:
    def __init__(self, cls, name, argv, expect, *, env=None, cwd=None, timeout=20, writes=(), check=None, setup=None,
                 signals=(), stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, owner=None, text=None):
        self.cls, self.name, self.argv, self.expect = cls, name, argv, expect
        self.env, self.cwd, self.timeout, self.writes, self.check, self.setup = env, cwd, timeout, writes, check, setup
        self.signals, self.stdin, self.stdout, self.owner, self.text = signals, stdin, stdout, owner, text

    def outcome(self, sandbox):
        """None where it passed, else why not."""
        before = sandbox.snapshot()
        r = run(self.argv() if callable(self.argv) else self.argv, self.env, self.cwd, self.timeout, self.signals,
                self.stdin() if callable(self.stdin) else self.stdin, self.stdout)
        shown = (r.out + r.err).decode("utf-8", "replace")
        problems = []
        if r.rc is None:
            problems.append("still running after %d s (killed)" % self.timeout)
        elif r.rc not in (self.expect if isinstance(self.expect, tuple) else (self.expect,)):
            problems.append("exit %d, not %s" % (r.rc, self.expect))
        if b"Traceback" in r.out + r.err:
            problems.append("a traceback")
        bad = sorted({"U+%04X" % ord(c) for c in (r.out + r.err).decode("utf-8", "surrogateescape") if acts_on_terminal(c)})
        if bad:
            problems.append("printed what a terminal acts on: %s" % ", ".join(bad))
        # an error is one line; a process ended by a signal (by dying of it, or exiting 128+N after
        # its one line) may have printed its progress before
        if r.rc is not None and 0 < r.rc < 128 and len(r.err.decode("utf-8", "replace").strip().splitlines()) != 1:
            problems.append("%d lines on stderr, not one" % len(r.err.decode("utf-8", "replace").strip().splitlines()))
        if r.leftover:
            problems.append("left %d process(es) running: %s" % (len(r.leftover), ", ".join(map(str, r.leftover))))
        if self.text is not None and self.text not in shown:
            problems.append("does not say %r" % self.text)
        after = sandbox.snapshot()
        allowed = [os.path.join(sandbox.root, w) for w in self.writes]
        changed = sorted(p for p in set(before) | set(after) if before.get(p) != after.get(p)
                         and not any(p == a or p.startswith(a.rstrip("/") + "/") for a in allowed))
        if changed:
            problems.append("wrote outside what it may write: %s" % ", ".join(os.path.relpath(p, sandbox.root)
                                                                              for p in changed[:5]))
        temporaries = [p for p in after if os.path.basename(p).startswith(".tmp-")]
        if temporaries:
            problems.append("left temporaries: %s" % ", ".join(os.path.relpath(p, sandbox.root) for p in temporaries[:3]))
        if self.check and not problems:
            why = self.check(r)
            if why:
                problems.append(why)
        if problems:
            return "; ".join(problems) + "\n      output: " + shown.strip().replace("\n", "\n              ")[:1500]
        return None


def cpu_seconds():
    """The CPU time of this process's finished children so far (the cases', and the base run's)."""
    cpu = resource.getrusage(resource.RUSAGE_CHILDREN)
    return cpu.ru_utime + cpu.ru_stime


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build")
    parser.add_argument("-k", default="", help="only the cases whose class/name holds this")
    parser.add_argument("-v", action="store_true", help="name every case as it passes")
    args = parser.parse_args()
    sys.path.insert(0, os.path.join(ROOT, "scripts"))  # heightmarch_tools, for the history's columns
    import hostile_cases
    sandbox = Sandbox()
    try:
        cases = hostile_cases.cases(os.path.abspath(args.build), sandbox)
        failed, skipped, passed = [], [], 0
        spent = cpu_seconds()
        for case in cases:
            label = "%s/%s" % (case.cls, case.name)
            if args.k not in label:
                continue
            try:
                if case.setup:
                    case.setup()
                why = case.outcome(sandbox)
            except Skip as e:
                skipped.append("%s: %s" % (label, e))
                continue
            if why:
                failed.append((label, case.owner, why))
                print("FAIL %s: %s" % (label, why))
            else:
                passed += 1
                if args.v:
                    print("ok   %s (%.1f s CPU)" % (label, cpu_seconds() - spent))
            spent = cpu_seconds()
        for s in skipped:
            print("skip " + s)
        print("%d passed, %d failed, %d skipped; %.1f s of CPU in the cases' processes" % (
            passed, len(failed), len(skipped), cpu_seconds()))
        for label, owner, _ in failed:
            if owner:
                print("  %s belongs to %s's area" % (label, owner))
        return 1 if failed else 0
    finally:
        sandbox.close()


if __name__ == "__main__":
    sys.exit(main())
