"""Speed of two builds judged on a noisy machine: a revision's heightmarch-bench built in a
separate worktree, both binaries run in alternating rounds, and per benchmark the per-round
ratios NEW/OLD of rays/s judged. scripts/regress, scripts/bisect and scripts/calibrate_regress use it.
"""
import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

from .benchmark_results import canonical, load_benchmarks, seconds
from .errors import Unusable
from .significance import bh_adjusted, signed_rank_below_zero
from .spreads import spread

MAX_ROUNDS = 1000
DEFAULT_FILTER = "BM_Trace/heightfield:bricks/technique:(pom|relief|steep)/layers:32/isa:(scalar|avx2|avx512)/threads:1/"
# Calibrated on this project's 2-core VM (docs/regression-tracking.md): 20 rounds of 10
# repetitions find a 4-5% slow-down in ~95% of runs and flag ~6% of runs of 9 identical benchmarks.
DEFAULT_ROUNDS, DEFAULT_THRESHOLD, DEFAULT_FDR = 20, 0.01, 0.05
DEFAULT_MIN_TIME, DEFAULT_REPETITIONS = 0.01, 10  # per benchmark and round: many short repetitions


def timing_flags(min_time=DEFAULT_MIN_TIME, repetitions=DEFAULT_REPETITIONS):
    """heightmarch-bench's flags for one side of a round: 1 thread's trace of a 512x512 view of
    bricks, each repetition of each benchmark at a random place in the run (no benchmark owes its
    speed to where it sits in the run: a first calibration without that saw 101 layers 14% slower
    than 100)."""
    return ["--hm_size=512", "--hm_heightfields=bricks", "--hm_min_time=%g" % min_time,
            "--benchmark_repetitions=%d" % repetitions, "--benchmark_enable_random_interleaving=true"]


class Parser(argparse.ArgumentParser):
    """Usage errors as Unusable: one line, exit 2."""

    def error(self, message):
        raise Unusable(message)


def detector_options(parser):
    """The detector's options, shared by regress and bisect."""
    parser.add_argument("--runs", type=int, default=DEFAULT_ROUNDS, help="rounds (default %d)" % DEFAULT_ROUNDS)
    parser.add_argument("--filter", default=DEFAULT_FILTER, help="benchmark regular expression")
    parser.add_argument("--threshold", type=float, default=DEFAULT_THRESHOLD,
                        help="slow-down that counts (default %g)" % DEFAULT_THRESHOLD)
    parser.add_argument("--fdr", type=float, default=DEFAULT_FDR,
                        help="Benjamini-Hochberg level over the benchmarks (default %g)" % DEFAULT_FDR)


def parse(parser, argv):
    """Parses argv (benchmark flags after "--") and checks the detector's options."""
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    args = parser.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    args.flags = ["--benchmark_filter=" + args.filter] + timing_flags() + extra
    if not 1 <= args.runs <= MAX_ROUNDS:
        raise Unusable("--runs %d is not in 1..%d" % (args.runs, MAX_ROUNDS))
    for option, value in (("--threshold", args.threshold), ("--fdr", args.fdr)):
        if not 0 < value < 1:
            raise Unusable("%s %g is not in (0, 1)" % (option, value))
    check_filter(args.filter)
    return args


def git(root, *args):
    return subprocess.run(["git", "-C", root] + list(args), check=True, capture_output=True, text=True).stdout.strip()


def resolve(root, rev):
    """The full commit id of rev, or Unusable."""
    try:
        return git(root, "rev-parse", "--verify", "--quiet", rev + "^{commit}")
    except subprocess.CalledProcessError:
        raise Unusable("unknown revision %s" % rev)


def check_filter(pattern):
    if not pattern:
        raise Unusable("--filter is empty")
    try:
        re.compile(pattern)
    except re.error as e:
        raise Unusable("--filter %s is not a regular expression: %s" % (pattern, e))


def build(source, build_dir, log, configure=True):
    """Builds heightmarch-bench of the tree at source into build_dir (configured first as Release
    without tests, unless it is a build directory of the user's); its path. Output goes to log."""
    commands = [["cmake", "-S", source, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release", "-DHEIGHTMARCH_BUILD_TESTS=OFF"]] if configure else []
    commands.append(["cmake", "--build", build_dir, "-j", str(os.cpu_count() or 1), "--target", "heightmarch-bench"])
    for cmd in commands:
        if subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT).returncode != 0:
            raise Unusable("building %s failed (%s)" % (source, log.name))
    return os.path.join(build_dir, "heightmarch-bench")


class Worktree:
    """A detached worktree of commit under a temporary directory, removed on exit."""

    def __init__(self, root, commit):
        self.root, self.commit = root, commit

    def __enter__(self):
        self.work = tempfile.mkdtemp(prefix="heightmarch-speed-")
        self.tree = os.path.join(self.work, "tree")
        git(self.root, "worktree", "add", "--detach", self.tree, self.commit)
        return self

    def __exit__(self, *exc):
        subprocess.run(["git", "-C", self.root, "worktree", "remove", "--force", self.tree], capture_output=True)
        shutil.rmtree(self.work, ignore_errors=True)


def check_benchmarks(binary, flags, which):
    """Unusable unless binary accepts the flags and its filter names at least one benchmark."""
    result = subprocess.run([binary, "--benchmark_list_tests=true"] + flags, capture_output=True, text=True)
    if result.returncode != 0:
        raise Unusable("%s refuses the benchmark flags: %s" % (os.path.basename(binary),
                                                                (result.stderr.strip().splitlines() or ["exit %d" % result.returncode])[0]))
    if not result.stdout.split():
        pattern = next(f for f in flags if f.startswith("--benchmark_filter="))
        raise Unusable("--filter %s names no benchmark of %s" % (pattern.split("=", 1)[1], which))


def short(name):
    """A name as both builds share it: both ran at the same sizes, and older revisions name
    min_time: instead of view:/depth_map:."""
    return re.sub(r"/(view|depth_map):[^/]*", "", canonical(name))


def timings(path):
    """{name: {"real_time": [s], "cpu_time": [s]}} of a heightmarch-bench JSON output, one value per
    repetition: a trace's wall time, and the CPU time the process spent on it."""
    out = {}
    for b in load_benchmarks(path)["benchmarks"]:
        if b.get("run_type", "iteration") == "iteration" and not b.get("error_occurred"):
            times = out.setdefault(short(b.get("run_name", b["name"])), {"real_time": [], "cpu_time": []})
            for clock in times:
                times[clock].append(seconds(b, clock))
    return out


def load_average():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def interleaved_rounds(sides, rounds, work, progress=sys.stderr):
    """Runs sides["old"] and sides["new"] (each a command line) in rounds, old first in odd rounds
    and new first in even ones (A B B A ...: a drift of the machine's speed over a round pair hits
    both sides alike). Per round: {"old": {name: [rays/s]}, "new": {...}, "load": 1-minute load
    average at its start}, each side {name: timings}."""
    out = []
    for i in range(1, rounds + 1):
        result = {"load": load_average()}
        for side in ("old", "new") if i % 2 else ("new", "old"):
            print("round %d/%d, %s" % (i, rounds, side), file=progress)
            path = os.path.join(work, "%s-%d.json" % (side, i))
            with open(path, "w") as f:
                run = subprocess.run(sides[side] + ["--benchmark_format=json"], stdout=f, stderr=subprocess.PIPE, text=True)
            if run.returncode != 0:
                raise Unusable("%s exited %d: %s" % (sides[side][0], run.returncode,
                                                     (run.stderr.strip().splitlines() or ["no message"])[-1]))
            result[side] = timings(path)
        out.append(result)
    return out


def clock(name):
    """The clock a benchmark is judged on: CPU time at 1 thread, where waiting for a core shared
    with other processes does not count (heightmarch-bench runs a 1-thread trace on its main
    thread, so revisions that measured the thread's CPU time measured the same); wall time
    otherwise, since a slower parallel trace may spend no more CPU time."""
    return "cpu_time" if "/threads:1/" in name + "/" else "real_time"


SLOW_MODE = 0.15  # the slow mode is 30-40% above the fast one, the changes to find below 10%


def judge(rounds, pairs, threshold, fdr):
    """[(pair, speed NEW/OLD, q-value, (median, min, max) of the per-round ratios, regressed)].
    Per round, each side's fastest repetition on the pair's clock: on this shared VM a 1-thread
    trace's CPU time has two modes (its core to itself; sharing it with the host or a sibling
    thread, ~30-40% more) whose mix changes from moment to moment, and the fastest of a round's
    repetitions is the trace's own cost unless the whole round ran in the slow mode. Such a round
    (either side's fastest more than SLOW_MODE above that side's fastest over all rounds) is set
    aside (unless fewer than 2 rounds would remain): one of them among 10 rounds was enough to
    hide an 8% slow-down. The per-round ratios of the others are paired by round (both sides ran within seconds of each other); the speed is
    their median, Wilcoxon's signed-rank test says whether they lie below 1, Benjamini-Hochberg
    over the pairs at level fdr keeps the chance of any false flag at most fdr; a regression is
    significant and slower by more than threshold."""
    measured = []
    for new, old in pairs:
        c = clock(new)
        fastest = [(min(r["old"][old][c]), min(r["new"][new][c])) for r in rounds if old in r["old"] and new in r["new"]]
        floor = [min(side) for side in zip(*fastest)]
        kept = [(o, n) for o, n in fastest if o <= floor[0] * (1 + SLOW_MODE) and n <= floor[1] * (1 + SLOW_MODE)]
        ratios = [o / n for o, n in (kept if len(kept) >= 2 else fastest)]
        measured.append(((new, old), spread(ratios), signed_rank_below_zero([math.log(x) for x in ratios])))
    q = bh_adjusted([p for _, _, p in measured])
    return [(pair, s[0], qvalue, s, qvalue <= fdr and s[0] < 1 - threshold) for (pair, s, _), qvalue in zip(measured, q)]


def shared_pairs(rounds):
    """(name, name) of every benchmark both sides ran in every round."""
    return [(n, n) for n in sorted(set.intersection(*[set(r[side]) for r in rounds for side in ("old", "new")]))]


def verdict_lines(verdicts):
    """The table regress and bisect print: per benchmark the speed ratio NEW/OLD, its q-value and the
    spread of the per-round ratios."""
    lines = ["%-90s %7s %8s %17s" % ("benchmark (speed NEW/OLD: median of the per-round ratios)", "speed", "q-value",
                                     "(min-max)")]
    for (name, _), speed, q, s, regressed in verdicts:
        lines.append("%-90s %7.3f %8.4f   (%.3f-%.3f) %s" % (name[:90], speed, q, s[1], s[2],
                                                             "REGRESSION" if regressed else ""))
    return lines
