#!/usr/bin/env bash
# Only heightmarch-glsl-worker links OSMesa and EGL (and so libLLVM): the CLI and the test binary
# start without them and reach GLSL through the worker, which links no OpenImageIO; and
# heightmarch::core configures without either (HEIGHTMARCH_GLSL=OFF) where pkg-config finds neither.
# Usage: test_no_gl_in_core.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
build="${1:?usage: $0 BUILD_DIR}"
status=0
for binary in heightmarch heightmarch-tests; do
  [ -x "$build/$binary" ] || { echo "FAIL: $build/$binary is not built"; exit 1; }
  if found="$(ldd "$build/$binary" | grep -i -E 'osmesa|libEGL|llvm')"; then
    echo "FAIL: $binary loads GL libraries:"
    echo "$found"
    status=1
  else
    echo "ok: $binary loads neither libOSMesa, libEGL nor libLLVM"
  fi
done
if ldd "$build/heightmarch-glsl-worker" | grep -i osmesa >/dev/null &&
   ldd "$build/heightmarch-glsl-worker" | grep libEGL >/dev/null; then
  echo "ok: heightmarch-glsl-worker links libOSMesa and libEGL"
else
  echo "FAIL: heightmarch-glsl-worker does not link libOSMesa and libEGL (is the check itself broken?)"
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
if grep -i -E 'osmesa|libEGL|llvm' <<<"$loaded"; then
  echo "FAIL: heightmarch --help loads GL libraries at run time"
  status=1
else
  echo "ok: heightmarch --help loads neither at run time"
fi

# A pkg-config that knows neither osmesa nor egl: the core must configure with it, the GLSL
# backend must not, and say why (or the check proves nothing). Configure only: what links is
# shown above; a worker with one of them is test_gl_paths.sh's.
printf '#!/bin/sh\ncase "$*" in *osmesa*|*egl*) exit 1 ;; esac\nexec pkg-config "$@"\n' > "$tmp/pkg-config"
chmod +x "$tmp/pkg-config"
if PKG_CONFIG="$tmp/pkg-config" cmake -S "$root" -B "$tmp/core" -DHEIGHTMARCH_GLSL=OFF > "$tmp/core.log" 2>&1 &&
   ! grep -rqi -E 'osmesa|libEGL' "$tmp/core/CMakeFiles" --include='*.make' --include='*.txt'; then
  echo "ok: heightmarch::core configures without OSMesa and EGL (HEIGHTMARCH_GLSL=OFF), and no target links them"
else
  cat "$tmp/core.log"
  echo "FAIL: heightmarch::core does not configure without OSMesa and EGL"
  status=1
fi
if PKG_CONFIG="$tmp/pkg-config" cmake -S "$root" -B "$tmp/gl" > "$tmp/gl.log" 2>&1; then
  echo "FAIL: the GLSL backend configured without OSMesa and EGL (is the check itself broken?)"
  status=1
elif ! grep -q "The GLSL worker needs OSMesa or EGL" "$tmp/gl.log"; then
  cat "$tmp/gl.log"
  echo "FAIL: configuring the GLSL backend without OSMesa and EGL does not say why it stops"
  status=1
fi
exit $status
