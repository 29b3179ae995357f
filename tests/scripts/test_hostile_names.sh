#!/usr/bin/env bash
# Maps named to break out of every output format: a quick suite on depth maps named with HTML
# (`<img src=x onerror=...>`, `<!--<script>`), a Markdown link, a spreadsheet formula, a newline
# and a heading, terminal escapes, matplotlib's mathtext ($x^2$), and two maps both named rock.png in two directories (one given
# by an absolute path), the first of which the gallery draws. Then:
# - the gallery's images are all in the run's gallery/, none beside the maps (a file planted
#   there is untouched);
# - measurements.csv: no cell a spreadsheet would evaluate (= + - @ tab CR) but numbers;
# - report.md and tables.md: no unescaped HTML, no link but the report's own, no heading split
#   by a name, every table row with its header's cells, no terminal escape; nor in what the suite
#   printed;
# - report.html in headless Chromium (check_page_injection.py): drawn, every row of the
#   recommendation clicked, no script run.
# A small quick plan (POM and maxmip, matrix and gallery, no GLSL) on 64x64 maps: about 30 s.
# Usage: test_hostile_names.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
build="$(cd "${1:?usage: test_hostile_names.sh BUILD_DIR}" && pwd)"
export PYTHONPATH="$root/scripts:$root/tests/scripts"

mkdir -p "$tmp/in/a" "$tmp/in/b" "$tmp/cwd"
/usr/bin/python3 - "$tmp/in" <<'PY'
import os, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
x = np.linspace(0, 1, 64)
depth = 0.5 + 0.4 * np.outer(np.sin(6 * x), np.cos(5 * x))
for name in ("a/rock.png", "b/rock.png", "<img src=x onerror=window.__pwned=1;document.title='PWN'>.png",
             "<!--<script>.png", "[x](javascript:alert(1)).png", "=HYPERLINK(\"http:__x\").png",
             "a\n### heading.png", "\x1b]0;PWN\x07\x1b[2J.png", "a$x^2$.png"):
    plt.imsave(os.path.join(sys.argv[1], name), depth, cmap="gray", vmin=0, vmax=1)
PY
echo planted > "$tmp/in/a/rock.png-exact-render.png"
touch -d '2000-01-01' "$tmp/in/a/rock.png-exact-render.png"
maps="$tmp/in/a/rock.png"  # absolute: its label is its path, never a place to write
for f in "$tmp"/in/b/rock.png "$tmp"/in/*.png; do maps="$maps,../in/${f#"$tmp/in/"}"; done
(cd "$tmp/cwd" && "$build/heightmarch" suite --quick --no-builtins --heightmap "$maps" --no-glsl --techniques pom,maxmip \
   --parts matrix,gallery --out run > "$tmp/suite.out" 2>&1) || { cat "$tmp/suite.out"; fail "the suite exited non-zero"; }
run="$tmp/cwd/run"
[ ! -e "$run/INCOMPLETE" ] || fail "the run is INCOMPLETE"

# The gallery: every image the rows name exists in run/gallery/, and nothing was written beside the maps.
/usr/bin/python3 - "$run" <<'PY' || fail "the gallery's files"
import gzip, json, os, sys
run = sys.argv[1]
images = [p for r in json.load(gzip.open(os.path.join(run, "measurements.json.gz")))["rows"] for p in (r["images"] or {}).values() if p]
assert len(images) >= 9, images
for p in images:
    assert p.startswith("gallery/") and "/" not in p[len("gallery/"):] and os.path.isfile(os.path.join(run, p)), p
assert sorted(os.listdir(os.path.join(run, "gallery"))) == sorted(p[len("gallery/"):] for p in images)
print("ok: the %d gallery images of a map given as %s are in the run's gallery/" % (len(images), images[0]))
PY
[ "$(find "$tmp/in" -type f -printf x | wc -c)" = 10 ] && [ "$(cat "$tmp/in/a/rock.png-exact-render.png")" = planted ] \
  || fail "something was written beside the maps"
echo "ok: nothing written beside the maps (a file planted there untouched)"

"$build/heightmarch" report "$run" --csv > /dev/null || fail "heightmarch report --csv"
/usr/bin/python3 - "$run/measurements.csv" <<'PY' || fail "measurements.csv"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1], newline="")))
labels = {r["heightfield.label"] for r in rows}
assert "'=HYPERLINK(\"http:__x\").png" in labels, labels
for r in rows:
    for column, cell in r.items():
        if cell[:1] in ("=", "+", "-", "@", "\t", "\r"):
            float(cell)  # only a number may begin so
print("ok: measurements.csv: the formula label reads '=HYPERLINK(...); no cell a spreadsheet evaluates")
PY

/usr/bin/python3 - "$run" "$tmp/suite.out" <<'PY' || fail "report.md and tables.md"
import os, re, sys
run = sys.argv[1]
for name in ("report.md", "tables.md"):
    text = open(os.path.join(run, name)).read()
    assert "\x1b" not in text, name
    assert not re.search(r"(?<!\\)<", text), (name, re.search(r".{0,40}(?<!\\)<.{0,40}", text).group(0))
    for target in re.findall(r"(?<!\\)\]\(([^)]*)\)", text):  # every link and image: the report's own files and docs
        assert re.fullmatch(r"[A-Za-z0-9_./%#+-]+", target) and ":" not in target, (name, target)
    lines = text.splitlines()
    assert not any(re.match(r"#+ heading", line) for line in lines), name  # a name never starts a heading
    header = None
    for line in lines:
        cells = len(re.findall(r"(?<!\\)\|", line))
        if not line.startswith("|"):
            header = None
        elif header is None:
            header = cells
        else:
            assert cells == header, (name, line)
assert "\x1b" not in open(sys.argv[2], errors="replace").read(), "the suite printed a terminal escape"
print("ok: report.md and tables.md: names are text (no HTML, no link, no heading, no cut row, no escape); so is the suite's output")
PY

/usr/bin/python3 "$root/tests/scripts/check_page_injection.py" "$run" || fail "report.html"
