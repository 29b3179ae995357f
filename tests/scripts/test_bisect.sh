#!/usr/bin/env bash
# scripts/bisect over a synthetic repository of 9 commits whose "heightmarch-bench" (a CMake-built
# script) reports rays/s from a number in its source (fake_bench_repo.sh): the commit that plants a
# 20% slow-down is found and printed with its figures and the verdict line; a range without one
# ends "nothing to find" (exit 1); bad arguments exit 2 with one line; SIGTERM while a bisect step
# times a commit leaves no worktree, no bisect state and no running child. Needs no build of
# heightmarch; about 30 s.
# Usage: test_bisect.sh [BUILD_DIR] (unused)
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
fail() { echo "FAIL: $*"; cat "$tmp/out" "$tmp/err" 2>/dev/null | tail -30; exit 1; }

# shellcheck source=tests/scripts/fake_bench_repo.sh
. "$root/tests/scripts/fake_bench_repo.sh"
repo="$tmp/repo"
make_fake_repo "$repo"

rc=0
"$root/scripts/bisect" HEAD~8 HEAD --runs 5 > "$tmp/out" 2> "$tmp/err" || rc=$?
[ "$rc" = 0 ] || fail "bisect exited $rc"
grep -q "^bisect: first slower commit: $planted commit 6$" "$tmp/out" || fail "the planted commit is not found"
grep -Eq "threads:1 +0\.(79|80)[0-9] .*REGRESSION" "$tmp/out" || fail "its figures are not printed"
[ "$(tail -1 "$tmp/out")" = "REGRESSION: first slower commit ${planted:0:7} commit 6" ] || fail "the last line is not the verdict"
git -C "$repo" worktree list | grep -qv "$repo " && fail "a worktree was left behind"
[ -z "$(git -C "$repo" status --porcelain)" ] && [ "$(git -C "$repo" rev-parse HEAD)" = "$(git -C "$repo" rev-parse master 2>/dev/null || git -C "$repo" rev-parse main)" ] \
  || fail "the checkout was touched"
echo "ok: bisect finds the commit that plants a 20% slow-down ($(grep -c '^bisect: timing' "$tmp/err") commits timed)"

rc=0
"$root/scripts/bisect" HEAD~8 HEAD~4 --runs 5 > "$tmp/out" 2> "$tmp/err" || rc=$?
[ "$rc" = 1 ] && grep -q "is not slower than GOOD HEAD~8 by the detector: nothing to find" "$tmp/out" || fail "a range without a slow-down: exit $rc"
tail -1 "$tmp/out" | grep -q "^no regression: BAD HEAD~4 is not slower" || fail "no verdict line"
echo "ok: a range without a slow-down: nothing to find (exit 1)"

for bad in "HEAD HEAD~2::is not an ancestor of BAD" "nope HEAD::unknown revision nope" "HEAD~2 HEAD --runs 0::--runs 0 is not in 1..1000" \
    "HEAD~2 HEAD --build $tmp/mistyped::--build $tmp/mistyped: no such directory"; do
  rc=0
  # shellcheck disable=SC2086
  "$root/scripts/bisect" ${bad%%::*} > "$tmp/out" 2> "$tmp/err" || rc=$?
  [ "$rc" = 2 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q -- "${bad##*::}" "$tmp/err" || fail "bisect ${bad%%::*}: exit $rc"
done
[ ! -e "$tmp/mistyped" ] || fail "a mistyped --build was made"
echo "ok: bad arguments exit 2 with one line (a mistyped --build is refused, not made)"

# SIGTERM while `git bisect run` times commit 5 (its first step, in a hung benchmark): bisect exits
# 143, ends the step and the benchmark in it, and leaves no worktree and no bisect in progress.
mkdir "$tmp/t"  # its temporary directories: none may be left
TMPDIR="$tmp/t" FAKE_BENCH_HANG="$tmp/pids" FAKE_BENCH_HANG_AT=5 "$root/scripts/bisect" HEAD~8 HEAD --runs 5 > "$tmp/out" 2> "$tmp/err" &
interrupted $! "$tmp/pids" || fail "SIGTERM during a bisect step"
[ "$(tail -1 "$tmp/err")" = "bisect: interrupted (SIGTERM)" ] && grep -q "^bisect: stopping: " "$tmp/err" && ! grep -q Traceback "$tmp/err" || fail "no one-line message"
[ "$(git -C "$repo" worktree list | wc -l)" = 1 ] || fail "a worktree was left: $(git -C "$repo" worktree list)"
[ -z "$(ls -A "$tmp/t")" ] || fail "left in TMPDIR: $(ls -A "$tmp/t")"
echo "ok: SIGTERM during a bisect step: exit 143, no worktree, no running child, nothing left"

