#!/usr/bin/env bash
# heightmarch as a CMake package: installs BUILD_DIR to a temporary prefix, checks that no
# build-tree or source-tree path reaches the installed package files, then builds tests/package
# against it with find_package(heightmarch) and runs its two programs (heightmarch::core on the
# CPU, heightmarch::glsl through the installed worker). Last, configures tests/package with
# heightmarch as a subdirectory (same aliases, no tool/benchmarks/tests by default).
# Usage: test_package.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
build="$(cd "${1:?usage: test_package.sh BUILD_DIR}" && pwd)"
launcher=()
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

cmake --install "$build" --prefix "$tmp/prefix" > "$tmp/install.log" || { cat "$tmp/install.log"; fail "cmake --install"; }
for f in lib/libheightmarch_core.a include/heightmarch/tracer.hpp bin/heightmarch-glsl-worker \
         lib/cmake/heightmarch/heightmarchConfig.cmake lib/cmake/heightmarch/heightmarchConfigVersion.cmake; do
  [ -e "$tmp/prefix/$f" ] || fail "not installed: $f"
done
# The tool's internals (the plan, the measurement pass, its files) are no library API.
for f in configuration measurement suite_plan recommendation run_outputs claims; do
  [ ! -e "$tmp/prefix/include/heightmarch/$f.hpp" ] || fail "a tool internal installed as API: heightmarch/$f.hpp"
done
if grep -rn -e "$build" -e "$root" "$tmp/prefix/lib/cmake"; then fail "a build or source path leaks into the package"; fi
echo "ok: installed library, headers, worker and config; no tool internals; no build-tree path in the package"

cmake -S "$root/tests/package" -B "$tmp/consumer" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" \
  -DCMAKE_PREFIX_PATH="$tmp/prefix" > "$tmp/configure.log" 2>&1 || { cat "$tmp/configure.log"; fail "consumer configure"; }
cmake --build "$tmp/consumer" -j2 > "$tmp/build.log" 2>&1 || { cat "$tmp/build.log"; fail "consumer build"; }
"$tmp/consumer/trace_flat" || fail "trace_flat (heightmarch::core)"
"$tmp/consumer/glsl_flat" || fail "glsl_flat (heightmarch::glsl)"
echo "ok: find_package(heightmarch) consumer builds, traces and hits"

cmake -S "$root/tests/package" -B "$tmp/subproject" "${launcher[@]}" -DHEIGHTMARCH_SUBPROJECT_DIR="$root" \
  > "$tmp/subproject.log" 2>&1 || { cat "$tmp/subproject.log"; fail "consumer with add_subdirectory"; }
echo "ok: add_subdirectory gives heightmarch::core and heightmarch::glsl, without the tool"
