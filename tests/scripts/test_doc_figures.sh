#!/usr/bin/env bash
# The figures README.md and docs/ quote from committed runs agree with the runs they name
# (scripts/doc_figures --check), and a stale one fails the check: a copy of the docs with one
# figure changed, and one naming a run that does not exist.
# Usage: test_doc_figures.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
build="$(cd "${1:-$root/build}" && pwd)"

"$root/scripts/doc_figures" --check --heightmarch "$build/heightmarch" > "$tmp/check.out" 2>&1 ||
  { cat "$tmp/check.out"; fail "a figure in README.md or docs/ disagrees with the run it names"; }
cat "$tmp/check.out"
grep -Eq "^doc_figures: [1-9][0-9]* figures agree" "$tmp/check.out" || fail "no figure was checked"

# A stale figure: the first machine line and the first grid figure of the docs, each changed.
mkdir -p "$tmp/tree/docs"
cp "$root/README.md" "$tmp/tree/"
cp "$root"/docs/*.md "$tmp/tree/docs/"
check_copy() { "$root/scripts/doc_figures" --check --root "$tmp/tree" --results "$root/results" --heightmarch "$build/heightmarch"; }
sed -i '0,/<!-- figure row \([^>]*\)-->[^<]*<!-- \/figure -->/s//<!-- figure row \1-->99.9<!-- \/figure -->/' "$tmp/tree/docs/recommendation.md"
if check_copy > "$tmp/stale.out" 2>&1; then cat "$tmp/stale.out"; fail "a changed figure passed the check"; fi
grep -q "docs/recommendation.md:[0-9]*: the text says '99.9', its run gives" "$tmp/stale.out" ||
  { cat "$tmp/stale.out"; fail "the stale figure is not named with its file and line"; }
# Rewriting mends it.
"$root/scripts/doc_figures" --root "$tmp/tree" --results "$root/results" --heightmarch "$build/heightmarch" > /dev/null
check_copy > /dev/null || fail "scripts/doc_figures did not rewrite the stale figure"
sed -i '0,/<!-- figure machine latest -->/s//<!-- figure machine 2000-01-01-none -->/' "$tmp/tree/README.md"
if check_copy > "$tmp/missing.out" 2>&1; then fail "a figure naming no committed run passed the check"; fi
grep -q "README.md:[0-9]*: no run 2000-01-01-none" "$tmp/missing.out" || { cat "$tmp/missing.out"; fail "no clear line for a missing run"; }
echo "ok: a changed figure and one naming a missing run fail the check, each named with its line"
