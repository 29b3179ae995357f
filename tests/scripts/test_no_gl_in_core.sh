#!/usr/bin/env bash
# Only heightmarch-glsl-worker links OSMesa (and so libLLVM): the CLI and the test binary start
# without them and reach GLSL through the worker, which links no OpenImageIO; and heightmarch::core
# configures without OSMesa (HEIGHTMARCH_GLSL=OFF) where pkg-config cannot find it.
# Usage: test_no_gl_in_core.sh BUILD_DIR
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="${1:?usage: $0 BUILD_DIR}"
status=0
for binary in heightmarch heightmarch-tests; do
  [ -x "$build/$binary" ] || { echo "FAIL: $build/$binary is not built"; exit 1; }
  if found="$(ldd "$build/$binary" | grep -i -E 'osmesa|llvm')"; then
    echo "FAIL: $binary loads GL libraries:"
    echo "$found"
    status=1
  else
    echo "ok: $binary loads neither libOSMesa nor libLLVM"
  fi
done
if ldd "$build/heightmarch-glsl-worker" | grep -i osmesa >/dev/null; then
  echo "ok: heightmarch-glsl-worker links libOSMesa"
else
  echo "FAIL: heightmarch-glsl-worker does not link libOSMesa (is the check itself broken?)"
  status=1
fi
# The worker checks what it is sent without the image libraries, which would triple what it holds
# before any input (about 60 MiB; OpenImageIO and its libraries add some 120).
if ldd "$build/heightmarch-glsl-worker" | grep -i openimageio >/dev/null; then
  echo "FAIL: heightmarch-glsl-worker links OpenImageIO"
  status=1
else
  echo "ok: heightmarch-glsl-worker links no OpenImageIO"
fi
# Nor may --help load them at run time (a dlopen).
loaded="$(LD_DEBUG=libs "$build/heightmarch" --help 2>&1 >/dev/null | grep 'calling init:' || true)"
if grep -i -E 'osmesa|llvm' <<<"$loaded"; then
  echo "FAIL: heightmarch --help loads GL libraries at run time"
  status=1
else
  echo "ok: heightmarch --help loads neither at run time"
fi

# A pkg-config that knows no osmesa: the core must configure with it, the GLSL backend must not
# (or the check proves nothing). Configure only: what links is shown above.
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
printf '#!/bin/sh\ncase "$*" in *osmesa*) exit 1 ;; esac\nexec pkg-config "$@"\n' > "$tmp/pkg-config"
chmod +x "$tmp/pkg-config"
if PKG_CONFIG="$tmp/pkg-config" cmake -S "$root" -B "$tmp/core" -DHEIGHTMARCH_GLSL=OFF > "$tmp/core.log" 2>&1 &&
   ! grep -rqi osmesa "$tmp/core/CMakeFiles" --include='*.make' --include='*.txt'; then
  echo "ok: heightmarch::core configures without OSMesa (HEIGHTMARCH_GLSL=OFF), and no target links it"
else
  cat "$tmp/core.log"
  echo "FAIL: heightmarch::core does not configure without OSMesa"
  status=1
fi
if PKG_CONFIG="$tmp/pkg-config" cmake -S "$root" -B "$tmp/gl" > "$tmp/gl.log" 2>&1; then
  echo "FAIL: the GLSL backend configured without OSMesa (is the check itself broken?)"
  status=1
fi
exit $status
