# shellcheck shell=bash
# Sourced by test_bisect.sh and test_regress.sh: make_fake_repo DIR makes a git repository of 9
# commits whose "heightmarch-bench" (a script CMake writes at build time, carrying its commit as
# heightmarch's binaries do) speaks heightmarch-bench's flags and prints Google Benchmark JSON whose
# time per trace is 1000 / SPEED ms (SPEED from speed.txt: 1000, and 800 from commit 6 on, the
# planted 20% slow-down) with 0.5% of noise.
# For the tests of signals, two hooks hang on purpose, writing the PIDs that must not outlive the
# tool to the file the variable names:
# - FAKE_BUILD_HANG=FILE: building heightmarch-bench hangs (a shell and its sleep);
# - FAKE_BENCH_HANG=FILE: the benchmark hangs (itself and its sleep), at the commit whose step.txt
#   is FAKE_BENCH_HANG_AT (any commit when that is unset).
# Sets planted to the commit of the slow-down.
make_fake_repo() {
  mkdir -p "$1" && cd "$1" || return
  git init -q && git config user.email test@example.com && git config user.name test
  echo "build/" > .gitignore  # as in heightmarch: the build cache lives under build/
  cat > CMakeLists.txt <<'CMAKE'
cmake_minimum_required(VERSION 3.16)
project(fake NONE)
file(READ ${CMAKE_SOURCE_DIR}/speed.txt SPEED)
string(STRIP "${SPEED}" SPEED)
file(READ ${CMAKE_SOURCE_DIR}/step.txt STEP)
string(STRIP "${STEP}" STEP)
# The commit it is built from, carried as heightmarch's binaries carry theirs (regress's cache checks it)
execute_process(COMMAND git -C ${CMAKE_SOURCE_DIR} rev-parse --short=12 HEAD OUTPUT_VARIABLE COMMIT
                OUTPUT_STRIP_TRAILING_WHITESPACE)
configure_file(bench.in ${CMAKE_BINARY_DIR}/heightmarch-bench @ONLY FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE)
add_custom_target(heightmarch-bench COMMAND sh -c
  "if [ -n \"$FAKE_BUILD_HANG\" ]; then sleep 300 & echo $$ $! >> \"$FAKE_BUILD_HANG\"; wait; fi" VERBATIM)
CMAKE
  cat > bench.in <<'BENCH'
#!/usr/bin/env bash
# built from commit @COMMIT@
names="BM_Trace/heightfield:bricks/technique:pom/layers:32/isa:avx2/threads:1/view:512x512/depth_map:512x512/manual_time"
for arg in "$@"; do
  case "$arg" in
    --benchmark_list_tests=true) echo "$names"; exit 0 ;;
    --benchmark_*|--hm_*) ;;
    *) echo "unknown option $arg" >&2; exit 2 ;;
  esac
done
if [ -n "${FAKE_BENCH_HANG:-}" ] && [ "${FAKE_BENCH_HANG_AT:-@STEP@}" = @STEP@ ]; then
  sleep 300 & echo $$ $! >> "$FAKE_BENCH_HANG"; wait
fi
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
  # shellcheck disable=SC2034  # planted is for the tests that source this
  planted="$(git rev-parse HEAD~3)"
}

# wait_for_pids FILE: waits (at most 60 s) until FILE names the processes of a hang.
wait_for_pids() {
  local i
  for i in $(seq 600); do
    [ -s "$1" ] && return 0
    sleep 0.1
  done
  echo "FAIL: no hang reached within 60 s"; return 1
}

# interrupted PID PIDS_FILE: sends SIGTERM to the tool PID once its hang is reached, waits for it,
# and checks it exited 143 and that no process of PIDS_FILE runs any more.
interrupted() {
  local rc=0 p
  wait_for_pids "$2"
  kill -TERM "$1"
  wait "$1" || rc=$?
  [ "$rc" = 143 ] || { echo "FAIL: exit $rc after SIGTERM, not 143"; return 1; }
  sleep 0.2
  for p in $(cat "$2"); do
    if kill -0 "$p" 2>/dev/null; then echo "FAIL: process $p ($(ps -o args= -p "$p")) outlived the tool"; return 1; fi
  done
}
