"""Compares two heightmarch Google Benchmark JSON runs: speed and error measures.

Usage: scripts/compare OLD.json NEW.json [--threshold 0.05] [--small-threshold X] [--fdr 0.05] [--force-speed]

- First lines: a WARNING for each of CPU model, core count, best ISA, compiler, view size,
  depth-map size, build type and Google Benchmark's library build type that differs between the
  runs' contexts ("unknown" where a file lacks the key).
- Benchmarks are matched by name, aggregates (_mean, _median, ...) ignored. Older names still
  match (said once): /min_time: is dropped, and where only one run's names carry view: and
  depth_map: the other's sizes come from its context. Benchmarks of one run only are listed;
  none shared is unusable input, and the message says when only sizes (or other fields) differ.
- Speed, on log times (CPU time at 1 thread, where waiting for a core does not count, else wall
  time; a suite's bench.json gives wall time for both), against the machine:
  - the controls, benchmarks whose speed no commit of heightmarch changes (BM_Calibration, a
    fixed loop; llvmpipe's BM_GLSL rows, unless their error measures changed: then the shader
    did), give the machine's shift between the runs (their median change, at least 3 of them);
    every other benchmark is judged against it (without controls: against OLD as it is);
  - the whole run: its median benchmark's change against OLD. Beyond the threshold it fails,
    said in the verdict, never absorbed: a RUN-WIDE REGRESSION when it lies beyond the controls'
    shift too (significant by the rank test of the benchmarks' changes against the controls'),
    a RUN-WIDE SHIFT when the controls moved as much (the machine, or the build's compiler and
    flags, or Mesa, moved: the code cannot be told from it; scripts/regress can) or when there
    are no controls to tell;
  - each benchmark with repetitions in both runs (>= 2): Welch's t-test of NEW slower than OLD;
  - each family (the kind and the fields that name its code, BM_Trace/technique:pom, with >= 3
    benchmarks): the rank test of its benchmarks' changes against the rest of the run's;
  - the Benjamini-Hochberg correction over all these tests at --fdr: with no change at all, the
    chance of any flag is at most --fdr, however many benchmarks the run has;
  - a REGRESSION is significant and slower than the controls by more than the threshold (a
    family by its median). Without repetitions the median change alone decides (said once).
  A run of fewer than 20 benchmarks (besides the controls) is a small run: too few to estimate
  the run-wide shift, which compare says. Each benchmark with repetitions is then judged on its
  own against OLD, with no correction for the machine, by Welch's t-test, Benjamini-Hochberg over
  them and --small-threshold as the minimum effect (calibrated on runs of one binary twice on this
  project's machine: docs/regression-tracking.md); a small run without repetitions cannot be
  judged and is refused (exit 2).
  Speed is not judged when CPU model, core count, view size, depth-map size or build type are
  known to differ: the changes are printed but do not fail unless --force-speed ("unknown" on
  one side warns but is judged).
- GLSL benchmarks run on a GL renderer (the context's heightmarch_gl): where the two runs' differ,
  their GLSL benchmarks are kept apart, as another machine's would be (said, and not compared,
  nor taken as controls); the others are compared as usual.
- Samples per ray and the error measures (those the files' context names in
  heightmarch_error_measures; before it uv_error_*, wrong_surface_rate, depth_error_mean,
  shadow_*) are deterministic: any change beyond 1e-6 relative or 1e-9 absolute is a BEHAVIOUR
  CHANGE, reported apart from speed. They are not judged when view or depth-map sizes differ.

Exits 0 with no regression or behaviour change, 1 with a speed regression (of benchmarks or of
the whole run) and/or a behaviour change, 2 on unusable input (one line on stderr): a missing file, invalid JSON,
JSON that is not Google Benchmark's shape (a "benchmarks" list of objects; names and units as strings; real and cpu times
finite and positive in a unit of s, ms, us, ns; counters numbers or null), no shared benchmark,
a threshold or level outside (0, 1).
"""
import argparse
import math
import statistics

from .benchmark_results import clock, context_value, fields, load_benchmarks, matched_runs, seconds
from .cli import Parser
from .errors import Unusable
from .escape import terminal
from .significance import bh_adjusted, rank_greater, welch_greater

# The deterministic counters: samples per ray and the error measures, which a file names in its
# context (heightmarch_error_measures); files written before it carry these.
BEHAVIOUR_COUNTERS = ["samples_per_ray"]
OLDER_ERROR_MEASURES = ["uv_error_mean", "uv_error_rms", "uv_error_p50", "uv_error_p95", "uv_error_p99", "uv_error_max",
                        "wrong_surface_rate", "depth_error_mean", "shadow_error_mean", "shadow_mismatch_rate"]
REL_TOL, ABS_TOL = 1e-6, 1e-9
# Context keys: label, key, whether a difference makes speed / error measures incomparable.
CONTEXT = [("CPU model", "heightmarch_cpu", True, False),
           ("core count", "num_cpus", True, False),
           ("best ISA", "heightmarch_best_isa", False, False),
           ("compiler", "heightmarch_compiler", False, False),
           ("view size", "heightmarch_view", True, True),
           ("depth-map size", "heightmarch_depth_map", True, True),
           ("build type", "heightmarch_build_type", True, False),
           ("benchmark library build type", "library_build_type", False, False)]
LIST_CAP = 20
MIN_FOR_SHIFT = 20  # benchmarks with repetitions needed to estimate the run-wide shift
MIN_CONTROLS = 3  # control benchmarks with repetitions needed to estimate the machine's shift
SMALL_THRESHOLD = 0.40  # measured on 10-benchmark runs of one binary twice: docs/regression-tracking.md
MIN_FAMILY = 3  # benchmarks a family (and the rest of the run) needs for its rank test


def why_nothing_shared(old_names, new_names):
    """Names the fields whose values never agree when dropping them makes names match."""
    old_fields, new_fields = [fields(n) for n in old_names], [fields(n) for n in new_names]
    keys = {k for f in old_fields + new_fields for k in f}
    differing = sorted(k for k in keys if not {f.get(k) for f in old_fields} & {f.get(k) for f in new_fields})

    def without(name):
        return "/".join(p for p in name.split("/") if p.split(":", 1)[0] not in differing)

    if differing and {without(n) for n in old_names} & {without(n) for n in new_names}:
        def values(fs, k):
            return ",".join(sorted({f.get(k) or "none" for f in fs}))

        why = "names differ only in their %s fields (OLD %s; NEW %s)" % (
            "/".join(k + ":" for k in differing),
            " ".join("%s:%s" % (k, values(old_fields, k)) for k in differing),
            " ".join("%s:%s" % (k, values(new_fields, k)) for k in differing))
        if {"view", "depth_map"} & set(differing):
            why += ": the runs are at different sizes"
        return why
    return "e.g. OLD %s, NEW %s" % (min(old_names), min(new_names))


def error_measures(data):
    """The error measures a file's rows carry, as its context names them."""
    named = context_value(data, "heightmarch_error_measures")
    return OLDER_ERROR_MEASURES if named == "unknown" else [m.strip() for m in named.split(",") if m.strip()]


def counter_value(entries, counter):
    """The median of a counter over the repetitions; NaN where the file holds null (its NaN)."""
    values = [b[counter] for b in entries if b[counter] is not None]
    return statistics.median(values) if values else math.nan


def same(a, b):
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return abs(a - b) <= max(ABS_TOL, REL_TOL * max(abs(a), abs(b)))


# Fields that vary within a kernel's family; any other field (the technique, a shader, a
# renderer, a view window) keeps families apart.
WITHIN_FAMILY = ("heightfield", "layers", "isa", "threads", "view", "depth_map")


def family(name):
    """A benchmark's family: its kind and the fields that name the code it runs
    (BM_Trace/technique:pom), which a change to one kernel or shader slows down together."""
    parts = name.split("/")
    return "/".join([parts[0]] + [p for p in parts[1:] if ":" in p and p.split(":", 1)[0] not in WITHIN_FAMILY])


def control_kind(name):
    """"calibration" or "glsl" for a control benchmark (one whose speed no commit of heightmarch
    changes: the calibration loop, llvmpipe's GLSL rows), else None."""
    kind = name.split("/", 1)[0]
    if kind == "BM_Calibration":
        return "calibration"
    if kind == "BM_GLSL" and "llvmpipe" in fields(name).get("renderer", "llvmpipe"):
        return "glsl"
    return None


def log_times(runs, name):
    return [math.log(seconds(b, clock(name))) for b in runs[name]]


def median_change(names, delta):
    return statistics.median(delta[n] for n in names) if names else None


def judge_speed(old_runs, new_runs, shared, behaviour_changed, args):
    """The speed rule (the docstring's). Returns {"benchmarks": {name: (change, change against the
    reference, q-value or None, slower, role)}, "families": {family: (count, median change against
    the reference, q-value, slower)}, "run": the run-wide figures and verdict, "notes": lines}."""
    logs = {n: (log_times(old_runs, n), log_times(new_runs, n)) for n in shared}
    delta = {n: statistics.median(b) - statistics.median(a) for n, (a, b) in logs.items()}
    with_reps = {n for n in shared if min(len(logs[n][0]), len(logs[n][1])) >= 2}
    # A GLSL row whose measures changed runs a changed shader: no control.
    role = {n: ("code" if control_kind(n) is None or n in behaviour_changed else "control") for n in shared}
    code = [n for n in shared if role[n] == "code"]
    controls = [n for n in shared if role[n] == "control"]
    small = len(code) < MIN_FOR_SHIFT
    notes, pvalues = [], {}
    run = {"small": small, "code_shift": median_change(code, delta), "control_shift": None, "slower": False,
           "cause": None}
    if small:
        if not with_reps.intersection(code):
            raise Unusable("speed cannot be judged: %d benchmark(s), too few to estimate the run-wide shift (%d needed), "
                           "and none with repetitions in both runs to judge it on its own: rerun both with "
                           "--benchmark_repetitions=10, or time both builds side by side with scripts/regress"
                           % (len(code), MIN_FOR_SHIFT))
        limit = math.log1p(args.small_threshold)
        reference = 0.0
        notes.append("small run: %d benchmark(s), too few to estimate the run-wide shift (%d needed): each is judged on "
                     "its own repetitions against OLD, with no run-wide correction, and only a change beyond "
                     "--small-threshold (%.0f%%) counts" % (len(code), MIN_FOR_SHIFT, 100 * args.small_threshold))
    else:
        limit = math.log1p(args.threshold)
        if len(controls) >= MIN_CONTROLS:
            run["control_shift"] = median_change(controls, delta)
            by_kind = ", ".join("%s %+.1f%% (%d)" % (k, 100 * math.expm1(median_change(ns, delta)), len(ns)) for k, ns in
                                ((k, [n for n in controls if control_kind(n) == k]) for k in ("calibration", "glsl")) if ns)
            notes.append("machine: the controls (benchmarks no commit changes) moved NEW %+.1f%% against OLD (%s): speed "
                         "is judged against them" % (100 * math.expm1(run["control_shift"]), by_kind))
            # The code against the controls as a whole: a change that slows every kernel alike.
            pvalues["run"] = rank_greater([delta[n] for n in code], [delta[n] for n in controls])
        else:
            notes.append("machine: not estimated (%d control benchmark(s), %d needed: BM_Calibration, "
                         "llvmpipe's BM_GLSL): speed is judged against OLD as it is" % (len(controls), MIN_CONTROLS))
        reference = run["control_shift"] or 0.0
        notes.append("whole run: NEW %+.1f%% against OLD (its median benchmark, of %d)"
                     % (100 * math.expm1(run["code_shift"]), len(code)))
    for n in (n for n in code if n in with_reps):
        pvalues[n] = welch_greater([x - reference for x in logs[n][1]], logs[n][0])
    members = {}
    if not small:
        for n in code:
            members.setdefault(family(n), []).append(delta[n] - reference)
        for f, values in members.items():
            rest = [delta[n] - reference for n in code if family(n) != f]
            if len(values) >= MIN_FAMILY and len(rest) >= MIN_FAMILY:
                pvalues[f] = rank_greater(values, rest)
    keys = list(pvalues)
    q = dict(zip(keys, bh_adjusted([pvalues[k] for k in keys])))
    benchmarks = {}
    for n in shared:
        relative = delta[n] - reference
        # without repetitions (a large run only) the median change alone decides
        judged = role[n] == "code" and (n in q or not small)
        benchmarks[n] = (math.expm1(delta[n]), math.expm1(relative), q.get(n),
                         judged and relative > limit and (n not in q or q[n] <= args.fdr), role[n])
    families = {}
    for f, values in members.items():
        if f in q:
            effect = statistics.median(values)
            families[f] = (len(values), math.expm1(effect), q[f], effect > limit and q[f] <= args.fdr)
    if not small:
        moved = run["code_shift"] > limit
        beyond = "run" in q and q["run"] <= args.fdr and run["code_shift"] - run["control_shift"] > limit
        run["q"] = q.get("run")
        run["slower"] = moved or beyond
        run["cause"] = ("code" if beyond else None if not moved else
                        "machine" if run["control_shift"] is not None and run["code_shift"] - run["control_shift"] <= limit
                        else "unknown")
    return {"benchmarks": benchmarks, "families": families, "run": run, "notes": notes,
            "no_reps": len(shared) - len(with_reps), "limit": limit}


def run_verdict(run, threshold):
    """The line that says how the whole run moved, and whether that fails."""
    code = 100 * math.expm1(run["code_shift"])
    controls = "" if run["control_shift"] is None else ", the controls %+.1f%%" % (100 * math.expm1(run["control_shift"]))
    if run["cause"] == "code":
        return ("RUN-WIDE REGRESSION: the whole run (its median benchmark) is %+.1f%% against OLD%s (q %.4f): most of the "
                "code is slower, beyond the machine (a lost compiler flag, a narrower ISA?)" % (code, controls, run["q"]))
    if run["cause"] == "machine":
        return ("RUN-WIDE SHIFT: the whole run (its median benchmark) is %+.1f%% against OLD%s: the machine (or the "
                "build's compiler, flags, Mesa) moved as much as the code; a change of every benchmark cannot be told "
                "from it: rerun both on a quiet machine, or time both builds side by side with scripts/regress"
                % (code, controls))
    if run["cause"] == "unknown":
        why = ("no control benchmark to tell the machine from the code" if run["control_shift"] is None else
               "the controls do not tell whether the machine or the code moved")
        return ("RUN-WIDE SHIFT: the whole run (its median benchmark) is %+.1f%% against OLD%s, beyond %.0f%%: %s; "
                "time both builds side by side with scripts/regress" % (code, controls, 100 * threshold, why))
    return None


def print_only_in(label, names, other_errors):
    if not names:
        return
    print("\nonly in %s (%d):" % (label, len(names)))
    for name in names[:LIST_CAP]:
        print("  " + terminal(name + ("  [failed in the other run: %s]" % other_errors[name] if name in other_errors else "")))
    if len(names) > LIST_CAP:
        print("  ... and %d more" % (len(names) - LIST_CAP))


def compare(args):
    old, new = load_benchmarks(args.old), load_benchmarks(args.new)
    speed_judged = behaviour_judged = True
    differs = []
    for label, key, speed, errors in CONTEXT:
        a, b = context_value(old, key), context_value(new, key)
        if a == b:
            continue
        if "unknown" in (a, b):
            print("WARNING: %s: OLD %s, NEW %s: cannot tell whether they match" % (label, terminal(a), terminal(b)))
            continue
        consequence = ""
        if speed:
            speed_judged = args.force_speed
            differs.append(label)
            consequence = ": speed changes are not comparable"
        if errors:
            behaviour_judged = False
            consequence += ", nor error measures"
        print("WARNING: %s differs: OLD %s, NEW %s%s" % (label, terminal(a), terminal(b), consequence))
    if not speed_judged:
        print("WARNING: speed changes are printed but not judged (--force-speed judges them)")

    old_runs, new_runs, old_raw, new_raw, old_errors, new_errors, old_sizes, new_sizes = matched_runs(old, new)
    gl_old, gl_new = context_value(old, "heightmarch_gl"), context_value(new, "heightmarch_gl")
    if gl_old != gl_new and "unknown" not in (gl_old, gl_new):
        kept_apart = [n for n in old_runs if n in new_runs and n.startswith("BM_GLSL/")]
        for name in kept_apart:
            del old_runs[name], new_runs[name]
        print("WARNING: GL renderer differs: OLD %s, NEW %s: %d GLSL benchmark(s) kept apart, not compared"
              % (gl_old, gl_new, len(kept_apart)))
    shared = [n for n in old_runs if n in new_runs]
    for path, runs in ((args.old, old_runs), (args.new, new_runs)):
        if not runs:
            raise Unusable("%s: holds no benchmark result" % path)
    if not shared:
        raise Unusable("%s and %s share no benchmark: %s"
                       % (args.old, args.new, why_nothing_shared(list(old_runs), list(new_runs))))
    renamed = sum(old_raw[n] != new_raw[n] for n in shared)
    if renamed:
        how = ["/min_time: dropped"] if any("/min_time:" in r for r in list(old_raw.values()) + list(new_raw.values())) else []
        how += ["view:/depth_map: from %s's context" % label
                for label, sizes in (("OLD", old_sizes), ("NEW", new_sizes)) if sizes]
        print("note: %d benchmark(s) matched across name formats: %s" % (renamed, ", ".join(how)))
    changed = {}
    counters_one_side = {}
    counters = BEHAVIOUR_COUNTERS + sorted(set(error_measures(old)) | set(error_measures(new)))
    for name in shared:
        o, n = old_runs[name], new_runs[name]
        diffs = []
        for counter in counters:
            have_o, have_n = counter in o[0], counter in n[0]
            if have_o != have_n:
                side = "OLD" if have_o else "NEW"
                counters_one_side[(counter, side)] = counters_one_side.get((counter, side), 0) + 1
            elif have_o:
                a, c = counter_value(o, counter), counter_value(n, counter)
                if not same(a, c):
                    diffs.append("%s %.9g -> %.9g" % (counter, a, c))
        if diffs:
            changed[name] = diffs
    judgement = judge_speed(old_runs, new_runs, shared, changed, args)
    run = judgement["run"]
    if judgement["no_reps"]:
        print("note: %d benchmark(s) lack repetitions in one run or both (>= 2 needed for the t-test): %s"
              % (judgement["no_reps"], "not judged" if run["small"] else "judged on the median time change alone"))
    for note in judgement["notes"]:
        print(note)

    against = "vs OLD" if run["small"] or run["control_shift"] is None else "vs ctrl"
    print("\n%8s %8s %8s  %-10s  %s" % ("time", against, "q-value", "",
                                        "benchmark (time, median NEW vs OLD: CPU time at 1 thread, else wall)"))
    slower = []
    for name in shared:
        change, relative, q, is_slower, role = judgement["benchmarks"][name]
        if is_slower:
            slower.append(name)
        verdict = ("REGRESSION" if speed_judged else "slower") if is_slower else "(control)" if role == "control" else ""
        print("%+7.1f%% %+7.1f%% %8s  %-10s  %s" % (100 * change, 100 * relative, "-" if q is None else "%.4f" % q, verdict,
                                                terminal(name)))

    print_only_in("OLD", [x for x in old_runs if x not in new_runs], new_errors)
    print_only_in("NEW", [x for x in new_runs if x not in old_runs], old_errors)
    for (counter, side), count in sorted(counters_one_side.items()):
        print("note: counter %s only in %s (%d benchmark(s)): not compared" % (counter, side, count))

    if changed:
        if behaviour_judged:
            print("\nerror measures changed beyond %g relative and %g absolute, a BEHAVIOUR CHANGE:" % (REL_TOL, ABS_TOL))
        else:
            print("\nerror measures differ, as expected at different sizes (not judged):")
        for name, diffs in changed.items():
            print("  %s: %s" % (terminal(name), ", ".join(diffs)))

    families = judgement["families"]
    if families:
        print("\nfamilies (kind and technique) against the rest of the run: median change %s, q-value" % against)
        for family, (count, relative, q, is_slower) in sorted(families.items()):
            print("%+7.1f%% %8.4f  %-10s  %s (%d benchmarks)" % (100 * relative, q, ("REGRESSION" if speed_judged else "slower")
                                                                if is_slower else "", terminal(family), count))
    slower_families = [f for f, (_, _, _, is_slower) in sorted(families.items()) if is_slower]

    print()
    failures = []
    threshold = args.small_threshold if run["small"] else args.threshold
    what = "slower %s by more than %.0f%% (Benjamini-Hochberg q <= %g)" % (
        "than OLD" if against == "vs OLD" else "than the controls", 100 * threshold, args.fdr)
    whole = run_verdict(run, threshold) if run["slower"] else None
    if not speed_judged:
        print("%d benchmark(s) and %d famil%s %s, not judged: %s differs"
              % (len(slower), len(slower_families), "y" if len(slower_families) == 1 else "ies", what, " and ".join(differs)))
        if whole:
            print("not judged: " + whole)
    else:
        if whole:
            failures.append("run-wide shift" if run["cause"] != "code" else "run-wide regression")
            print(whole)
        elif not run["small"] and run["code_shift"] < -judgement["limit"]:
            print("note: the whole run is %+.1f%% against OLD: faster throughout" % (100 * math.expm1(run["code_shift"])))
        if slower or slower_families:
            failures.append("speed regression")
            print("SPEED REGRESSION: %d benchmark(s) and %d famil%s %s:" % (
                len(slower), len(slower_families), "y" if len(slower_families) == 1 else "ies", what))
            for name in slower_families + slower:
                print("  " + terminal(name))
        else:
            print("no speed regression: no benchmark nor family %s" % what)
    if not changed:
        print("error measures unchanged in %d shared benchmark(s)" % len(shared))
    elif behaviour_judged:
        failures.append("behaviour change")
        print("BEHAVIOUR CHANGE: error measures changed in %d benchmark(s) (listed above)" % len(changed))
    else:
        print("error measures differ in %d benchmark(s), not judged: the sizes differ" % len(changed))
    if failures:
        print("FAILED: " + " and ".join(failures))
        return 1
    return 0


def main(argv):
    parser = Parser(prog="compare", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old", help="the earlier run: a suite's bench.json or heightmarch-bench --benchmark_out")
    parser.add_argument("new", help="the later run, the same")
    parser.add_argument("--threshold", type=float, default=0.05,
                        help="relative slow-down that counts, of a benchmark, a family or the whole run (default 0.05)")
    parser.add_argument("--small-threshold", type=float, default=SMALL_THRESHOLD,
                        help="the same in a run too small to estimate the run-wide shift (default %g)" % SMALL_THRESHOLD)
    parser.add_argument("--fdr", type=float, default=0.05,
                        help="Benjamini-Hochberg level over the run's benchmarks and families (default 0.05)")
    parser.add_argument("--force-speed", action="store_true",
                        help="judge speed even when CPU, sizes or build type differ")
    args = parser.parse_args(argv)
    for option, value in (("--threshold", args.threshold), ("--small-threshold", args.small_threshold), ("--fdr", args.fdr)):
        if not 0 < value < 1:
            raise Unusable("%s %g is not in (0, 1)" % (option, value))
    return compare(args)
