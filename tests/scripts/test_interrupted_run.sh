#!/usr/bin/env bash
# An interrupted run never enters the history, and a recorded one is never said to be interrupted:
# - a recorded quick suite (--record) sent SIGTERM while its first report (the one before the run is
#   complete) draws the plots passes the signal to the report (its own process group), both end
#   (143), the report says so in one line with no traceback, the run stays INCOMPLETE and
#   results/history.csv gets no row;
# - a suite killed outright (SIGKILL) takes its report with it (parent-death signal), again with
#   no history row;
# - Ctrl-C (SIGINT) at the moment the recording report has renamed the history into place (an
#   LD_PRELOAD shim sends it from the rename itself): the run is recorded once, both processes say
#   the signal came after the record, and the suite exits 0 with results/latest moved;
# - a run left alone is recorded.
# Each signal lands at a point the test holds still: the report is stopped (SIGSTOP) once it draws,
# known to be the first report by its command line, and let go once the signal is on its way; so
# the load of the machine cannot move the signal to the wrong report. A small quick plan (POM, the
# matrix): about 30 s.
# Usage: test_interrupted_run.sh BUILD_DIR
set -euo pipefail
build="$(cd "${1:?usage: test_interrupted_run.sh BUILD_DIR}" && pwd)"
tmp="$(mktemp -d)"
suite="" report=""
trap '[ -z "$report" ] || kill -CONT "$report" 2>/dev/null; [ -z "$suite" ] || kill -KILL "$suite" 2>/dev/null; rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; cat "$tmp/out" 2>/dev/null || true; exit 1; }
cd "$tmp"

# Starts a recorded quick suite and waits (at most 120 s) until its first report has started
# drawing (the run's plots/ exists), then stops that report; sets suite, report (the report's pid,
# stopped) and run. A report caught with --history is the second (the first ended meanwhile): it is
# let go, and the whole is tried again.
start_until_report() {
  for _ in 1 2 3; do
    "$build/heightmarch" suite --quick --techniques pom --parts matrix --record > "$tmp/out" 2>&1 &
    suite=$!
    report=""
    for _ in $(seq 2400); do
      run="$(ls -d "$tmp"/results/*-quick 2>/dev/null | tail -1 || true)"
      report="$(pgrep -P "$suite" -f heightmarch_tools || true)"
      if [ -n "$report" ] && [ -n "$run" ] && [ -d "$run/plots" ]; then
        kill -STOP "$report"
        tr '\0' ' ' < "/proc/$report/cmdline" | grep -q -- "--history" || return 0
        kill -CONT "$report"
        report=""
        wait "$suite" || true
        suite=""
        sleep 1  # a fresh run directory (its name has the second)
        continue 2
      fi
      kill -0 "$suite" 2>/dev/null || fail "the suite ended before its report started"
      sleep 0.05
    done
    fail "the report did not start within 120 s"
  done
  fail "three times the first report ended before it was caught"
}

history_rows() { [ -e "$tmp/results/history.csv" ] && tail -n +2 "$tmp/results/history.csv" | wc -l || echo 0; }

start_until_report
kill -TERM "$suite"  # passed on to the stopped report: pending until it goes on
kill -CONT "$report"
rc=0
wait "$suite" || rc=$?
suite=""
[ "$rc" = 143 ] || fail "the suite sent SIGTERM exited $rc, not 143"
for _ in $(seq 200); do kill -0 "$report" 2>/dev/null || break; sleep 0.05; done
! kill -0 "$report" 2>/dev/null || fail "the report ($report) outlived its suite"
report=""
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
kill -CONT "$report" 2>/dev/null || true  # its parent-death signal is pending
for _ in $(seq 200); do kill -0 "$report" 2>/dev/null || break; sleep 0.05; done
! kill -0 "$report" 2>/dev/null || fail "the report ($report) outlived its SIGKILLed suite"
report=""
[ "$(history_rows)" = 0 ] || fail "the killed run entered the history"
echo "ok: a SIGKILLed suite takes its report with it; no history row"

# Ctrl-C at the moment after the history row is written: the shim renames, then sends SIGINT to
# the report's parent, the suite (a terminal's Ctrl-C reaches the suite's group, which passes it
# on), and to the report itself (the suite's pass may reach it only once it has ended).
cat > "$tmp/after_rename.c" <<'C'
#define _GNU_SOURCE
#include <dlfcn.h>
#include <signal.h>
#include <string.h>
#include <unistd.h>
static int after(const char* to, int rc) {
  const char* base = strrchr(to, '/');
  if (rc == 0 && strcmp(base ? base + 1 : to, "history.csv") == 0) {
    kill(getppid(), SIGINT);
    kill(getpid(), SIGINT);
  }
  return rc;
}
int rename(const char* from, const char* to) {
  int (*real)(const char*, const char*) = (int (*)(const char*, const char*))dlsym(RTLD_NEXT, "rename");
  return after(to, real(from, to));
}
int renameat(int from_dir, const char* from, int to_dir, const char* to) {
  int (*real)(int, const char*, int, const char*) =
      (int (*)(int, const char*, int, const char*))dlsym(RTLD_NEXT, "renameat");
  return after(to, real(from_dir, from, to_dir, to));
}
C
cc -shared -fPIC -o "$tmp/after_rename.so" "$tmp/after_rename.c" -ldl || fail "cannot build the rename shim"
sleep 1
rc=0
LD_PRELOAD="$tmp/after_rename.so" "$build/heightmarch" suite --quick --techniques pom --parts matrix --record \
  > "$tmp/out" 2>&1 || rc=$?
run="$(ls -d "$tmp"/results/*-quick | tail -1)"
[ "$rc" = 0 ] || fail "Ctrl-C right after the history row was written: exit $rc, not 0"
[ "$(tail -n +2 "$tmp/results/history.csv" | cut -d, -f1,2 | sort -u | wc -l)" = 1 ] || fail "not one run in the history"
grep -q "^report: SIGINT came after the run was recorded in results/history.csv: it is complete and recorded$" "$tmp/out" &&
  grep -q "^suite: SIGINT came after the run was recorded in results/history.csv: it is complete and recorded$" "$tmp/out" ||
  fail "no line saying the signal came after the record"
[ ! -e "$run/INCOMPLETE" ] && [ "$(readlink "$tmp/results/latest")" = "$(basename "$run")" ] ||
  fail "the recorded run is INCOMPLETE, or results/latest does not point at it"
! grep -q Traceback "$tmp/out" || fail "a traceback reached the user"
echo "ok: Ctrl-C right after the history row is written: exit 0, recorded once, each process says the signal came after"

sleep 1
"$build/heightmarch" suite --quick --techniques pom --parts matrix --record > "$tmp/out" 2>&1 || fail "the last suite"
[ "$(tail -n +2 "$tmp/results/history.csv" | cut -d, -f1,2 | sort -u | wc -l)" = 2 ] \
  || fail "the run left alone is not recorded beside the first"
echo "ok: the run left alone is recorded"
