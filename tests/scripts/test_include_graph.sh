#!/usr/bin/env bash
# The layers hold: no include runs up a layer and no two folders include each other, a public
# header counting as its implementation's folder (scripts/include_graph, docs/architecture.md).
# And the check can fail: a tree whose low layer includes a public header implemented higher up
# fails it, as the tree of d85ad05 (kernel_abi.hpp, naive_port.hpp and precomputed.hpp reaching
# src/trace through isa.hpp and technique.hpp) does where the history holds that commit.
# Usage: test_include_graph.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
graph="$root/scripts/include_graph"
out="$("$graph" "$root")" || { echo "$out"; echo "FAIL: the include graph breaks the layers"; exit 1; }
echo "$out" | tail -1

mkdir -p "$tmp/include/heightmarch" "$tmp/src/trace" "$tmp/src/kernels"
echo '#pragma once' > "$tmp/include/heightmarch/table.hpp"
echo '#include "heightmarch/table.hpp"' > "$tmp/src/trace/table.cpp"
echo '#include "heightmarch/table.hpp"' > "$tmp/src/kernels/kernel.hpp"
if out="$("$graph" "$tmp")"; then echo "$out"; echo "FAIL: an include of a header implemented higher up passes"; exit 1; fi
echo "$out" | grep -q "up a layer: src/kernels/kernel.hpp includes include/heightmarch/table.hpp (src/trace)" ||
  { echo "$out"; echo "FAIL: the upward include is not named"; exit 1; }
echo '#include "heightmarch/table.hpp"' > "$tmp/src/kernels/table.cpp"
if out="$("$graph" "$tmp")" || ! echo "$out" | grep -q "ambiguous: include/heightmarch/table.hpp"; then
  echo "$out"; echo "FAIL: a public header with two implementations passes"; exit 1
fi
echo "ok: an upward include through a public header and an ambiguous public header fail"

if git -C "$root" cat-file -e "d85ad05^{commit}" 2> /dev/null; then
  if out="$(cd "$root" && "$graph" --rev d85ad05)"; then echo "$out"; echo "FAIL: the tree of d85ad05 passes"; exit 1; fi
  echo "ok: the tree of d85ad05 fails ($(echo "$out" | grep -c 'up a layer:') includes up a layer)"
fi
