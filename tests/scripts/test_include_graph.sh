#!/usr/bin/env bash
# The layers hold: no public header includes src/, no include runs up a layer, no two folders
# include each other (scripts/include_graph, docs/architecture.md).
# Usage: test_include_graph.sh BUILD_DIR
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="$("$root/scripts/include_graph" "$root")" || { echo "$out"; echo "FAIL: the include graph breaks the layers"; exit 1; }
echo "$out" | tail -1
