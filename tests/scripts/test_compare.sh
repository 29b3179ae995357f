#!/usr/bin/env bash
# scripts/compare on synthetic runs, one check per rule of its docstring: identical runs pass, a
# 30% slow-down is a named REGRESSION, no shared benchmark is unusable input (exit 2), benchmarks
# of one run only are listed, context differences are WARNINGs in the first lines, changed error
# measures are a BEHAVIOUR CHANGE, runs without repetitions fall back to the median change,
# names with min_time: match the new release's names, and input that is not Google Benchmark's
# shape exits 2 with one line; the speed rule keeps runs of the same code quiet while it flags a
# 10% slow-down of one family; the latest committed run passes against itself. Needs no build.
# Usage: test_compare.sh BUILD_DIR (unused)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# write_run FILE [SPEC_JSON]: a run of BM_Trace benchmarks. SPEC keys (all optional): techniques,
# reps, slow {technique: factor}, style "new" (view:/depth_map: in names) or "old" (min_time:),
# view, depth_map, cpu, build_type, counter_scale {counter: factor}.
write_run() {
  /usr/bin/python3 - "$1" "${2:-{\}}" <<'PY'
import json, sys
path, spec = sys.argv[1], json.loads(sys.argv[2])
reps, view, depth = spec.get("reps", 9), spec.get("view", "1024x1024"), spec.get("depth_map", "512x512")
benchmarks = []
for k, technique in enumerate(spec.get("techniques", ["pom", "steep"])):
    name = "BM_Trace/heightfield:bricks/technique:%s/layers:32/isa:avx2/threads:1/" % technique
    name += "min_time:0.200/real_time" if spec.get("style") == "old" else "view:%s/depth_map:%s/real_time" % (view, depth)
    counters = {"uv_error_mean": 0.5 + k, "uv_error_p95": 2.0 + k, "wrong_surface_rate": 0.01, "samples_per_ray": 20.0 + k}
    for counter, factor in spec.get("counter_scale", {}).items():
        counters[counter] *= factor
    times = [(40.0 + 10 * k) * (1 + 0.003 * ((rep * 7) % 5)) * spec.get("slow", {}).get(technique, 1.0) for rep in range(reps)]
    common = {"name": name, "run_name": name, "repetitions": reps, "threads": 1, "time_unit": "ms"}
    for rep, t in enumerate(times):
        benchmarks.append(dict(common, run_type="iteration", repetition_index=rep, iterations=10, real_time=t,
                               cpu_time=t, rays_per_second=1e6 / t, **counters))
    if reps > 1:  # aggregates, which compare must ignore
        for agg in ("mean", "median", "stddev", "cv"):
            benchmarks.append(dict(common, name=name + "_" + agg, run_type="aggregate", aggregate_name=agg,
                                   iterations=reps, real_time=1.0, cpu_time=1.0, **counters))
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
[ "$rc" = 0 ] && has "no speed regression" && has "error measures unchanged in 2" && ! has WARNING || fail "identical runs do not pass (exit $rc)"
echo "ok: identical runs pass (exit 0)"

write_run "$tmp/slow.json" '{"slow": {"pom": 1.3}}'
run slow "$tmp/old.json" "$tmp/slow.json"
[ "$rc" = 1 ] || fail "a 30% slow-down exits $rc, not 1"
grep "REGRESSION" "$tmp/slow.out" | grep -q "technique:pom" || fail "the slower benchmark is not named as a REGRESSION"
! grep "technique:steep" "$tmp/slow.out" | grep -q REGRESSION || fail "the unchanged benchmark is flagged"
has "SPEED REGRESSION: 1 benchmark" && ! has "BEHAVIOUR CHANGE" || fail "the summary does not say speed regression alone"
echo "ok: the 30% slower benchmark (9 repetitions, t-test) is a named REGRESSION, the unchanged one is not (exit 1)"

write_run "$tmp/other.json" '{"techniques": ["relief", "parallax"]}'
run unshared "$tmp/old.json" "$tmp/other.json"
[ "$rc" = 2 ] && [ "$(wc -l < "$tmp/unshared.err")" = 1 ] && has "share no benchmark" err || fail "no shared benchmark: exit $rc, not 2 with one line"
echo "ok: no shared benchmark exits 2 with one line: $(cat "$tmp/unshared.err")"

write_run "$tmp/partial.json" "{\"techniques\": [\"pom\", \"relief\", $(seq -s, -f '"t%g"' 1 24)]}"
run only_in "$tmp/old.json" "$tmp/partial.json"
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

write_run "$tmp/changed.json" '{"counter_scale": {"uv_error_mean": 1.001}}'
write_run "$tmp/rounded.json" '{"counter_scale": {"uv_error_mean": 1.0000000001}}'
run behaviour "$tmp/old.json" "$tmp/changed.json"
[ "$rc" = 1 ] && has "a BEHAVIOUR CHANGE:$" && has "^BEHAVIOUR CHANGE: error measures changed in 2 benchmark" && has "uv_error_mean 0.5 -> 0.5005" \
  && has "no speed regression" && has "^FAILED: behaviour change$" || fail "a changed error measure is not a BEHAVIOUR CHANGE (exit $rc)"
run rounding "$tmp/old.json" "$tmp/rounded.json"
[ "$rc" = 0 ] || fail "a change within the tolerance exits $rc"
echo "ok: a changed error counter is a BEHAVIOUR CHANGE apart from speed (exit 1); 1e-10 relative is not"

write_run "$tmp/once.json" '{"reps": 1}'
write_run "$tmp/once-slow.json" '{"reps": 1, "slow": {"pom": 1.3}}'
run no_reps "$tmp/once.json" "$tmp/once-slow.json"
[ "$rc" = 1 ] && has "judged on the median time change alone" && grep "technique:pom" "$tmp/no_reps.out" | grep -q "  -  *REGRESSION" \
  || fail "without repetitions: no fallback said, or the slow-down missed (exit $rc)"
echo "ok: without repetitions compare falls back to the median change and says so"

run min_time "$tmp/old-1024.json" "$tmp/old.json"
[ "$rc" = 0 ] && has "note: 2 benchmark(s) matched across name formats: /min_time: dropped, view:/depth_map: from OLD's context" \
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

# The speed rule on many benchmarks (compare's judge_speed, in-process): 20 pairs of synthetic runs of
# the same code (200 benchmarks in 10 families, 5 repetitions with 5% noise and a load spike now and
# then, the whole NEW run shifted by up to 10%) flag nothing in at least 19; a 10% slow-down of one
# family is flagged in each of 5 pairs, and no other family with it.
PYTHONPATH="$root/scripts" /usr/bin/python3 - "$root/scripts/compare" <<'PY' || exit 1
import argparse, importlib.machinery, importlib.util, random, sys
loader = importlib.machinery.SourceFileLoader("compare", sys.argv[1])
compare = importlib.util.module_from_spec(importlib.util.spec_from_loader("compare", loader))
loader.exec_module(compare)
rng = random.Random(22)
names = ["BM_Trace/heightfield:h%d/technique:t%d/layers:32/isa:avx2/threads:1" % (k, j) for j in range(10) for k in range(20)]
base = {n: rng.uniform(0.5, 20.0) for n in names}


def run(shift=1.0, slow=None):
    runs = {}
    for n in names:
        factor = shift * (1.1 if slow and "/technique:%s/" % slow in n else 1.0)
        runs[n] = [{"real_time": base[n] * factor * rng.lognormvariate(0, 0.05) * (1.3 if rng.random() < 0.1 else 1.0),
                    "time_unit": "ms"} for _ in range(5)]
    return runs


args = argparse.Namespace(threshold=0.05, fdr=0.05)
flagged = []
for _ in range(20):
    j = compare.judge_speed(run(), run(rng.uniform(0.9, 1.1)), names, args)
    flagged.append(sum(v[3] for v in j["benchmarks"].values()) + sum(v[3] for v in j["families"].values()))
if sum(f > 0 for f in flagged) > 1:
    sys.exit("FAIL: runs of the same code flag something in %d of 20 pairs: %s" % (sum(f > 0 for f in flagged), flagged))
for _ in range(5):
    j = compare.judge_speed(run(), run(rng.uniform(0.9, 1.1), slow="t3"), names, args)
    families = sorted(f for f, v in j["families"].items() if v[3])
    if families != ["BM_Trace/technique:t3"]:
        sys.exit("FAIL: a 10%% slow-down of family t3 flags the families %s" % families)
print("ok: 20 pairs of the same code flag nothing in %d; a 10%% slow-down of one family is flagged in 5 of 5, alone"
      % sum(f == 0 for f in flagged))
PY

run baseline "$root/results/latest/bench.json" "$root/results/latest/bench.json"
[ "$rc" = 0 ] || fail "the committed baseline against itself exits $rc"
echo "ok: the latest committed run against itself passes"
