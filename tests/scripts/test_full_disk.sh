#!/usr/bin/env bash
# A full disk never leaves a broken file under its final name nor a temporary behind: trace --out,
# heightmarch-bench --benchmark_out and suite --out on a 100 KB tmpfs (as root), else under a
# 100 KB file size limit (ulimit -f, with SIGXFSZ ignored so a write fails with EFBIG instead),
# each exit non-zero with one line naming the file and the system's reason.
# Usage: test_full_disk.sh BUILD_DIR
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
tmp="$(mktemp -d)"
mounted=0
cleanup() { [ "$mounted" = 1 ] && umount "$tmp/disk"; rm -rf "$tmp"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }

mkdir "$tmp/disk"
limit=""
if [ "$(id -u)" = 0 ] && mount -t tmpfs -o size=100k tmpfs "$tmp/disk" 2> /dev/null; then
  mounted=1
  echo "a 100 KB tmpfs"
else
  limit="ulimit -f 100; trap '' XFSZ;"
  echo "a 100 KB file size limit (no tmpfs here)"
fi

# run NAME COMMAND...: runs it under the limit, keeping NAME.out and the exit code in rc.
run() {
  local name="$1"; shift
  last="$name"; rc=0
  bash -c "$limit \"\$@\"" _ "$@" > "$tmp/$name.out" 2>&1 || rc=$?
}
no_temporaries() {
  local left
  left="$(find "$tmp/disk" -name '*.tmp-*' -o -name '*.tmp')"
  [ -z "$left" ] || fail "$last left temporaries: $left"
}

run trace "$build/heightmarch" trace --res 64 --size 512x512 --out "$tmp/disk/trace"
[ "$rc" = 1 ] || fail "trace --out on a full disk exits $rc: $(cat "$tmp/trace.out")"
grep -q "cannot write" "$tmp/trace.out" && [ "$(wc -l < "$tmp/trace.out")" = 1 ] || fail "trace: not one line: $(cat "$tmp/trace.out")"
no_temporaries
echo "ok: trace --out: exit 1, $(cat "$tmp/trace.out")"
rm -rf "${tmp:?}/disk/"*

# rays.csv is written through a buffer, piece by piece: the same guarantees.
{ echo "tx,ty,vx,vy,vz"; for i in $(seq 1 20000); do echo "0.$i,0.5,0.6,0,0.8"; done; } > "$tmp/rays.csv"
run rays "$build/heightmarch" trace --res 64 --rays "$tmp/rays.csv" --out "$tmp/disk/rays"
[ "$rc" = 1 ] || fail "trace --rays --out on a full disk exits $rc: $(cat "$tmp/rays.out")"
grep -q "rays.csv: cannot write" "$tmp/rays.out" && [ "$(wc -l < "$tmp/rays.out")" = 1 ] || fail "rays: not one line: $(cat "$tmp/rays.out")"
[ ! -e "$tmp/disk/rays/rays.csv" ] || fail "trace --rays left a broken rays.csv"
no_temporaries
echo "ok: trace --rays --out: exit 1, $(cat "$tmp/rays.out")"
rm -rf "${tmp:?}/disk/"*

if [ -x "$build/heightmarch-bench" ]; then
  head -c 90000 /dev/zero > "$tmp/disk/filler" 2> /dev/null || true
  run bench "$build/heightmarch-bench" --hm_size=64 --hm_res=32 --hm_heightfields=bricks --hm_layers=4,8,16,32 \
    --hm_isas=scalar --hm_threads=1 --hm_min_time=0.001 --benchmark_repetitions=30 --benchmark_out="$tmp/disk/bench.json"
  [ "$rc" = 1 ] || fail "heightmarch-bench on a full disk exits $rc"
  grep -q "heightmarch-bench: $tmp/disk/bench.json: cannot write" "$tmp/bench.out" || fail "bench: $(tail -3 "$tmp/bench.out")"
  [ ! -e "$tmp/disk/bench.json" ] || fail "heightmarch-bench left a broken bench.json"
  no_temporaries
  echo "ok: heightmarch-bench --benchmark_out: exit 1, no bench.json, $(tail -1 "$tmp/bench.out")"
  rm -rf "${tmp:?}/disk/"*
fi

# One repetition: what a run writes, and where the disk runs out, does not depend on how often
# each row is timed.
run suite "$build/heightmarch" suite --quick --no-glsl --repetitions 1 --out "$tmp/disk/run"
[ "$rc" = 1 ] || fail "suite on a full disk exits $rc: $(tail -3 "$tmp/suite.out")"
tail -1 "$tmp/suite.out" | grep -q "cannot write" || fail "suite: $(tail -3 "$tmp/suite.out")"
for f in measurements.json.gz bench.json.gz report.md; do [ ! -e "$tmp/disk/run/$f" ] || fail "suite left $f"; done
no_temporaries
echo "ok: suite --out: exit 1, INCOMPLETE kept, no temporaries, $(tail -1 "$tmp/suite.out")"
