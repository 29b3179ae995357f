#!/usr/bin/env bash
# An interrupted run never enters the history: a recorded quick suite (--record) sent SIGTERM
# while its report draws the plots passes the signal to the report (its own process group), both
# end (143), the report says so in one line with no traceback, the run stays INCOMPLETE and
# results/history.csv gets no row; a suite killed outright (SIGKILL) takes its report with it
# (parent-death signal), again with no history row. A third run, left alone, is recorded. A small
# quick plan (POM, the matrix): about 20 s.
# Usage: test_interrupted_run.sh BUILD_DIR
set -euo pipefail
build="$(cd "${1:?usage: test_interrupted_run.sh BUILD_DIR}" && pwd)"
tmp="$(mktemp -d)"
suite=""
trap '[ -z "$suite" ] || kill -KILL "$suite" 2>/dev/null; rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; cat "$tmp/out" 2>/dev/null || true; exit 1; }
cd "$tmp"

# Starts a recorded quick suite and waits (at most 120 s) until its report has started drawing
# (the run's plots/ exists); sets suite, report (the report's pid) and run.
start_until_report() {
  "$build/heightmarch" suite --quick --techniques pom --parts matrix --record > "$tmp/out" 2>&1 &
  suite=$!
  report=""
  for _ in $(seq 2400); do
    run="$(ls -d "$tmp"/results/*-quick 2>/dev/null | tail -1 || true)"
    report="$(pgrep -P "$suite" -f heightmarch_tools || true)"
    [ -n "$report" ] && [ -n "$run" ] && [ -d "$run/plots" ] && return 0
    kill -0 "$suite" 2>/dev/null || fail "the suite ended before its report started"
    sleep 0.05
  done
  fail "the report did not start within 120 s"
}

history_rows() { [ -e "$tmp/results/history.csv" ] && tail -n +2 "$tmp/results/history.csv" | wc -l || echo 0; }

start_until_report
kill -TERM "$suite"
rc=0
wait "$suite" || rc=$?
suite=""
[ "$rc" = 143 ] || fail "the suite sent SIGTERM exited $rc, not 143"
! kill -0 "$report" 2>/dev/null || fail "the report ($report) outlived its suite"
grep -q "^report: interrupted (SIGTERM)$" "$tmp/out" || fail "the report did not say it was interrupted"
! grep -q Traceback "$tmp/out" || fail "a traceback reached the user"
[ -e "$run/INCOMPLETE" ] || fail "the interrupted run does not say INCOMPLETE"
[ "$(history_rows)" = 0 ] || fail "the interrupted run entered the history"
echo "ok: SIGTERM during the report reaches it, one line each, the run stays INCOMPLETE, no history row"

sleep 1  # a fresh run directory (its name has the second)
start_until_report
kill -KILL "$suite"
{ wait "$suite"; } 2>/dev/null || true  # bash would say "Killed"
suite=""
for _ in $(seq 200); do kill -0 "$report" 2>/dev/null || break; sleep 0.05; done
! kill -0 "$report" 2>/dev/null || fail "the report ($report) outlived its SIGKILLed suite"
[ "$(history_rows)" = 0 ] || fail "the killed run entered the history"
echo "ok: a SIGKILLed suite takes its report with it; no history row"

sleep 1
"$build/heightmarch" suite --quick --techniques pom --parts matrix --record > "$tmp/out" 2>&1 || fail "the third suite"
[ "$(history_rows)" -gt 0 ] && [ "$(tail -n +2 "$tmp/results/history.csv" | cut -d, -f1,2 | sort -u | wc -l)" = 1 ] \
  || fail "the completed run is not the one run in the history"
echo "ok: the run left alone is recorded, alone"
