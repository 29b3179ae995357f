#!/usr/bin/env bash
# Only heightmarch-glsl-worker links OSMesa (and so libLLVM): the CLI and the test binary start
# without them and reach GLSL through the worker, which links no OpenImageIO. Usage: test_no_gl_in_core.sh BUILD_DIR
set -euo pipefail
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
exit $status
