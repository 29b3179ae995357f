#!/usr/bin/env bash
# scripts/compare on synthetic runs, one check per rule of its docstring: identical runs pass (the
# machine's shift taken from the controls), a 30% slow-down is a named REGRESSION, no shared
# benchmark is unusable input (exit 2), benchmarks of one run only are listed, context differences
# are WARNINGs in the first lines, changed error measures (those the files name) are a BEHAVIOUR
# CHANGE, runs without repetitions fall back to the median change, names with min_time: match the
# new release's names, a FIFO, /dev/zero, a file beyond the memory budget and input that is not
# Google Benchmark's shape exit 2 with one line; the speed rule keeps runs of the same code quiet
# while it flags a 10% slow-down of one family; a uniform 20% slow-down of the latest committed run
# fails; small runs of one binary raise no false alarm; the latest committed run passes against
# itself. Needs no build; about 30 s on 2 busy cores.
# Usage: test_compare.sh BUILD_DIR (unused)
set -euo pipefail
source "$(dirname "$0")/prelude.sh"

# write_run FILE [SPEC_JSON]: a run of BM_Trace benchmarks, each technique on heightfields h0..hN-1,
# and its controls: BM_Calibration at 1 and 2 threads and each technique's BM_GLSL on h0. SPEC keys
# (all optional): techniques, heightfields (N, 6), controls (true), reps, slow {technique: factor},
# code (a factor on every time but the controls'), machine (a factor on every time), style "new"
# (view:/depth_map: in names) or "old" (min_time:), view, depth_map, cpu, build_type,
# counter_scale {counter: factor}.
write_run() {
  /usr/bin/python3 - "$1" "${2:-{\}}" <<'PY'
import json, sys
path, spec = sys.argv[1], json.loads(sys.argv[2])
reps, view, depth = spec.get("reps", 9), spec.get("view", "1024x1024"), spec.get("depth_map", "512x512")
benchmarks = []


def add(kind, heightfield, technique, k, factor):
    name = "%s/heightfield:%s/%slayers:32/isa:%s/threads:%d/" % (
        kind, heightfield, "technique:%s/" % technique if technique else "", "glsl" if kind == "BM_GLSL" else "avx2",
        2 if kind == "BM_Calibration" and k else 1)
    name += "min_time:0.200/real_time" if spec.get("style") == "old" else "view:%s/depth_map:%s/real_time" % (view, depth)
    counters = {} if kind == "BM_Calibration" else {
        "uv_error_mean": 0.5 + k, "uv_error_p95": 2.0 + k, "wrong_surface_rate": 0.01, "samples_per_ray": 20.0 + k}
    for counter, scale in spec.get("counter_scale", {}).items():
        if counter in counters:
            counters[counter] *= scale
    times = [(40.0 + 10 * k) * (1 + 0.003 * ((rep * 7) % 5)) * factor * spec.get("machine", 1.0) for rep in range(reps)]
    common = {"name": name, "run_name": name, "repetitions": reps, "threads": 1, "time_unit": "ms"}
    for rep, t in enumerate(times):
        benchmarks.append(dict(common, run_type="iteration", repetition_index=rep, iterations=10, real_time=t,
                               cpu_time=t, rays_per_second=1e6 / t, **counters))
    if reps > 1:  # aggregates, which compare must ignore
        for agg in ("mean", "median", "stddev", "cv"):
            benchmarks.append(dict(common, name=name + "_" + agg, run_type="aggregate", aggregate_name=agg,
                                   iterations=reps, real_time=1.0, cpu_time=1.0, **counters))


techniques = spec.get("techniques", ["pom", "steep", "relief", "secant"])
for k, technique in enumerate(techniques):
    for h in range(spec.get("heightfields", 6)):
        add("BM_Trace", "h%d" % h, technique, k, spec.get("slow", {}).get(technique, 1.0) * spec.get("code", 1.0))
if spec.get("controls", True):
    for k in range(2):
        add("BM_Calibration", "h0", None, k, 1.0)
    for k, technique in enumerate(techniques):
        add("BM_GLSL", "h0", technique, k, 1.0)
context = {"date": "x", "num_cpus": 2, "library_build_type": "release",
           "heightmarch_cpu": spec.get("cpu", "AMD EPYC"), "heightmarch_best_isa": "avx512",
           "heightmarch_view": ("default " if spec.get("style") == "old" else "") + view,
           "heightmarch_depth_map": depth, "heightmarch_build_type": spec.get("build_type", "Release")}
json.dump({"context": context, "benchmarks": benchmarks}, open(path, "w"))
PY
}

# run CASE OLD NEW [OPTIONS]: runs compare, keeping CASE.out, CASE.err and the exit code in rc.
run() {
  local case="$1"; shift
  last="$case"; rc=0
  "$root/scripts/compare" "$@" > "$tmp/$case.out" 2> "$tmp/$case.err" || rc=$?
}
fail() { echo "--- stdout"; head -40 "$tmp/$last.out"; echo "--- stderr"; cat "$tmp/$last.err"; echo "FAIL: $*"; exit 1; }
has() { grep -q -- "$1" "$tmp/$last.${2:-out}"; }
first_lines_have() { head -3 "$tmp/$last.out" | grep -q -- "$1"; }

write_run "$tmp/old.json"
write_run "$tmp/same.json"
run identical "$tmp/old.json" "$tmp/same.json"
[ "$rc" = 0 ] && has "no speed regression" && has "error measures unchanged in 30" && ! has WARNING \
  && has "^machine: the controls .* moved NEW +0.0% against OLD (calibration +0.0% (2), glsl +0.0% (4))" || fail "identical runs do not pass (exit $rc)"
echo "ok: identical runs pass (exit 0), the machine's shift taken from the 6 controls"

write_run "$tmp/slow.json" '{"slow": {"pom": 1.3}}'
run slow "$tmp/old.json" "$tmp/slow.json"
[ "$rc" = 1 ] || fail "a 30% slow-down exits $rc, not 1"
[ "$(grep "REGRESSION  *BM_Trace/heightfield:h./technique:pom/" "$tmp/slow.out" | wc -l)" = 6 ] || fail "the slower benchmarks are not named as REGRESSIONs"
! grep "technique:steep" "$tmp/slow.out" | grep -q REGRESSION || fail "an unchanged benchmark is flagged"
has "SPEED REGRESSION: 6 benchmark(s) and 1 family" && has "REGRESSION  BM_Trace/technique:pom (6 benchmarks)" && ! has "RUN-WIDE" \
  && ! has "BEHAVIOUR CHANGE" || fail "the summary does not say speed regression alone"
echo "ok: the 30% slower benchmarks (9 repetitions, t-test) and their family are named REGRESSIONs, the unchanged ones are not (exit 1)"

write_run "$tmp/other.json" '{"techniques": ["parallax", "cone"], "controls": false}'
run unshared "$tmp/old.json" "$tmp/other.json"
[ "$rc" = 2 ] && [ "$(wc -l < "$tmp/unshared.err")" = 1 ] && has "share no benchmark" err || fail "no shared benchmark: exit $rc, not 2 with one line"
echo "ok: no shared benchmark exits 2 with one line: $(cat "$tmp/unshared.err")"

write_run "$tmp/few.json" '{"techniques": ["pom", "steep"], "heightfields": 1, "controls": false}'
write_run "$tmp/partial.json" "{\"techniques\": [\"pom\", \"relief\", $(seq -s, -f '"t%g"' 1 24)], \"heightfields\": 1, \"controls\": false}"
run only_in "$tmp/few.json" "$tmp/partial.json"
[ "$rc" = 0 ] || fail "partly shared runs exit $rc"
has "^only in OLD (1):" && has "technique:steep/" && has "^only in NEW (25):" && has "technique:relief/" && has "and 5 more" || fail "benchmarks of one run only are not listed"
echo "ok: benchmarks of one run only are listed (capped at 20 with a count)"

write_run "$tmp/intel.json" '{"cpu": "Intel Xeon", "slow": {"pom": 1.3}}'
run cpu "$tmp/old.json" "$tmp/intel.json"
first_lines_have "WARNING: CPU model differs: OLD AMD EPYC, NEW Intel Xeon: speed changes are not comparable" || fail "no CPU WARNING in the first lines"
[ "$rc" = 0 ] && has "not judged: CPU model differs" || fail "a slow-down across CPUs exits $rc, not 0 with not judged"
run cpu_forced "$tmp/old.json" "$tmp/intel.json" --force-speed
[ "$rc" = 1 ] && has "SPEED REGRESSION" || fail "--force-speed does not judge speed across CPUs (exit $rc)"
echo "ok: CPU differs: WARNING in the first lines, speed printed but not judged (exit 0; 1 with --force-speed)"

write_run "$tmp/old-1024.json" '{"style": "old"}'
write_run "$tmp/old-256.json" '{"style": "old", "view": "256x256", "counter_scale": {"uv_error_mean": 0.5}}'
run view_context "$tmp/old-1024.json" "$tmp/old-256.json"
first_lines_have "WARNING: view size differs: OLD 1024x1024, NEW 256x256" && [ "$rc" = 0 ] && has "not judged: the sizes differ" || fail "view size differs: no WARNING or judged (exit $rc)"
write_run "$tmp/view-256.json" '{"view": "256x256"}'
run view_names "$tmp/old.json" "$tmp/view-256.json"
first_lines_have "WARNING: view size differs" && [ "$rc" = 2 ] && has "names differ only in their view: fields.*different sizes" err || fail "sizes in the names: not exit 2 saying so (exit $rc)"
echo "ok: view size differs: WARNING, not judged; with sizes in the names exit 2: $(cat "$tmp/view_names.err")"

write_run "$tmp/debug.json" '{"build_type": "Debug"}'
run build_type "$tmp/old.json" "$tmp/debug.json"
first_lines_have "WARNING: build type differs: OLD Release, NEW Debug" || fail "no build-type WARNING in the first lines"
/usr/bin/python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); d["context"] = {"date": "x"}; json.dump(d, open(sys.argv[2], "w"))' \
  "$tmp/old.json" "$tmp/bare.json"
run unknown "$tmp/bare.json" "$tmp/old.json"
[ "$rc" = 0 ] && first_lines_have "WARNING: CPU model: OLD unknown, NEW AMD EPYC: cannot tell whether they match" \
  || fail "a context without the keys: exit $rc or no unknown WARNING"
echo "ok: build type differs: WARNING in the first lines; a context without the keys says unknown"

# GLSL benchmarks on two GL renderers are kept apart (and a slower GPU is no regression); the
# CPU's are compared as usual.
/usr/bin/python3 - "$tmp/old.json" "$tmp/gl-a.json" "$tmp/gl-b.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
for b in d["benchmarks"]:
    for key in ("name", "run_name"):
        if "/technique:pom/" in b[key]:
            b[key] = b[key].replace("BM_Trace/", "BM_GLSL/").replace("/isa:avx2/threads:1/", "/isa:glsl/threads:1/gl:egl/")
for path, gl, scale in ((sys.argv[2], "glsl (llvmpipe, LLVM 15.0.6, 256 bits; EGL)", 1.0), (sys.argv[3], "glsl (GPU X; EGL)", 2.0)):
    d["context"]["heightmarch_gl"] = gl
    for b in d["benchmarks"]:
        b["real_time"] *= scale if b["name"].startswith("BM_GLSL/") else 1.0
    json.dump(d, open(path, "w"))
PY
run gl "$tmp/gl-a.json" "$tmp/gl-b.json"
[ "$rc" = 0 ] && has "WARNING: GL renderer differs: OLD glsl (llvmpipe, LLVM 15.0.6, 256 bits; EGL), NEW glsl (GPU X; EGL): 10 GLSL benchmark(s) kept apart, not compared" \
  && ! has "REGRESSION" && ! grep -v WARNING "$tmp/gl.out" | grep -q BM_GLSL && has "technique:steep" \
  || fail "GLSL benchmarks of two renderers are compared (exit $rc)"
echo "ok: GLSL benchmarks of two GL renderers are kept apart, the CPU's compared"

write_run "$tmp/changed.json" '{"counter_scale": {"uv_error_mean": 1.001}}'
write_run "$tmp/rounded.json" '{"counter_scale": {"uv_error_mean": 1.0000000001}}'
run behaviour "$tmp/old.json" "$tmp/changed.json"
[ "$rc" = 1 ] && has "a BEHAVIOUR CHANGE:$" && has "^BEHAVIOUR CHANGE: error measures changed in 28 benchmark" && has "uv_error_mean 0.5 -> 0.5005" \
  && has "no speed regression" && has "^FAILED: behaviour change$" || fail "a changed error measure is not a BEHAVIOUR CHANGE (exit $rc)"
run rounding "$tmp/old.json" "$tmp/rounded.json"
[ "$rc" = 0 ] || fail "a change within the tolerance exits $rc"
echo "ok: a changed error counter is a BEHAVIOUR CHANGE apart from speed (exit 1); 1e-10 relative is not"

# The measures compared are those the files' context names (heightmarch_error_measures): a new one
# is compared without a change here.
/usr/bin/python3 - "$tmp/old.json" "$tmp/measures-old.json" "$tmp/measures-new.json" <<'PY'
import json, sys
for path, value in ((sys.argv[2], 0.25), (sys.argv[3], 0.5)):
    d = json.load(open(sys.argv[1]))
    d["context"]["heightmarch_error_measures"] = "uv_error_mean,glint_error_mean"
    for b in d["benchmarks"]:
        b["glint_error_mean"] = value
    json.dump(d, open(path, "w"))
PY
run measures "$tmp/measures-old.json" "$tmp/measures-new.json"
[ "$rc" = 1 ] && has "glint_error_mean 0.25 -> 0.5" && has "^BEHAVIOUR CHANGE" || fail "a measure the context names is not compared (exit $rc)"
echo "ok: the error measures compared are those the files name"

write_run "$tmp/once.json" '{"reps": 1}'
write_run "$tmp/once-slow.json" '{"reps": 1, "slow": {"pom": 1.3}}'
run no_reps "$tmp/once.json" "$tmp/once-slow.json"
[ "$rc" = 1 ] && has "judged on the median time change alone" && grep "h0/technique:pom" "$tmp/no_reps.out" | grep -q "  -  *REGRESSION" \
  || fail "without repetitions: no fallback said, or the slow-down missed (exit $rc)"
echo "ok: without repetitions compare falls back to the median change and says so"

run min_time "$tmp/old-1024.json" "$tmp/old.json"
[ "$rc" = 0 ] && has "note: 30 benchmark(s) matched across name formats: /min_time: dropped, view:/depth_map: from OLD's context" \
  && ! has "only in" || fail "names with min_time: do not match the new names (exit $rc)"
run min_time_256 "$tmp/old-1024.json" "$tmp/view-256.json"
[ "$rc" = 2 ] || fail "an old 1024x1024 run matches a 256x256 run (exit $rc)"
echo "ok: old names with min_time: match new names at the same sizes, not at other sizes"

echo "not json" > "$tmp/bad.json"
run bad "$tmp/old.json" "$tmp/bad.json"
[ "$rc" = 2 ] && has "bad.json: invalid JSON" err || fail "invalid JSON exits $rc"
run missing "$tmp/old.json" "$tmp/none.json"
[ "$rc" = 2 ] && has "none.json: no such file" err || fail "a missing file exits $rc"
echo "ok: invalid JSON and a missing file exit 2 naming the file"

# Files that are no files, or too large: refused before a byte is read, one line, exit 2, no wait.
mkfifo "$tmp/fifo.json"
ln -s /dev/zero "$tmp/zero.json"
for bad in "fifo.json::is a FIFO, not a regular file" "zero.json::is a character device, not a regular file" \
           "old.json::would need about .* more than the .* left of the memory budget"; do
  rc=0
  HEIGHTMARCH_MEMORY_LIMIT=$([ "${bad%%::*}" = old.json ] && echo 64K || echo 1G) \
    timeout 20 "$root/scripts/compare" "$tmp/same.json" "$tmp/${bad%%::*}" > "$tmp/file.out" 2> "$tmp/file.err" || rc=$?
  last="file"
  [ "$rc" = 2 ] && [ "$(wc -l < "$tmp/file.err")" = 1 ] && has "${bad##*::}" err || fail "NEW ${bad%%::*}: exit $rc"
done
echo "ok: a FIFO, /dev/zero and a file beyond the memory budget exit 2 with one line, at once"

# Input that is not Google Benchmark's shape: exit 2 with one line, never a traceback or a verdict.
# bad_case NAME PYTHON: PYTHON edits `d` (old.json) and `b` (its first iteration) into NAME.json.
bad_case() {
  /usr/bin/python3 - "$tmp/old.json" "$tmp/$1.json" "$2" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
b = d["benchmarks"][0]
exec(sys.argv[3])
with open(sys.argv[2], "w") as f:
    f.write(d if isinstance(d, str) else json.dumps(d))
PY
  for order in new old; do
    if [ "$order" = new ]; then run "bad_$1" "$tmp/old.json" "$tmp/$1.json"; else run "bad_$1" "$tmp/$1.json" "$tmp/old.json"; fi
    [ "$rc" = 2 ] && [ "$(wc -l < "$tmp/bad_$1.err")" = 1 ] && has "$3" err && ! has Traceback err \
      || fail "$1 ($order file): exit $rc, not 2 with one line naming '$3'"
  done
}
bad_case string_time 'b["real_time"] = "40.0"' 'real_time is "40.0", not a finite positive time'
bad_case null_time 'b["cpu_time"] = None' 'cpu_time is null, not a finite positive time'
bad_case zero_time 'b["real_time"] = 0' 'real_time is 0, not a finite positive time'
bad_case negative_time 'b["real_time"] = -3.5' 'real_time is -3.5, not a finite positive time'
bad_case nan_time 'b["real_time"] = float("nan")' 'real_time is NaN, not a finite positive time'
bad_case unit 'b["time_unit"] = "fortnight"' 'time_unit "fortnight" is none of s, ms, us, ns'
bad_case no_unit 'del b["time_unit"]' 'has no time_unit'
bad_case list_entry 'd["benchmarks"][0] = [b]' 'benchmarks\[0\] is list, not an object'
bad_case list_top 'd = [d]' 'no "benchmarks" list'
bad_case object_benchmarks 'd["benchmarks"] = {"a": b}' 'no "benchmarks" list'
bad_case list_context 'd["context"] = [1]' '"context" is list, not an object'
bad_case name_number 'b["name"] = 7' 'name is 7, not a string'
bad_case counter_string 'b["samples_per_ray"] = "20"' 'samples_per_ray is "20", not a number'
bad_case repetitions 'b["repetitions"] = "9"' 'repetitions is "9", not a count'
bad_case nested 'd = "[" * 100000 + "]" * 100000' 'nested too deeply'
bad_case nested_counter 'b["uv_error_mean"] = json.loads("[" * 50 + "]" * 50)' 'uv_error_mean is \[\[\['
echo "ok: 16 kinds of input that is not Google Benchmark's shape exit 2 with one line, as OLD and as NEW"

# The speed rule on many benchmarks (compare's judge_speed, in-process): synthetic runs of 200
# benchmarks in 10 families and 12 controls, 5 repetitions with 5% noise and a load spike now and
# then, the machine of the NEW run faster or slower as a whole (controls included). 20 pairs of the
# same code, the machine moved by up to 3%, flag nothing in at least 19; a 10% slow-down of one
# family is flagged in each of 5 pairs, and no other family with it; a machine 10-20% slower is a
# RUN-WIDE SHIFT put down to the machine with no benchmark flagged; every benchmark 20% slower on an
# unchanged machine is a RUN-WIDE REGRESSION.
PYTHONPATH="$root/scripts" /usr/bin/python3 - <<'PY' || exit 1
import argparse, random, sys
from heightmarch_tools import compare
rng = random.Random(22)
names = ["BM_Trace/heightfield:h%d/technique:t%d/layers:32/isa:avx2/threads:1" % (k, j) for j in range(10) for k in range(20)]
controls = ["BM_GLSL/heightfield:h%d/technique:t%d/layers:32/isa:glsl/threads:1" % (k, j) for j in range(5) for k in range(2)]
controls += ["BM_Calibration/heightfield:h0/isa:calibration/threads:%d" % t for t in (1, 2)]
base = {n: rng.uniform(0.5, 20.0) for n in names + controls}


def run(machine=1.0, code=1.0, slow=None):
    runs = {}
    for n in names + controls:
        factor = machine * (1.0 if n in controls else code * (1.1 if slow and "/technique:%s/" % slow in n else 1.0))
        times = [base[n] * factor * rng.lognormvariate(0, 0.05) * (1.3 if rng.random() < 0.1 else 1.0) for _ in range(5)]
        runs[n] = [{"real_time": t, "cpu_time": t, "time_unit": "ms"} for t in times]
    return runs


def judge(new):
    return compare.judge_speed(run(), new, names + controls, {}, argparse.Namespace(threshold=0.05, small_threshold=0.3,
                                                                                      fdr=0.05))


def flags(j):
    return sum(v[3] for v in j["benchmarks"].values()) + sum(v[3] for v in j["families"].values()) + j["run"]["slower"]


flagged = [flags(judge(run(rng.uniform(0.97, 1.03)))) for _ in range(20)]
if sum(f > 0 for f in flagged) > 1:
    sys.exit("FAIL: runs of the same code flag something in %d of 20 pairs: %s" % (sum(f > 0 for f in flagged), flagged))
for _ in range(5):
    j = judge(run(rng.uniform(0.97, 1.03), slow="t3"))
    families = sorted(f for f, v in j["families"].items() if v[3])
    if families != ["BM_Trace/technique:t3"] or j["run"]["slower"]:
        sys.exit("FAIL: a 10%% slow-down of family t3 flags the families %s, the run %s" % (families, j["run"]))
for _ in range(5):
    j = judge(run(rng.uniform(1.1, 1.2)))
    if j["run"]["cause"] != "machine" or any(v[3] for v in j["benchmarks"].values()):
        sys.exit("FAIL: a slower machine: %s, %d benchmarks flagged" % (j["run"], sum(v[3] for v in j["benchmarks"].values())))
j = judge(run(code=1.2))
if j["run"]["cause"] != "code":
    sys.exit("FAIL: every benchmark 20%% slower, the controls not: %s" % j["run"])
print("ok: 20 pairs of the same code flag nothing in %d; a 10%% slow-down of one family is flagged in 5 of 5, alone; a "
      "slower machine is a run-wide shift of the machine with no benchmark flagged; all code slower is a run-wide "
      "regression" % sum(f == 0 for f in flagged))
PY

# A commit that slows every kernel alike is not absorbed: the latest committed run with every time
# 20% longer (llvmpipe's GLSL rows, its controls, too) fails as a run-wide shift of the machine; with
# every time but the controls' 20% longer it fails as a run-wide regression, each benchmark named.
scale_run() {  # scale_run OUT FACTOR CONTROLS_TOO
  /usr/bin/python3 - "$root/results/latest/bench.json.gz" "$@" <<'PY'
import gzip, json, sys
d = json.load(gzip.open(sys.argv[1]))
for b in d["benchmarks"]:
    if sys.argv[4] == "yes" or not b["name"].startswith("BM_GLSL/"):
        b["real_time"] *= float(sys.argv[3])
        b["cpu_time"] *= float(sys.argv[3])
json.dump(d, open(sys.argv[2], "w"))
PY
}
scale_run "$tmp/all-slower.json" 1.2 yes
run uniform "$root/results/latest/bench.json.gz" "$tmp/all-slower.json"
[ "$rc" = 1 ] && has "^RUN-WIDE SHIFT: the whole run (its median benchmark) is +20.0% against OLD, the controls +20.0%: the machine" \
  && has "^FAILED: run-wide shift$" || fail "every benchmark 20% slower: exit $rc, not a run-wide shift"
scale_run "$tmp/code-slower.json" 1.2 no
run uniform_code "$root/results/latest/bench.json.gz" "$tmp/code-slower.json"
[ "$rc" = 1 ] && has "^RUN-WIDE REGRESSION: the whole run (its median benchmark) is +20.0% against OLD, the controls +0.0%" \
  && has "^SPEED REGRESSION: [0-9][0-9]* benchmark(s)" || fail "every benchmark but the controls 20% slower: exit $rc, not a run-wide regression"
echo "ok: a uniform 20% slow-down fails: a run-wide shift when the controls moved too, a run-wide regression when they did not"

# Small runs: 10 benchmarks (too few for a run-wide shift), 5 pairs of runs of one binary whose benchmarks
# moved by up to 28% between the runs, as on this machine, with 5 repetitions each (1% apart): no
# false alarm; the same without repetitions is refused in one line (exit 2); a benchmark 60% slower
# is found.
small_run() {  # small_run OUT SEED REPS MOVED [SLOWER]: MOVED 1, each benchmark 22% faster to 28% slower
  /usr/bin/python3 - "$@" <<'PY'
import json, random, sys
path, seed, reps = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
rng = random.Random(seed)
benchmarks = []
for i, technique in enumerate(["pom", "relief", "steep", "secant", "cone"] * 2):
    name = "BM_Trace/heightfield:bricks/technique:%s/layers:32/isa:%s/threads:1/view:1024x1024/depth_map:512x512" % (
        technique, "avx2" if i < 5 else "avx512")
    run_factor = (rng.uniform(0.78, 1.28) if sys.argv[4] == "1" else 1.0) * (1.6 if len(sys.argv) > 5 and i == 0 else 1.0)
    for rep in range(reps):
        t = (20 + 5 * i) * run_factor * rng.uniform(0.995, 1.005)
        benchmarks.append({"name": name, "run_name": name, "run_type": "iteration", "repetitions": reps, "iterations": 4,
                           "real_time": t, "cpu_time": t, "time_unit": "ms"})
json.dump({"context": {}, "benchmarks": benchmarks}, open(path, "w"))
PY
}
small_alarms=0
for seed in $(seq 1 5); do
  small_run "$tmp/small-a.json" "$seed" 5 0
  small_run "$tmp/small-b.json" "$seed" 5 1
  run small "$tmp/small-a.json" "$tmp/small-b.json"
  [ "$rc" != 2 ] || fail "a small run with repetitions was refused"
  [ "$rc" = 0 ] || small_alarms=$((small_alarms + 1))
done
[ "$small_alarms" = 0 ] && has "^small run: 10 benchmark(s), too few to estimate the run-wide shift (20 needed): each is judged on its own" \
  || fail "5 pairs of small runs of one binary: $small_alarms false alarms"
small_run "$tmp/small-once-a.json" 1 1 0
small_run "$tmp/small-once-b.json" 1 1 1
run small_once "$tmp/small-once-a.json" "$tmp/small-once-b.json"
[ "$rc" = 2 ] && [ "$(wc -l < "$tmp/small_once.err")" = 1 ] \
  && has "speed cannot be judged: 10 benchmark(s), too few to estimate the run-wide shift (20 needed), and none with repetitions" err \
  || fail "a small run without repetitions: exit $rc, not 2 with one line"
small_run "$tmp/small-slower.json" 10 5 0 slower
run small_slower "$tmp/small-a.json" "$tmp/small-slower.json"
[ "$rc" = 1 ] && grep "REGRESSION" "$tmp/small_slower.out" | grep -q "technique:pom/layers:32/isa:avx2" || fail "a 60% slower benchmark in a small run: exit $rc"
echo "ok: small runs of one binary: no false alarm in 5 pairs; without repetitions refused in one line; 60% slower found"

run baseline "$root/results/latest/bench.json.gz" "$root/results/latest/bench.json.gz"
[ "$rc" = 0 ] || fail "the committed baseline against itself exits $rc"
echo "ok: the latest committed run against itself passes"
