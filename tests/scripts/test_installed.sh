#!/usr/bin/env bash
# heightmarch as installed: BUILD_DIR installed into a temporary prefix, the prefix moved elsewhere,
# then, with the build tree and the source tree out of reach (empty directories mounted over them
# in a private mount namespace), the installed tool's quick suite writes a complete run with its
# report (report.md, tables.md, report.html, plots) whose links to the docs land
# in the installed docs, and `heightmarch report RUN` writes the report again from
# measurements.json.gz. A small quick plan (POM and maxmip, the matrix and the gallery): about 10 s.
# Usage: test_installed.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
build="$(cd "${1:?usage: test_installed.sh BUILD_DIR}" && pwd)"

cmake --install "$build" --prefix "$tmp/prefix" > "$tmp/install.log" || { cat "$tmp/install.log"; fail "cmake --install"; }
mv "$tmp/prefix" "$tmp/moved"  # nothing may depend on where it was installed either
tool="$tmp/moved/bin/heightmarch"
for f in bin/heightmarch bin/heightmarch-glsl-worker share/heightmarch/python/heightmarch_tools/report.py \
         share/heightmarch/python/heightmarch_tools/page/page.js share/heightmarch/docs/measures.md; do
  [ -e "$tmp/moved/$f" ] || fail "not installed: $f"
done

# Runs a command with the build and source trees hidden: a private mount namespace (as root, or as
# a user namespace's root) with empty directories mounted over them.
namespace=()
for try in "unshare --mount" "unshare --user --map-root-user --mount"; do
  if $try -- true 2>/dev/null; then read -ra namespace <<< "$try"; break; fi
done
if [ ${#namespace[@]} = 0 ]; then
  echo "SKIP: no mount namespace here (unshare --mount refused), so the build tree cannot be hidden"
  exit 77
fi
hidden() {
  TMP="$tmp" "${namespace[@]}" -- sh -c \
    'mount -t tmpfs none "$1" && { [ ! -d "$2" ] || mount -t tmpfs none "$2"; } && shift 2 && cd "$TMP" && exec "$@"' \
    sh "$build" "$root" "$@"
}
hidden sh -c "[ ! -e '$build/CMakeCache.txt' ] && [ ! -e '$root/scripts' ]" || fail "the trees are not hidden"

hidden "$tool" suite --quick --techniques pom,maxmip --parts matrix,gallery --out "$tmp/run" > "$tmp/suite.out" 2>&1 \
  || { cat "$tmp/suite.out"; fail "the installed suite --quick failed with the build and source trees hidden"; }
run="$tmp/run"
[ ! -e "$run/INCOMPLETE" ] || fail "the installed suite's run is INCOMPLETE"
for f in measurements.json.gz report.md tables.md report.html ../plotly-basic.min.js plots/error_vs_layers.png; do
  [ -s "$run/$f" ] || fail "the installed suite wrote no $f"
done
grep -q "^## What to ship" "$run/report.md" || fail "report.md lacks what to ship"
links="$(grep -o '](\.\./[^)#]*docs/[^)#]*' "$run/report.md" | sed 's/^](//' | sort -u)"
[ -n "$links" ] || fail "report.md links no doc"
for link in $links; do
  target="$(realpath -m "$run/$link")"
  [[ "$target" == "$tmp/moved/share/heightmarch/docs/"* ]] && [ -e "$target" ] || fail "a doc link leads to $target"
done
echo "ok: the installed quick suite (moved prefix, build and source trees hidden) writes a complete run and report; its doc links land in the installed docs"

rm "$run/report.md" "$run/report.html"
hidden "$tool" report "$run" > "$tmp/report.out" 2>&1 || { cat "$tmp/report.out"; fail "heightmarch report"; }
[ -s "$run/report.md" ] && [ -s "$run/report.html" ] || fail "heightmarch report did not write the report again"
echo "ok: heightmarch report RUN writes the report again from measurements.json.gz"
