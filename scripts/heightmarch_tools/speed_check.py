"""Speed of two builds judged on a noisy machine: both heightmarch-bench binaries run in
alternating rounds, and per benchmark the per-round ratios NEW/OLD of rays/s judged.
scripts/regress, scripts/bisect and scripts/calibrate_regress use it.
"""
import argparse
import collections
import math
import os
import re
import subprocess
import sys
import time

from . import processes
from .benchmark_results import canonical, clock, load_benchmarks, seconds
from .cli import Parser
from .errors import Unusable
from .escape import terminal
from .revisions import duration
from .significance import bh_adjusted, signed_rank_below_zero
from .spreads import spread

MAX_ROUNDS = 1000
# The searches at the widest ISAs: scalar, which took two thirds of a round's time, is left to
# --filter, so that 20 rounds take about a minute of CPU (docs/regression-tracking.md).
DEFAULT_FILTER = "BM_Trace/heightfield:bricks/technique:(pom|relief|steep)/layers:32/isa:(avx2|avx512)/threads:1/"
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


class WideHelp(argparse.RawDescriptionHelpFormatter):
    """The docstring as written, and room for the default filter on one line."""

    def __init__(self, prog):
        super().__init__(prog, width=130)


def parser(doc, prog):
    """The command line of regress or bisect: usage errors one line (exit 2), --help the whole
    docstring with every default."""
    return Parser(prog=prog, description=doc, formatter_class=WideHelp)


def detector_options(parser):
    """The detector's options, shared by regress and bisect."""
    parser.add_argument("--runs", type=int, default=DEFAULT_ROUNDS, metavar="N",
                        help="rounds, each running both builds (1..%d; default %d)" % (MAX_ROUNDS, DEFAULT_ROUNDS))
    parser.add_argument("--filter", default=DEFAULT_FILTER, metavar="REGEX",
                        help="the benchmarks timed, a regular expression over heightmarch-bench's names "
                             "(default %s)" % DEFAULT_FILTER.replace("%", "%%"))
    parser.add_argument("--threshold", type=float, default=DEFAULT_THRESHOLD, metavar="X",
                        help="the slow-down (or speed-up) that counts, relative (default %g)" % DEFAULT_THRESHOLD)
    parser.add_argument("--fdr", type=float, default=DEFAULT_FDR, metavar="Q",
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


def check_filter(pattern):
    if not pattern:
        raise Unusable("--filter is empty")
    try:
        re.compile(pattern)
    except re.error as e:
        raise Unusable("--filter %s is not a regular expression: %s" % (pattern, e))


def check_benchmarks(binary, flags, which):
    """Unusable unless binary accepts the flags and its filter names at least one benchmark."""
    result = processes.run([binary, "--benchmark_list_tests=true"] + flags, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True)
    if result.returncode != 0:
        first = (result.stderr.strip().splitlines() or ["exit %d" % result.returncode])[0]
        raise Unusable("%s refuses the benchmark flags: %s" % (os.path.basename(binary), first))
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
            for field in times:
                times[field].append(seconds(b, field))
    return out


def load_average():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def to_stderr(line):
    """A progress line (it may quote a commit's subject)."""
    print(terminal(line), file=sys.stderr, flush=True)


def interleaved_rounds(sides, rounds, work, progress=to_stderr, round_seconds=None):
    """Runs sides["old"] and sides["new"] (each a command line) in rounds, old first in odd rounds
    and new first in even ones (A B B A ...: a drift of the machine's speed over a round pair hits
    both sides alike). Per round: {"old": {name: timings}, "new": {...}, "load": 1-minute load
    average at its start}. progress gets a line per round with the time left: from the rounds so
    far, before the first from round_seconds (a past run's) where given."""
    out = []
    start = time.monotonic()
    for i in range(1, rounds + 1):
        per_round = (time.monotonic() - start) / (i - 1) if i > 1 else round_seconds
        progress("round %d/%d (load %.1f%s)" % (i, rounds, load_average(), ", about %s left" % duration(
            per_round * (rounds - i + 1)) if per_round else ""))
        result = {"load": load_average()}
        for side in ("old", "new") if i % 2 else ("new", "old"):
            path = os.path.join(work, "%s-%d.json" % (side, i))
            with open(path, "w") as f:
                run = processes.run(sides[side] + ["--benchmark_format=json"], stdout=f, stderr=subprocess.PIPE, text=True)
            if run.returncode != 0:
                raise Unusable("%s exited %d: %s" % (sides[side][0], run.returncode,
                                                     (run.stderr.strip().splitlines() or ["no message"])[-1]))
            result[side] = timings(path)
        out.append(result)
    return out


SLOW_MODE = 0.15  # the slow mode is 30-40% above the fast one, the changes to find below 10%


Verdict = collections.namedtuple("Verdict", "pair speed q spread improved regressed")


def judge(rounds, pairs, threshold, fdr):
    """[Verdict(pair, speed NEW/OLD, q-value of "slower", (median, min, max) of the per-round
    ratios, improved, regressed)].
    Per round, each side's fastest repetition on the pair's clock: on this shared VM a 1-thread
    trace's CPU time has two modes (its core to itself; sharing it with the host or a sibling
    thread, ~30-40% more) whose mix changes from moment to moment, and the fastest of a round's
    repetitions is the trace's own cost unless the whole round ran in the slow mode. Such a round
    (either side's fastest more than SLOW_MODE above that side's fastest over all rounds) is set
    aside (unless fewer than 2 rounds would remain): one of them among 10 rounds was enough to
    hide an 8% slow-down. The per-round ratios of the others are paired by round (both sides ran
    within seconds of each other); the speed is their median, Wilcoxon's signed-rank test says
    whether they lie below 1, Benjamini-Hochberg over the pairs at level fdr keeps the chance of
    any false flag at most fdr; a regression is significant and slower by more than threshold. An
    improvement is the same the other way (its own tests and correction)."""
    measured = []
    for new, old in pairs:
        c = clock(new)
        fastest = [(min(r["old"][old][c]), min(r["new"][new][c])) for r in rounds if old in r["old"] and new in r["new"]]
        floor = [min(side) for side in zip(*fastest)]
        kept = [(o, n) for o, n in fastest if o <= floor[0] * (1 + SLOW_MODE) and n <= floor[1] * (1 + SLOW_MODE)]
        logs = [math.log(o / n) for o, n in (kept if len(kept) >= 2 else fastest)]
        measured.append(((new, old), spread([math.exp(x) for x in logs]), signed_rank_below_zero(logs),
                         signed_rank_below_zero([-x for x in logs])))
    slower = bh_adjusted([m[2] for m in measured])
    faster = bh_adjusted([m[3] for m in measured])
    return [Verdict(pair, s[0], q, s, q_faster <= fdr and s[0] > 1 + threshold, q <= fdr and s[0] < 1 - threshold)
            for (pair, s, _, _), q, q_faster in zip(measured, slower, faster)]


def shared_pairs(rounds):
    """(name, name) of every benchmark both sides ran in every round."""
    return [(n, n) for n in sorted(set.intersection(*[set(r[side]) for r in rounds for side in ("old", "new")]))]


def verdict_lines(verdicts):
    """The table regress and bisect print: per benchmark the speed ratio NEW/OLD, its q-value and the
    spread of the per-round ratios."""
    lines = ["%-90s %7s %8s %17s" % ("benchmark (speed NEW/OLD: median of the per-round ratios)", "speed", "q-value",
                                     "(min-max)")]
    for v in verdicts:
        lines.append("%-90s %7.3f %8.4f   (%.3f-%.3f) %s" % (v.pair[0][:90], v.speed, v.q, v.spread[1], v.spread[2],
                                                             "REGRESSION" if v.regressed else "improved" if v.improved else ""))
    return lines


def verdict(verdicts, threshold):
    """The closing line and exit code: (`REGRESSION: ...`, 1), (`improvement: ...`, 0) or
    (`no regression ...`, 0)."""
    regressed = [v for v in verdicts if v.regressed]
    improved = [v for v in verdicts if v.improved]
    if regressed:
        worst = min(regressed, key=lambda v: v.speed)
        return ("REGRESSION: %d of %d benchmarks slower by more than %g%% (slowest: %s at %.3f of OLD's speed)"
                % (len(regressed), len(verdicts), 100 * threshold, worst.pair[0], worst.speed), 1)
    if improved:
        best = max(improved, key=lambda v: v.speed)
        return ("improvement: %d of %d benchmarks faster by more than %g%%, none slower (fastest: %s at %.3f of OLD's "
                "speed)" % (len(improved), len(verdicts), 100 * threshold, best.pair[0], best.speed), 0)
    return "no regression: none of %d benchmarks slower by more than %g%%" % (len(verdicts), 100 * threshold), 0
