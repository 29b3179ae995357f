#!/usr/bin/env bash
# Every Markdown table of the docs and the README has as many cells in each row as in its header:
# a '|' inside a cell ("|grad D|", "|dx| + |dy|") must be escaped as \|, or it cuts the row. The
# report's and claims.md's cells are escaped by their writers (escape.markdown, markdown_text), tested
# with them. Needs no build.
# Usage: test_markdown_tables.sh [BUILD_DIR] (unused)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
/usr/bin/python3 - "$root" <<'PY'
import glob, os, re, sys
root = sys.argv[1]
cells = lambda line: len(re.findall(r"(?<!\\)\|", line.strip().strip("|").replace("``", ""))) + 1
bad = []
files = sorted(glob.glob(os.path.join(root, "docs", "*.md"))) + [os.path.join(root, "README.md")]
for path in files:
    lines, fence, header = open(path).read().splitlines(), False, None
    for n, line in enumerate(lines, 1):
        if line.startswith("```"):
            fence = not fence
        if fence or not line.startswith("|"):
            header = None
            continue
        if header is None:
            header = cells(line)
        elif cells(line) != header:
            bad.append("%s:%d: %d cells, its header %d" % (os.path.relpath(path, root), n, cells(line), header))
if bad:
    print("FAIL: a table row with an unescaped '|': " + "; ".join(bad[:5]))
    sys.exit(1)
print("ok: every table row of %d Markdown files has its header's cells" % len(files))
PY
