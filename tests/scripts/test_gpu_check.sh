#!/usr/bin/env bash
# scripts/gpu_check on llvmpipe (--gl-device software: the GPU's code path, minus the GPU), quick:
# it lists EGL's devices, holds each technique it checks against the CPU, times them through
# heightmarch-bench on the device, and writes its run directory with the report naming the
# renderer; without a GPU and without --gl-device it says so in one line; a bad option, count or
# path is refused in one line before anything runs. About 15 s.
# Usage: test_gpu_check.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
build="$(cd "${1:?usage: $0 BUILD_DIR}" && pwd)"

# Every option checked before anything runs: each refused in one line, exit 2, within seconds, with
# nothing built (a mistyped --build never runs scripts/setup), created or timed.
refused() {
  local expected="$1" rc=0
  shift
  timeout 20 "$root/scripts/gpu_check" "$@" > "$tmp/out" 2> "$tmp/err" || rc=$?
  [ "$rc" = 2 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q -- "$expected" "$tmp/err" && [ ! -s "$tmp/out" ] ||
    fail "gpu_check $*: exit $rc, not 2 with one line naming '$expected': $(head -c 300 "$tmp/err")"
}
refused "argument --repetitions: -1 is not a whole number in 1..1000" --gl-device software --quick --build "$build" --repetitions -1
refused "argument --repetitions: 0 is not a whole number" --quick --build "$build" --repetitions 0
refused "argument --size: 0x0 is not WxH with sides in \[1, 16384\]" --quick --size 0x0 --build "$build"
refused "argument --size: 1920x is not WxH" --size 1920x --build "$build"
refused "argument --size: 99999x8 is not WxH" --quick --size 99999x8 --build "$build"
refused "^gpu_check: --build /mistyped/dir: no such directory$" --build /mistyped/dir
refused "^gpu_check: --build $tmp: holds no heightmarch, heightmarch-bench, heightmarch-glsl-worker: build it first" --build "$tmp"
refused "^gpu_check: --debs $tmp/none: no such directory$" --quick --build "$build" --debs "$tmp/none"
touch "$tmp/file" && mkdir "$tmp/full" && touch "$tmp/full/x"
refused "^gpu_check: --out $tmp/file: is not a directory$" --quick --build "$build" --out "$tmp/file"
refused "^gpu_check: --out $tmp/full: holds files already" --quick --build "$build" --out "$tmp/full"
refused "^gpu_check: --out $tmp/none/a: its parent $tmp/none is no directory$" --quick --build "$build" --out "$tmp/none/a"
[ ! -e "$tmp/none" ] && [ "$(ls "$tmp/full")" = x ] || fail "a refused call created or wrote something"
refused "^gpu_check: --gl-device D*\.\.\.\[[0-9]* characters cut\]\.\.\.D*: EGL lists software" \
  --quick --build "$build" --out "$tmp/long" --gl-device "$(head -c 10240 /dev/zero | tr '\0' D)"
[ "$(wc -c < "$tmp/err")" -le 1024 ] || fail "a 10 KB --gl-device is echoed in a line of $(wc -c < "$tmp/err") bytes"
echo "ok: 12 bad options refused in one line each before anything runs (no setup for a mistyped --build), a long echoed value cut"

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
