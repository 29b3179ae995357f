#!/usr/bin/env bash
# arm64: the tracing core (HEIGHTMARCH_TRACE_ONLY) cross-built with Debian's g++-aarch64-linux-gnu
# into DIR, and its tests run under qemu-user at both ISAs of arm64's list, scalar and neon: every
# technique at neon bit for bit against scalar (both filters, both wraps), the packet ops, the
# sampler, the exact reference's float pass, the ports of the tutorial's POM (auto-vectorised and
# Highway) and the structured Highway POM; then the dispatch's tests again with the ISA capped at
# scalar, as on a core without neon. scripts/test installs the toolchain; where it could not, this
# skips with one line (exit 77). --build-only stops before the tests (scripts/test builds first,
# so that the ctest test only runs them).
# Usage: qemu_tests.sh DIR [--build-only]
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
dir="${1:?usage: $0 DIR [--build-only]}"
skip() { echo "arm64: skipped: $*"; exit 77; }
command -v aarch64-linux-gnu-g++ >/dev/null || skip "no aarch64-linux-gnu-g++ (Debian: g++-aarch64-linux-gnu)"
command -v qemu-aarch64 >/dev/null || skip "no qemu-aarch64 (Debian: qemu-user)"
# The arm64 libraries Debian's cross packages lack, unpacked from Debian's packages (installing
# the arm64 ones would pull in arm64 system packages): TBB (its CMake package names tbbbind too),
# Highway, and GLM's headers (the naive port's; architecture-independent, but found only in the
# sysroot). apt knows them once dpkg has the arm64 architecture (scripts/test adds it).
sysroot="$dir/sysroot"
packages=(libtbb-dev:arm64 libtbb12:arm64 libtbbmalloc2:arm64 libtbbbind-2-5:arm64 libhwy-dev:arm64 libhwy1:arm64
  libglm-dev)
if [ ! -f "$sysroot/unpacked" ] || [ "$(cat "$sysroot/unpacked")" != "${packages[*]}" ]; then
  rm -rf "$dir/debs" "$sysroot"
  mkdir -p "$dir/debs" "$sysroot"
  (cd "$dir/debs" && apt-get download -q "${packages[@]}" >/dev/null 2>&1) ||
    skip "cannot download ${packages[*]} (is the arm64 architecture in dpkg? dpkg --add-architecture arm64; apt-get update)"
  for deb in "$dir"/debs/*.deb; do dpkg-deb -x "$deb" "$sysroot"; done
  echo "${packages[*]}" > "$sysroot/unpacked"
fi
cmake -S "$root" -B "$dir/build" -DCMAKE_TOOLCHAIN_FILE="$root/cmake/aarch64-linux-gnu.cmake" \
  -DHEIGHTMARCH_ARM64_SYSROOT="$sysroot" -DCMAKE_BUILD_TYPE=Release -DHEIGHTMARCH_TRACE_ONLY=ON > "$dir/configure.log" ||
  { cat "$dir/configure.log"; exit 1; }
cmake --build "$dir/build" -j "$(nproc)" --target heightmarch-tests > "$dir/build.log" 2>&1 ||
  { tail -40 "$dir/build.log"; exit 1; }
readelf -h "$dir/build/heightmarch-tests" | grep -q AArch64 || { echo "arm64: heightmarch-tests is not an arm64 binary"; exit 1; }
[ "${2:-}" != "--build-only" ] || exit 0
run() { qemu-aarch64 -L /usr/aarch64-linux-gnu -E "LD_LIBRARY_PATH=$sysroot/usr/lib/aarch64-linux-gnu" "$@"; }
run "$dir/build/heightmarch-tests" --gtest_brief=1
echo "arm64: the dispatch's tests with HEIGHTMARCH_MAX_ISA=scalar"
run -E HEIGHTMARCH_MAX_ISA=scalar "$dir/build/heightmarch-tests" --gtest_brief=1 --gtest_filter='Dispatch.*:Determinism.*'
