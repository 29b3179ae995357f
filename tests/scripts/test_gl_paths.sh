#!/usr/bin/env bash
# Either GL library alone builds the GLSL worker: built with OSMesa hidden (HEIGHTMARCH_WITH_OSMESA
# =OFF, as on a Mesa of 25.1 or later, which has no OSMesa), it links EGL alone, CMake's summary
# says so, EGL is its default path, and the GLSL tests (glsl, worker, watchdog, conformance) pass
# through it. Only the worker is built again: the tool and the test binary of BUILD_DIR load no GL
# library (test_no_gl_in_core.sh) and reach GLSL through $HEIGHTMARCH_GLSL_WORKER, so with this
# worker they are what an OSMesa-less build makes. Costs about 35 s of CPU to build (no kernel is
# compiled) and 40 s of wall time for the tests, the watchdog's (waiting on its bounds) beside the rest.
# Usage: test_gl_paths.sh BUILD_DIR
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="$(cd "${1:?usage: $0 BUILD_DIR}" && pwd)"
egl="$build/egl-only"
cache() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }
cmake -S "$root" -B "$egl" -DCMAKE_BUILD_TYPE=Release -DHEIGHTMARCH_WITH_OSMESA=OFF -DHEIGHTMARCH_BUILD_CLI=OFF \
  -DHEIGHTMARCH_BUILD_BENCHMARKS=OFF -DHEIGHTMARCH_BUILD_TESTS=OFF -DCMAKE_CXX_COMPILER="$(cache CMAKE_CXX_COMPILER)" \
  -DCMAKE_CXX_COMPILER_LAUNCHER="$(cache CMAKE_CXX_COMPILER_LAUNCHER)" > "$egl.log" 2>&1 ||
  { cat "$egl.log"; echo "FAIL: the worker does not configure with OSMesa hidden"; exit 1; }
grep -q "heightmarch GLSL worker: EGL alone" "$egl.log" ||
  { cat "$egl.log"; echo "FAIL: CMake's summary does not say the worker has EGL alone"; exit 1; }
cmake --build "$egl" --target heightmarch-glsl-worker -j "$(nproc)" > "$egl-build.log" 2>&1 ||
  { tail -30 "$egl-build.log"; echo "FAIL: the worker does not build with OSMesa hidden"; exit 1; }
worker="$egl/heightmarch-glsl-worker"
# Read whole first: ldd writes a line at a time, and under pipefail `ldd | grep -q` fails when
# grep has matched and left before ldd's next line (SIGPIPE), as it did now and then.
libs="$(ldd "$worker")"
if grep -qi osmesa <<<"$libs" || ! grep -q libEGL <<<"$libs"; then
  echo "$libs"
  echo "FAIL: the worker built with OSMesa hidden does not link EGL alone"
  exit 1
fi
echo "ok: with OSMesa hidden the worker configures (its summary says EGL alone), builds and links EGL alone"

export HEIGHTMARCH_GLSL_WORKER="$worker"
out="$("$build/heightmarch" glsl --res 64 --size 64x64 --threads 1 --repetitions 1)"
grep -q "^GLSL through EGL on llvmpipe" <<<"$out" || { echo "$out"; echo "FAIL: its default path is not EGL"; exit 1; }
status=0
out="$("$build/heightmarch" glsl --gl osmesa --size 8x8 2>&1)" || status=$?
if [ "$status" != 2 ] || [ "$(wc -l <<<"$out")" != 1 ] || ! grep -q "built without OSMesa" <<<"$out"; then
  echo "$out (exit $status)"
  echo "FAIL: --gl osmesa on a worker without it is not one line and exit 2"
  exit 1
fi
echo "ok: its default path is EGL; --gl osmesa says in one line that it was built without"
# The watchdog's tests mostly wait on its bounds: they run beside the others.
"$build/heightmarch-tests" --gtest_filter='GlslWatchdog*' --gtest_brief=1 > "$egl-watchdog.log" 2>&1 &
watchdog=$!
"$build/heightmarch-tests" --gtest_filter='Glsl*:-GlslWatchdog*' --gtest_brief=1 ||
  { wait "$watchdog" || true; echo "FAIL: the GLSL tests fail through the EGL-only worker"; exit 1; }
wait "$watchdog" || { cat "$egl-watchdog.log"; echo "FAIL: the GLSL watchdog's tests fail through the EGL-only worker"; exit 1; }
tail -1 "$egl-watchdog.log"
echo "ok: the GLSL tests pass through the worker built with EGL alone"
