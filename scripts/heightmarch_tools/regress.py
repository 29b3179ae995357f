"""Tells whether the current build is slower than revision REV, on a noisy machine.

Usage: scripts/regress REV [--runs N] [--filter REGEX] [--threshold X] [--fdr Q] [--build DIR] [-- BENCHMARK FLAGS]

REV's heightmarch-bench is built once with the current build's settings (build type, compilers,
flags) in a worktree of its own and kept under DIR/regress-cache, keyed by the commit and those
settings: a later run against the same REV starts timing at once (ccache, where installed, speeds
up a first build). The current build, DIR (default: build/ of the repository of the current
directory), is brought up to date first. Both binaries then run in alternating rounds (A B B A
...) and each benchmark is judged on its per-round ratios NEW/OLD by regress's detector
(heightmarch_tools/speed_check.py: each round's fastest repetition on CPU time at 1 thread, rounds run
wholly in the machine's slow mode set aside, Wilcoxon's signed-rank test over the rounds,
Benjamini-Hochberg over the benchmarks at --fdr). A regression is significant and slower by more
than --threshold. The defaults are calibrated (docs/regression-tracking.md).

It says what it is doing and about how long it has left on stderr, prints a table of the
benchmarks, and ends with one verdict line: `no regression: ...`, `REGRESSION: ...` or
`improvement: ...`.

Its arguments are checked before anything is built (REV a commit, N in 1..1000, the threshold in
(0, 1), the filter a regular expression that names at least one benchmark of the current build,
the extra flags accepted by it). On SIGINT, SIGTERM or SIGHUP it ends its children (their whole
process groups), removes its worktree and temporary files, and exits 128 + the signal's number.
Exits 0 with no regression (or an improvement), 1 with a regression, 2 on unusable input.
"""
import os
import sys
import tempfile
import time

from .cli import Interrupted
from .errors import Unusable
from .revisions import BuildCache, build, build_settings, describe, duration, repository, resolve
from .speed_check import (check_benchmarks, detector_options, interleaved_rounds, judge, parse, parser, shared_pairs,
                          to_stderr, verdict, verdict_lines)


def progress(line):
    to_stderr("regress: " + line)


def arguments(argv, root):
    command = parser(__doc__, "regress")
    command.add_argument("rev", help="the revision to compare the current build against (OLD)")
    detector_options(command)
    command.add_argument("--build", default=os.path.join(root, "build"), metavar="DIR",
                         help="the current build directory (NEW; default: %s)" % os.path.join(root, "build"))
    return parse(command, argv)


def regress(argv):
    root = repository(os.getcwd())
    args = arguments(argv, root)
    commit = resolve(root, args.rev)
    new = os.path.join(args.build, "heightmarch-bench")
    if not os.path.exists(new):
        raise Unusable("%s holds no heightmarch-bench: build it first (scripts/setup)" % args.build)
    check_benchmarks(new, args.flags, "the current build")  # before anything is built
    start = time.monotonic()
    cache = BuildCache(args.build, build_settings(args.build))
    cache.checked_dir()  # a cache that is a link is refused before anything is built
    try:
        progress("bringing %s up to date" % args.build)
        with cache.current_build_log() as log:  # kept: a failure names it
            build(root, args.build, log)
        old = cache.build(root, commit, progress)
        check_benchmarks(old, args.flags, "REV %s" % args.rev)
        per_round = cache.timings().get("round_seconds")
        progress("timing OLD %s against NEW %s: %d rounds%s" % (
            describe(root, commit), args.build, args.runs,
            ", about %s (the last run's rounds took %s each)" % (duration(per_round * args.runs), duration(per_round))
            if per_round else ""))
        rounds_start = time.monotonic()
        with tempfile.TemporaryDirectory(prefix="regress-") as work:
            rounds = interleaved_rounds({"old": [old] + args.flags, "new": [new] + args.flags}, args.runs, work,
                                        progress=progress, round_seconds=per_round)
    except Interrupted:
        progress("stopping: its children ended, its worktree and temporary files removed; the build logs stay in %s"
                 % cache.dir)
        raise
    cache.record(round_seconds=(time.monotonic() - rounds_start) / args.runs)
    pairs = shared_pairs(rounds)
    if not pairs:
        raise Unusable("no benchmark of the filter ran in both builds")
    verdicts = judge(rounds, pairs, args.threshold, args.fdr)
    print("\n".join(verdict_lines(verdicts)))
    line, code = verdict(verdicts, args.threshold)
    progress("done in %s" % duration(time.monotonic() - start))
    print(line)
    return code


def main(argv):
    if not argv:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    return regress(argv)
