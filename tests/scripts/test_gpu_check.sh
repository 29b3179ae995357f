#!/usr/bin/env bash
# scripts/gpu_check on llvmpipe (--gl-device software: the GPU's code path, minus the GPU), quick:
# it lists EGL's devices, holds each technique it checks against the CPU, times them through
# heightmarch-bench on the device, and writes its run directory with the report naming the
# renderer; without a GPU and without --gl-device it says so in one line. About 10 s.
# Usage: test_gpu_check.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
build="$(cd "${1:?usage: $0 BUILD_DIR}" && pwd)"

status=0
out="$("$root/scripts/gpu_check" --quick --build "$build" --out "$tmp/none" 2>&1)" || status=$?
[ "$status" = 2 ] && [ "$(wc -l <<<"$out")" = 1 ] && grep -q "EGL lists no GPU" <<<"$out" ||
  fail "without a GPU and --gl-device the check does not say so in one line, exit 2: $out (exit $status)"
echo "ok: without a GPU it says so in one line"

"$root/scripts/gpu_check" --gl-device software --quick --build "$build" --out "$tmp/run" > "$tmp/log" 2>&1 ||
  { cat "$tmp/log"; fail "gpu_check --gl-device software --quick failed"; }
run="$tmp/run"
for f in devices.txt conformance.json bench.json report.md; do [ -s "$run/$f" ] || fail "no $f"; done
grep -q "^0	software	llvmpipe" "$run/devices.txt" || fail "devices.txt lists no software device"
/usr/bin/python3 - "$run" <<'PY' || fail "conformance.json or bench.json"
import json, sys
run = sys.argv[1]
records = json.load(open(run + "/conformance.json"))
assert {r["technique"] for r in records} == {"pom", "maxmip"}, records
for r in records:
    assert r["gl"]["path"] == "egl" and r["gl"]["device"] == "software" and "llvmpipe" in r["gl"]["renderer"], r["gl"]
    # llvmpipe against the CPU: the same sample counts, uv within its filter's last bit
    assert r["identical_sample_counts"] >= 0.999 and r["uv_difference_p99"] < 1e-3, r
bench = json.load(open(run + "/bench.json"))
medians = [b for b in bench["benchmarks"] if b.get("aggregate_name") == "median"]
assert len(medians) == 2 and all("/gl:egl@software/view:64x64/" in b["run_name"] for b in medians), medians
assert all(b["gl_wall_seconds"] > 0 and "gl_timer_seconds" in b for b in medians), medians
PY
grep -q "^# heightmarch GPU check: glsl (llvmpipe, LLVM .*; EGL)" "$run/report.md" || fail "report.md's title names no renderer"
grep -q "^| pom | 100.00% |" "$run/report.md" || fail "report.md has no conformance row for pom"
grep -q "^| bricks | maxmip | 1 |" "$run/report.md" || fail "report.md has no timing row for maxmip"
echo "ok: on llvmpipe it lists the device, checks pom and maxmip against the CPU, times them and reports"
