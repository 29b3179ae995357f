"""Speed of two builds judged on a noisy machine: a revision's heightmarch-bench built in a
separate worktree, both binaries run in alternating rounds, and per benchmark the per-round
ratios NEW/OLD of rays/s judged. scripts/regress, scripts/bisect and scripts/calibrate_regress use it.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

from benchmark_results import Unusable, canonical, load_benchmarks, seconds, spread

MAX_ROUNDS = 1000
DEFAULT_FILTER = "BM_Trace/heightfield:bricks/technique:(pom|relief|steep)/layers:32/isa:(scalar|avx2|avx512)/threads:1/"
DEFAULT_FLAGS = ["--hm_size=512", "--hm_heightfields=bricks", "--hm_min_time=0.1"]
DEFAULT_ROUNDS, DEFAULT_THRESHOLD = 5, 0.05


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


def parse(parser, argv):
    """Parses argv (benchmark flags after "--") and checks the detector's options."""
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    args = parser.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    args.flags = ["--benchmark_filter=" + args.filter] + DEFAULT_FLAGS + extra
    if not 1 <= args.runs <= MAX_ROUNDS:
        raise Unusable("--runs %d is not in 1..%d" % (args.runs, MAX_ROUNDS))
    if not 0 < args.threshold < 1:
        raise Unusable("--threshold %g is not in (0, 1)" % args.threshold)
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


def round_ratios(rounds, pairs, clock="cpu_time"):
    """Per pair (new name, old name): the per-round speed ratios NEW/OLD, from each side's fastest
    repetition of the round on the clock. Rounds where either side lacks the benchmark are skipped."""
    ratios = {}
    for r in rounds:
        for new, old in pairs:
            if new in r["new"] and old in r["old"]:
                ratios.setdefault((new, old), []).append(min(r["old"][old][clock]) / min(r["new"][new][clock]))
    return ratios


def shared_pairs(rounds):
    """(name, name) of every benchmark both sides ran in every round."""
    return [(n, n) for n in sorted(set.intersection(*[set(r[side]) for r in rounds for side in ("old", "new")]))]


def verdict_lines(verdicts):
    """The table regress and bisect print: per benchmark the median NEW/OLD ratio and its spread."""
    lines = ["%-95s %7s %15s" % ("benchmark (rays/s NEW/OLD)", "median", "spread")]
    for (name, _), s, regressed in verdicts:
        lines.append("%-95s %7.3f %7.3f..%.3f %s" % (name[:95], s[0], s[1], s[2], "REGRESSION" if regressed else ""))
    return lines


def judge(ratios, threshold):
    """[(pair, (median, min, max) of the ratios, regressed)]: a regression is a median below
    1 - threshold with the whole spread below 1."""
    out = []
    for pair in sorted(ratios):
        s = spread(ratios[pair])
        out.append((pair, s, s[0] < 1 - threshold and s[2] < 1))
    return out
