#!/usr/bin/env bash
# The suite's plumbing on its quick configuration: the run directory holds the benchmark JSON
# with the configurations asked for, the sweeps, the gallery, the claims, the report and its
# plots; the history gets one set of rows per recorded run.
# Usage: test_suite.sh BUILD_DIR
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$build/heightmarch" suite --quick --out "$tmp/run" > "$tmp/suite.out" 2>&1 || { cat "$tmp/suite.out"; fail "suite exited non-zero"; }
for f in bench.json bench-glsl-1thread.json sweep.csv gallery.json claims.md claims.json machine.json report.md \
         plots/error_vs_layers.png plots/error_vs_angle.png plots/error_vs_speed.png plots/isa_speedup.png; do
  [ -s "$tmp/run/$f" ] || fail "missing or empty $f"
done
[ ! -e "$tmp/run/INCOMPLETE" ] || fail "a completed run still says INCOMPLETE"
echo "ok: every file of the run exists"

/usr/bin/python3 - "$tmp/run" <<'PY' || fail "bench.json lacks configurations"
import json, sys
run = sys.argv[1]
names = [b["name"] for b in json.load(open(run + "/bench.json"))["benchmarks"]]
for hf in ("bricks", "terrain"):
    for technique in ("parallax", "parallax-limited", "steep", "steep-limited", "relief", "pom", "shadow"):
        for kind in ("BM_Trace", "BM_GLSL"):
            assert any(n.startswith("%s/heightfield:%s/technique:%s/" % (kind, hf, technique)) for n in names), (kind, hf, technique)
    for layers in ("8", "32", "8-32"):
        assert any("heightfield:%s/technique:pom/layers:%s/" % (hf, layers) in n for n in names), (hf, layers)
    assert any(n.startswith("BM_SamplerRoofline/heightfield:" + hf) for n in names), hf
    assert any(n.startswith("BM_NaivePort/heightfield:" + hf) for n in names), hf
counters = [b for b in json.load(open(run + "/bench.json"))["benchmarks"] if b["name"].startswith("BM_Trace")]
assert all("rays_per_second" in b and "uv_error_p95" in b and "samples_per_second" in b for b in counters)
claims = json.load(open(run + "/claims.json"))
assert [c["id"] for c in claims] == ["C%d" % i for i in range(1, 11)], [c["id"] for c in claims]
assert all(c["verdict"] in ("holds", "holds partly", "refuted", "not measured") for c in claims)
print("ok: bench.json holds every technique, layer spec, GLSL, roofline and naive port; claims C1-C10 have verdicts")
PY

grep -q "## Techniques x layers" "$tmp/run/report.md" || fail "report lacks the technique table"
grep -q "| bricks | pom | 32 |" "$tmp/run/report.md" || fail "report lacks the CPU/GLSL row of POM-32"
grep -q "claims.md" "$tmp/run/report.md" || fail "report does not link claims.md"
echo "ok: report.md has its tables and links"

"$root/scripts/report.py" "$tmp/run" --history "$tmp/history.csv" > /dev/null
sed -i 's/"commit": "[^"]*"/"commit": "second"/' "$tmp/run/machine.json"
"$root/scripts/report.py" "$tmp/run" --history "$tmp/history.csv" > /dev/null
runs=$(tail -n +2 "$tmp/history.csv" | cut -d, -f2 | sort -u | wc -l)
[ "$runs" -eq 2 ] || fail "history holds $runs runs, expected 2"
[ -s "$tmp/run/plots/history.png" ] || fail "no history plot with two runs"
echo "ok: history has one set of rows per run and is plotted"
