#!/usr/bin/env bash
# scripts/bisect over a synthetic repository of 9 commits whose "heightmarch-bench" (a CMake-built
# script) reports rays/s from a number in its source: the commit that plants a 20% slow-down is
# found and printed with its figures; a range without one ends "nothing to find" (exit 1); bad
# arguments exit 2 with one line. Needs no build of heightmarch.
# Usage: test_bisect.sh [BUILD_DIR] (unused)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; cat "$tmp/out" "$tmp/err" 2>/dev/null | tail -30; exit 1; }

repo="$tmp/repo"
mkdir -p "$repo" && cd "$repo"
git init -q && git config user.email test@example.com && git config user.name test
# The fake benchmark: lists its names, rejects unknown flags, prints Google Benchmark JSON whose
# time per trace is 1000 / SPEED ms (SPEED from speed.txt at build time) with 0.5% of noise.
cat > CMakeLists.txt <<'CMAKE'
cmake_minimum_required(VERSION 3.16)
project(fake NONE)
file(READ ${CMAKE_SOURCE_DIR}/speed.txt SPEED)
string(STRIP "${SPEED}" SPEED)
configure_file(bench.in ${CMAKE_BINARY_DIR}/heightmarch-bench @ONLY FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE)
add_custom_target(heightmarch-bench)
CMAKE
cat > bench.in <<'BENCH'
#!/usr/bin/env bash
names="BM_Trace/heightfield:bricks/technique:pom/layers:32/isa:avx2/threads:1/view:512x512/depth_map:512x512/manual_time"
for arg in "$@"; do
  case "$arg" in
    --benchmark_list_tests=true) echo "$names"; exit 0 ;;
    --benchmark_*|--hm_*) ;;
    *) echo "unknown option $arg" >&2; exit 2 ;;
  esac
done
time="$(awk -v s=@SPEED@ -v r=$RANDOM 'BEGIN { printf "%.6f", 1000 / (s * (1 + r / 32768 / 200)) }')"
printf '{"context": {}, "benchmarks": [{"name": "%s", "run_name": "%s", "run_type": "iteration", "iterations": 1, "real_time": %s, "cpu_time": %s, "time_unit": "ms"}]}\n' \
  "$names" "$names" "$time" "$time"
BENCH
for i in 1 2 3 4 5 6 7 8 9; do
  speed=1000; [ "$i" -ge 6 ] && speed=800   # commit 6 plants the slow-down
  echo "$speed" > speed.txt
  echo "$i" > step.txt
  git add -A && git commit -qm "commit $i"
done
planted="$(git rev-parse HEAD~3)"

rc=0
"$root/scripts/bisect" HEAD~8 HEAD --runs 5 > "$tmp/out" 2> "$tmp/err" || rc=$?
[ "$rc" = 0 ] || fail "bisect exited $rc"
grep -q "^bisect: first slower commit: $planted commit 6$" "$tmp/out" || fail "the planted commit is not found"
grep -Eq "threads:1 +0\.(79|80)[0-9] .*REGRESSION" "$tmp/out" || fail "its figures are not printed"
git -C "$repo" worktree list | grep -qv "$repo " && fail "a worktree was left behind"
[ -z "$(git -C "$repo" status --porcelain)" ] && [ "$(git -C "$repo" rev-parse HEAD)" = "$(git -C "$repo" rev-parse master 2>/dev/null || git -C "$repo" rev-parse main)" ] \
  || fail "the checkout was touched"
echo "ok: bisect finds the commit that plants a 20% slow-down ($(grep -c '^bisect: timing' "$tmp/err") commits timed)"

rc=0
"$root/scripts/bisect" HEAD~8 HEAD~4 --runs 5 > "$tmp/out" 2> "$tmp/err" || rc=$?
[ "$rc" = 1 ] && grep -q "is not slower than GOOD HEAD~8 by the detector: nothing to find" "$tmp/out" || fail "a range without a slow-down: exit $rc"
echo "ok: a range without a slow-down: nothing to find (exit 1)"

for bad in "HEAD HEAD~2::is not an ancestor of BAD" "nope HEAD::unknown revision nope" "HEAD~2 HEAD --runs 0::--runs 0 is not in 1..1000"; do
  rc=0
  # shellcheck disable=SC2086
  "$root/scripts/bisect" ${bad%%::*} > "$tmp/out" 2> "$tmp/err" || rc=$?
  [ "$rc" = 2 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q -- "${bad##*::}" "$tmp/err" || fail "bisect ${bad%%::*}: exit $rc"
done
echo "ok: bad arguments exit 2 with one line"
