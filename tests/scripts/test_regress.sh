#!/usr/bin/env bash
# scripts/regress checks its arguments before it builds anything: each bad argument exits 2 with
# one line naming it, within a second or two (no build, no worktree left behind). Then, on a
# synthetic repository, its build cache (and what it refuses to trust), progress, verdict line,
# --help and signals (below).
# About 30 s.
# Usage: test_regress.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
build="${1:-$root/build}"
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
refused $'\e]0;PWN\a\e[2J' :: 'unknown revision \\x1b\]0;PWN\\x07\\x1b\[2J'
! grep -q $'\e' "$tmp/err" || fail "a revision's escape bytes reached the terminal"
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
echo "ok: 13 bad arguments exit 2 with one line each, before anything is built (a revision's escape bytes made printable)"

# On the synthetic repository of fake_bench_repo.sh (its build/ is the current build, commit 9):
# regress builds REV once and then takes it from the cache, says what it does, and ends with its
# verdict line; SIGTERM while it builds REV or while a benchmark runs, and SIGINT, end it with
# 128 + the signal, no worktree, no running child and no traceback.
# shellcheck source=tests/scripts/fake_bench_repo.sh
. "$root/tests/scripts/fake_bench_repo.sh"
repo="$tmp/repo"
( make_fake_repo "$repo" && cmake -S "$repo" -B "$repo/build" > /dev/null )
cd "$repo"
rc=0
"$root/scripts/regress" HEAD~8 --runs 5 > "$tmp/out" 2> "$tmp/err" || rc=$?
[ "$rc" = 1 ] && grep -q "^regress: building .* commit 1 in a worktree" "$tmp/err" && grep -q "^regress: round 5/5" "$tmp/err" \
  && tail -1 "$tmp/out" | grep -Eq "^REGRESSION: 1 of 1 benchmarks slower by more than 1% \(slowest: .* at 0\.(79|80)[0-9] of OLD's speed\)$" \
  || fail "a 20% slower current build: exit $rc, or no progress or verdict line"
rc=0
"$root/scripts/regress" HEAD~8 --runs 5 > "$tmp/out" 2> "$tmp/err" || rc=$?
[ "$rc" = 1 ] && grep -q "^regress: cached build of .* commit 1" "$tmp/err" && ! grep -q "building .* in a worktree" "$tmp/err" \
  && grep -q "^regress: timing OLD .* about .* (the last run's rounds took" "$tmp/err" || fail "the second run did not use the cache (exit $rc)"
rc=0
"$root/scripts/regress" HEAD --runs 5 > "$tmp/out" 2> "$tmp/err" || rc=$?
[ "$rc" = 0 ] && tail -1 "$tmp/out" | grep -q "^no regression: none of 1 benchmarks slower by more than 1%$" || fail "an unchanged commit: exit $rc"
echo "ok: regress builds REV once, then takes it from the cache, says what it does and how long it has left, ends with its verdict line"

# The cache proves what it holds: a binary planted in REV's entry (its build.json left as it was) is
# never run, the entry is built again; an entry whose binary was built from another commit, its
# build.json and checksums forged to match, likewise. A regress-cache that links out of the build
# directory is refused in one line, nothing written through it.
entry="$(ls -d build/regress-cache/"$(git rev-parse --short=12 HEAD~8)"-*)"
printf '#!/bin/sh\ntouch "%s/planted-ran"; exit 0\n' "$tmp" > "$entry/heightmarch-bench"
rc=0
"$root/scripts/regress" HEAD~8 --runs 5 > "$tmp/out" 2> "$tmp/err" || rc=$?
[ "$rc" = 1 ] && [ ! -e "$tmp/planted-ran" ] && grep -q "^regress: the cached build in .* is not trusted (heightmarch-bench is not the file its build.json names)" "$tmp/err" \
  && grep -q "^regress: building .* commit 1 in a worktree" "$tmp/err" || fail "a planted binary in the cache: exit $rc, or it ran, or it was not built again"
other="$(ls -d build/regress-cache/"$(git rev-parse --short=12 HEAD)"-* 2>/dev/null || true)"
[ -z "$other" ] && "$root/scripts/regress" HEAD --runs 1 > /dev/null 2>&1 && other="$(ls -d build/regress-cache/"$(git rev-parse --short=12 HEAD)"-*)"
cp "$other/heightmarch-bench" "$entry/heightmarch-bench"  # HEAD's binary in HEAD~8's entry, its checksum forged
/usr/bin/python3 - "$entry" <<'PY'
import hashlib, json, sys
record = json.load(open(sys.argv[1] + "/build.json"))
record["checksums"]["heightmarch-bench"] = hashlib.sha256(open(sys.argv[1] + "/heightmarch-bench", "rb").read()).hexdigest()
json.dump(record, open(sys.argv[1] + "/build.json", "w"))
PY
rc=0
"$root/scripts/regress" HEAD~8 --runs 5 > "$tmp/out" 2> "$tmp/err" || rc=$?
[ "$rc" = 1 ] && grep -q "is not trusted (its heightmarch-bench was not built from $(git rev-parse --short=12 HEAD~8))" "$tmp/err" \
  || fail "another commit's binary with a forged build.json: exit $rc, or trusted"
mv build/regress-cache "$tmp/elsewhere" && ln -s "$tmp/elsewhere" build/regress-cache
before="$(cd "$tmp/elsewhere" && ls -lR --time-style=full-iso)"
rc=0
"$root/scripts/regress" HEAD~8 --runs 5 > "$tmp/out" 2> "$tmp/err" || rc=$?
[ "$rc" = 2 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q "regress-cache: is a link, not a directory" "$tmp/err" \
  && [ "$before" = "$(cd "$tmp/elsewhere" && ls -lR --time-style=full-iso)" ] || fail "a linked cache: exit $rc, or written through"
rm build/regress-cache && mv "$tmp/elsewhere" build/regress-cache
echo "ok: a planted binary, another commit's binary with a forged record and a linked cache are refused; nothing planted runs"

"$root/scripts/regress" --help > "$tmp/out"
grep -qF "BM_Trace/heightfield:bricks/technique:(pom|relief|steep)/layers:32/isa:(avx2|avx512)/threads:1/)" "$tmp/out" && grep -q "exits 128 + the signal's number" "$tmp/out" \
  && grep -q "(1..1000; default 20)" "$tmp/out" || fail "--help lacks the whole text or the defaults"
echo "ok: --help gives the whole description and every default"

# stopped SIGNAL EXIT HOOK ARGS...: regress ARGS with the hook set hangs; SIGNAL to it ends it with EXIT,
# no worktree, no running child, nothing in its TMPDIR or being stored in the cache, one line.
stopped() {
  local signal="$1" code="$2" hook="$3" rc=0 p
  shift 3
  rm -rf "$tmp/t" "$tmp/pids" && mkdir "$tmp/t"
  env TMPDIR="$tmp/t" "$hook=$tmp/pids" "$root/scripts/regress" "$@" > "$tmp/out" 2> "$tmp/err" &
  local pid=$!
  wait_for_pids "$tmp/pids" || fail "no hang"
  kill "-$signal" "$pid"
  wait "$pid" || rc=$?
  [ "$rc" = "$code" ] || fail "$hook, SIG$signal: exit $rc, not $code"
  sleep 0.2
  for p in $(cat "$tmp/pids"); do
    ! kill -0 "$p" 2>/dev/null || fail "$hook, SIG$signal: process $p ($(ps -o args= -p "$p")) outlived regress"
  done
  [ "$(tail -1 "$tmp/err")" = "regress: interrupted (SIG$signal)" ] && grep -q "^regress: stopping: " "$tmp/err" && ! grep -q Traceback "$tmp/err" || fail "$hook, SIG$signal: no one-line message"
  [ "$(git -C "$repo" worktree list | wc -l)" = 1 ] || fail "$hook, SIG$signal: a worktree was left"
  [ -z "$(ls -A "$tmp/t")" ] && ! ls -d "$repo"/build/regress-cache/.incoming-* 2> /dev/null || fail "$hook, SIG$signal: files were left"
}
stopped TERM 143 FAKE_BUILD_HANG HEAD~2
stopped TERM 143 FAKE_BENCH_HANG HEAD~8
stopped INT 130 FAKE_BENCH_HANG HEAD~8
echo "ok: SIGTERM while regress builds REV or times it, and SIGINT: exit 128 + the signal, no worktree, no running child, no traceback"
