#!/usr/bin/env bash
# arm64: the tracing core (HEIGHTMARCH_TRACE_ONLY) cross-built with Debian's g++-aarch64-linux-gnu
# into DIR, and its tests (scalar kernels, sampler, exact reference, techniques against the
# scalar reference, packet ops at width 1) run under qemu-user. scripts/test installs the
# toolchain; where it could not, this skips with one line (exit 77). --build-only stops before
# the tests (scripts/test builds first, so that the ctest test only runs them).
# Usage: scalar_tests.sh DIR [--build-only]
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
dir="${1:?usage: $0 DIR [--build-only]}"
skip() { echo "arm64: skipped: $*"; exit 77; }
command -v aarch64-linux-gnu-g++ >/dev/null || skip "no aarch64-linux-gnu-g++ (Debian: g++-aarch64-linux-gnu)"
command -v qemu-aarch64 >/dev/null || skip "no qemu-aarch64 (Debian: qemu-user)"
# TBB for arm64 (its CMake package names tbbbind too), unpacked from Debian's arm64 packages:
# installing them would pull in arm64 system packages. apt knows them once dpkg has the arm64
# architecture (scripts/test adds it).
sysroot="$dir/sysroot"
tbb_packages=(libtbb-dev:arm64 libtbb12:arm64 libtbbmalloc2:arm64 libtbbbind-2-5:arm64)
if [ ! -f "$sysroot/usr/lib/aarch64-linux-gnu/cmake/TBB/TBBConfig.cmake" ]; then
  mkdir -p "$dir/debs" "$sysroot"
  (cd "$dir/debs" && apt-get download -q "${tbb_packages[@]}" >/dev/null 2>&1) ||
    skip "cannot download ${tbb_packages[*]} (is the arm64 architecture in dpkg? dpkg --add-architecture arm64; apt-get update)"
  for deb in "$dir"/debs/*.deb; do dpkg-deb -x "$deb" "$sysroot"; done
fi
cmake -S "$root" -B "$dir/build" -DCMAKE_TOOLCHAIN_FILE="$root/cmake/aarch64-linux-gnu.cmake" \
  -DHEIGHTMARCH_ARM64_SYSROOT="$sysroot" -DCMAKE_BUILD_TYPE=Release -DHEIGHTMARCH_TRACE_ONLY=ON > "$dir/configure.log" ||
  { cat "$dir/configure.log"; exit 1; }
cmake --build "$dir/build" -j "$(nproc)" --target heightmarch-tests > "$dir/build.log" 2>&1 ||
  { tail -40 "$dir/build.log"; exit 1; }
readelf -h "$dir/build/heightmarch-tests" | grep -q AArch64 || { echo "arm64: heightmarch-tests is not an arm64 binary"; exit 1; }
[ "${2:-}" != "--build-only" ] || exit 0
qemu-aarch64 -L /usr/aarch64-linux-gnu -E "LD_LIBRARY_PATH=$sysroot/usr/lib/aarch64-linux-gnu" \
  "$dir/build/heightmarch-tests" --gtest_brief=1
