"""Finds the first commit between GOOD and BAD whose benchmarks are slower than GOOD's.

Usage: scripts/bisect GOOD BAD [--runs N] [--filter REGEX] [--threshold X] [--fdr Q] [--build DIR] [-- BENCHMARK FLAGS]

The repository is the one of the current directory; its checkout is never touched. GOOD's
heightmarch-bench comes from scripts/regress's build cache (DIR/regress-cache, built there once
with DIR's settings: build type, compilers, flags). In a worktree of BAD, `git bisect run` checks
out each commit it picks, takes its build from the cache or builds it there (incrementally, and
stores it), and times it against GOOD's in regress's interleaved rounds, judged by regress's
detector with the same options and defaults: a commit with any benchmark of the filter judged
slower is bad; one that does not build is skipped. BAD is timed first: when it is not slower
there is nothing to find. Progress and time estimates go to stderr; it prints the first slower
commit with its figures and those of its parent where it was timed, and ends with one verdict
line: `REGRESSION: first slower commit ...` or `no regression: BAD is not slower than GOOD ...`.

Its arguments are checked before anything is built (GOOD and BAD commits, GOOD an ancestor of BAD,
the detector's options as in regress); the filter must name a benchmark of both builds. On
SIGINT, SIGTERM or SIGHUP it ends its children (their whole process groups, `git bisect run`'s
steps and their builds and benchmarks too), removes its worktree and temporary files, and exits
128 + the signal's number. Exits 0 when the commit is found, 1 when BAD is not slower than GOOD,
2 on unusable input.
"""
import json
import os
import subprocess
import sys
import tempfile

from .cli import Interrupted
from .errors import Unusable
from .escape import terminal
from .processes import run
from .revisions import BuildCache, Worktree, build_settings, describe, git, repository, resolve
from .speed_check import (check_benchmarks, detector_options, interleaved_rounds, judge, parse, parser, shared_pairs,
                          to_stderr, verdict_lines)

SKIP = 125  # git bisect run: this commit cannot be tested
SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.realpath(__file__))), "bisect")  # what git bisect runs


def progress(line):
    to_stderr("bisect: " + line)


def arguments(argv, root):
    command = parser(__doc__, "bisect")
    command.add_argument("good", help="a commit that is not slower (an ancestor of BAD)")
    command.add_argument("bad", help="a commit that is slower than GOOD")
    detector_options(command)
    command.add_argument("--build", metavar="DIR",
                         help="the build directory whose settings the builds take and under which they are cached "
                              "(default: %s, made where missing)" % os.path.join(root, "build"))
    args = parse(command, argv)
    if args.build is not None and not os.path.isdir(args.build):  # a path given is never made in its place
        raise Unusable("--build %s: no such directory" % terminal(args.build))
    args.build = args.build or os.path.join(root, "build")
    return args


def time_against(good_binary, binary, args, work, cache):
    """Times binary against good_binary: (slower, verdict lines)."""
    rounds = interleaved_rounds({"old": [good_binary] + args.flags, "new": [binary] + args.flags}, args.runs, work,
                                progress=progress, round_seconds=cache.timings().get("round_seconds"))
    pairs = shared_pairs(rounds)
    if not pairs:
        raise Unusable("no benchmark of the filter ran in both builds")
    verdicts = judge(rounds, pairs, args.threshold, args.fdr)
    return any(v.regressed for v in verdicts), verdict_lines(verdicts)


def step(argv):
    """One `git bisect run` step (the hidden --step mode): exit 0 when the checked-out commit is not
    slower than GOOD, 1 when it is, 125 when it does not build; its figures go to STEPS."""
    good_binary, tree, build_dir, steps = argv[:4]
    root = repository(tree)
    args = arguments(argv[4:], root)
    cache = BuildCache(args.build, build_settings(args.build))
    commit = git(tree, "rev-parse", "HEAD")
    progress("timing %s" % describe(tree, commit))
    try:
        binary = cache.lookup(commit, progress) or cache.build_in(tree, build_dir, commit, progress)
        slower, lines = time_against(good_binary, binary, args, os.path.dirname(steps), cache)
    except Unusable as e:
        progress("skipping %s: %s" % (commit[:12], e))
        return SKIP
    with open(steps, "a") as f:
        f.write(json.dumps({"commit": commit, "slower": slower, "lines": lines}) + "\n")
    return 1 if slower else 0


def bisect(argv):
    root = repository(os.getcwd())
    args = arguments(argv, root)
    good, bad = resolve(root, args.good), resolve(root, args.bad)
    if good == bad or subprocess.run(["git", "-C", root, "merge-base", "--is-ancestor", good, bad]).returncode != 0:
        raise Unusable("GOOD %s is not an ancestor of BAD %s" % (args.good, args.bad))
    cache = BuildCache(args.build, build_settings(args.build))
    cache.checked_dir()  # a cache that is a link is refused before anything is built
    try:
        return bisect_with(root, args, argv, good, bad, cache)
    except Interrupted:
        progress("stopping: its children ended, its worktree and temporary files removed; the build logs stay in %s"
                 % cache.dir)
        raise


def bisect_with(root, args, argv, good, bad, cache):
    """bisect() once the arguments are checked."""
    good_binary = cache.build(root, good, progress)
    check_benchmarks(good_binary, args.flags, "GOOD")
    with tempfile.TemporaryDirectory(prefix="heightmarch-bisect-") as work, Worktree(root, bad) as bad_tree:
        steps, bad_build = os.path.join(work, "steps.jsonl"), os.path.join(bad_tree.work, "build")
        bad_binary = cache.lookup(bad, progress)
        if not bad_binary:
            progress("building BAD %s in its worktree (%s; log: %s)" % (describe(root, bad), cache.estimate(), cache.log(bad)))
            bad_binary = cache.build_in(bad_tree.tree, bad_build, bad, progress)
        check_benchmarks(bad_binary, args.flags, "BAD")
        progress("timing BAD %s against GOOD %s" % (describe(root, bad), describe(root, good)))
        slower, lines = time_against(good_binary, bad_binary, args, work, cache)
        if not slower:
            print("\n".join(lines))
            print(terminal("no regression: BAD %s is not slower than GOOD %s by the detector: nothing to find"
                           % (args.bad, args.good)))
            return 1
        count = int(git(root, "rev-list", "--count", "%s..%s" % (good, bad)))
        progress("bisecting %d commits: about %d more to time" % (count, max(0, count.bit_length() - 1)))
        git(bad_tree.tree, "bisect", "start", bad, good)
        result = run(["git", "-C", bad_tree.tree, "bisect", "run", sys.executable, SCRIPT,
                      "--step", good_binary, bad_tree.tree, bad_build, steps, "--build", args.build] + argv,
                     stdout=subprocess.PIPE, text=True)  # the steps' progress goes to stderr
        first = git(bad_tree.tree, "rev-parse", "refs/bisect/bad")
        git(bad_tree.tree, "bisect", "reset")
        if result.returncode != 0 or "is the first bad commit" not in result.stdout:
            raise Unusable("git bisect run found no first slower commit: %s"
                           % (result.stdout.strip().splitlines() or ["no output"])[-1])
        timed = {}
        with open(steps) as f:
            for line in f:
                s = json.loads(line)
                timed[s["commit"]] = s
    timed.setdefault(bad, {"commit": bad, "slower": True, "lines": lines})
    parent = git(root, "rev-parse", first + "^")
    print(terminal("bisect: first slower commit: %s" % git(root, "log", "-1", "--format=%H %s", first)))
    print("\n".join(timed[first]["lines"]))
    print(terminal("\nits parent: %s" % describe(root, parent)))
    print("\n".join(timed[parent]["lines"]) if parent in timed else
          "GOOD itself" if parent == good else "not timed (git bisect inferred it)")
    print("\nsteps: %s" % ", ".join("%s %s" % (c[:12], "slower" if s["slower"] else "not slower") for c, s in timed.items()))
    print(terminal("REGRESSION: first slower commit %s" % describe(root, first)))
    return 0


def main(argv):
    if argv[:1] == ["--step"]:
        return step(argv[1:])
    if not argv:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    return bisect(argv)
