#!/usr/bin/env bash
# scripts/regress checks its arguments before it builds anything: each bad argument exits 2 with
# one line naming it, within a second or two (no build, no worktree left behind).
# Usage: test_regress.sh BUILD_DIR
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="${1:-$root/build}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; cat "$tmp/err"; exit 1; }
# regress makes its worktrees under TMPDIR: here $tmp, so that one left behind is told apart from
# the worktrees other work on this repository holds meanwhile.
export TMPDIR="$tmp"

# refused ARGS... :: EXPECTED: regress exits 2 with one line on stderr holding EXPECTED
refused() {
  local args=() rc=0
  while [ "$1" != "::" ]; do args+=("$1"); shift; done
  "$root/scripts/regress" "${args[@]}" > "$tmp/out" 2> "$tmp/err" || rc=$?
  [ "$rc" = 2 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q -- "$2" "$tmp/err" && ! grep -q Traceback "$tmp/err" \
    || fail "regress ${args[*]}: exit $rc, not 2 with one line naming '$2'"
}
refused no-such-revision :: "unknown revision no-such-revision"
refused HEAD --runs 0 :: "--runs 0 is not in 1..1000"
refused HEAD --runs many :: "argument --runs: invalid int value"
refused HEAD --threshold 1.5 :: "--threshold 1.5 is not in (0, 1)"
refused HEAD --threshold nan :: "--threshold nan is not in (0, 1)"
refused HEAD --filter '(' :: "--filter ( is not a regular expression"
refused HEAD --filter '' :: "--filter is empty"
refused HEAD --frobnicate :: "unrecognized arguments: --frobnicate"
refused HEAD --runs :: "argument --runs: expected one argument"
refused HEAD --build "$tmp" :: "holds no heightmarch-bench"
refused HEAD --build "$build" --filter 'no-such-benchmark' :: "names no benchmark of the current build"
refused HEAD --build "$build" -- --hm_frobnicate=1 :: "refuses the benchmark flags: .*unknown option --hm_frobnicate"
git -C "$root" worktree list | grep -qF "$tmp/" && fail "a refused call left a worktree"
echo "ok: 12 bad arguments exit 2 with one line each, before anything is built"
