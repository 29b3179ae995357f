#!/usr/bin/env bash
# The suite's plumbing on its quick plan: one typed row per configuration in measurements.json
# (every technique on the CPU and as GLSL, the searches at every ISA this CPU runs, roofline, naive
# port, the exact reference and the calibration loop timed, sweeps, gallery, claims), every
# timed row with at least 5 repetitions and its spread, bench.json named as heightmarch-bench
# names, the claims, the recommendation, the report with spreads, the result files against their
# JSON Schemas, report.html in headless Chromium (check_report_page.py; its screenshot goes to
# BUILD_DIR/report_page.png), and a run directory that is fresh and locked; a quick run neither
# moves results/latest nor writes results/history.csv.
# Usage: test_suite.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
build="$(cd "${1:-$root/build}" && pwd)"

# A quick run into the default place: a fresh results/<date>-<commit>-<time>-quick of the cwd.
mkdir "$tmp/cwd"
(cd "$tmp/cwd" && "$build/heightmarch" suite --quick > "$tmp/suite.out" 2>&1) || { cat "$tmp/suite.out"; fail "suite exited non-zero"; }
run="$(ls -d "$tmp"/cwd/results/*-quick)"
[ "$(echo "$run" | wc -l)" -eq 1 ] || fail "expected one run directory, got: $run"
[ ! -e "$tmp/cwd/results/latest" ] || fail "a quick run moved results/latest"
[ ! -e "$tmp/cwd/results/history.csv" ] || fail "a quick run wrote results/history.csv"
for f in measurements.json.gz bench.json.gz recommendation.json claims.md claims.json report.md tables.md \
         report.html plots/error_vs_layers.png plots/error_vs_angle.png plots/error_vs_speed.png plots/isa_speedup.png \
         ../plotly-basic.min.js; do
  [ -s "$run/$f" ] || fail "missing or empty $f"
done
for f in measurements.json bench.json measurements.csv; do [ ! -e "$run/$f" ] || fail "$f kept uncompressed"; done
[ ! -e "$run/INCOMPLETE" ] || fail "a completed run still says INCOMPLETE"
[ "$(stat -c %a "$run/report.md")" = 644 ] || fail "report.md is not world-readable"
# The progress counts what its header announces: "... 415 runs) into DIR", then "n/415 runs done"
# (until the gallery of what to ship, a stage of its own with its own count).
runs_announced="$(sed -n 's/.*: \([0-9]*\) runs) into .*/\1/p' "$tmp/suite.out")"
measuring="$(sed '/the gallery of what to ship/q' "$tmp/suite.out")"
[ -n "$runs_announced" ] && grep -q "^  $runs_announced/$runs_announced runs done" <<< "$measuring" &&
  ! grep -v "/$runs_announced runs done" <<< "$measuring" | grep -q "runs done" ||
  { cat "$tmp/suite.out"; fail "the progress does not count the runs its header announces"; }
echo "ok: a fresh run directory with every file; latest and history untouched by --quick; progress counts its header's runs"

"$build/heightmarch" claims --list > "$tmp/claims.list" || fail "claims --list exited non-zero"
# The ISAs this CPU runs (under HEIGHTMARCH_MAX_ISA where set), as the tool says: the suite's
# searches run at each of them, and at no other.
runs="$("$build/heightmarch" --version | sed -n 's/^ISAs this CPU runs: \([^(]*\).*/\1/p')"
[ -n "$runs" ] || fail "heightmarch --version does not name the ISAs this CPU runs"
/usr/bin/python3 - "$run" "$tmp/claims.list" "$runs" <<'PY' || fail "measurements.json or bench.json lacks what the plan asked for"
import gzip, json, os, sys
run = sys.argv[1]
cpu_isas = [name.strip() for name in sys.argv[3].split(",")]
m = json.load(gzip.open(run + "/measurements.json.gz"))
rows = m["rows"]
techniques = [t["name"] for t in m["techniques"]]
assert [b for b in m["backends"] if b not in ("glsl", "naive", "exact", "calibration")] == cpu_isas, (m["backends"], cpu_isas)
assert set(m["backends"]) == {r["backend"] for r in rows}, (m["backends"], sorted({r["backend"] for r in rows}))
assert m["provenance"]["best_isa"] == cpu_isas[-1], (m["provenance"]["best_isa"], cpu_isas)
def has(**want):
    return any(all(r.get(k) == v for k, v in want.items()) for r in rows)
for hf in ("bricks", "terrain"):
    sel = [r for r in rows if r["heightfield"]["label"] == hf]
    for t in techniques:
        for kind in ("trace", "glsl"):
            assert any(r["kind"] == kind and r["technique"] == t and r["view"]["kind"] == "default" for r in sel), (hf, t, kind)
    for layers in ("8", "32", "8-32"):
        assert any(r["kind"] == "trace" and r["technique"] == "pom" and r["layers"] == layers for r in sel), (hf, layers)
    assert any(r["kind"] == "roofline" for r in sel) and any(r["kind"] == "naive" for r in sel), hf
    for t in ("steep", "relief", "pom", "secant", "cone", "maxmip"):
        for isa in cpu_isas:
            assert any(r["kind"] == "trace" and r["technique"] == t and r["layers"] in ("32", "1") and r["backend"] == isa
                       and "isa" in r["purposes"] and r["speed"] for r in sel), (hf, t, isa)
    assert any(r["kind"] == "exact" and "exact" in r["purposes"] and r["speed"] for r in sel), hf
    # compare's control: the calibration loop at every thread count in each heightfield's rounds
    assert {r["threads"] for r in sel if r["kind"] == "calibration" and r["speed"]} == {r["threads"] for r in sel}, hf
    assert len({r["view"]["theta"] for r in sel if r["view"]["kind"] == "sweep"}) == 18, hf
assert any("gallery" in r["purposes"] and r["images"] for r in rows)
# The window around the surface, its held-out twins, and what to ship seen on every map.
assert all(r["view"]["around"] for r in rows if "matrix" in r["purposes"])
held = [r for r in rows if r["purposes"] == ["held-out"]]
assert held and all(r["view"]["seed"] == 2 and not r["speed"] and r["errors"]["confidence"] for r in held)
for b in json.load(open(run + "/recommendation.json"))["backends"]:
    for a in b["per_heightfield"]:
        if a["choice"]:
            assert all(x["held_out"] for x in a["choice"]["rows"]), (b["name"], a["heightfield"])
            assert any("gallery" in r["purposes"] and r["images"] and r["heightfield"]["label"] == a["heightfield"]
                       and (r["technique"], r["layers"]) == (a["choice"]["technique"], a["choice"]["layers"])
                       for r in rows), (b["name"], a["heightfield"], a["choice"]["label"])
for r in rows:
    # An image a row does not draw is null (the shaded comparison's, where the row has no exact render).
    for image in filter(None, (r["images"] or {}).values()):
        assert os.path.getsize(os.path.join(run, image)) > 0, (r["id"], image)
    assert not r["images"] or r["images"]["cost"], r["id"]
for r in rows:
    if r["failure"]:
        raise AssertionError("row %d failed: %s" % (r["id"], r["failure"]))
    s = r["speed"]
    if s is None:
        continue
    rps = s["rays_per_second"]
    assert s["repetitions"] >= 5 and len(rps["rounds"]) == s["repetitions"] == len(s["seconds"]), r["id"]
    assert rps["min"] <= rps["median"] <= rps["max"] and rps["min"] > 0, r["id"]
    for rate, seconds in zip(rps["rounds"], s["seconds"]):
        assert abs(rate * seconds - r["rays"]) <= 1e-6 * r["rays"], r["id"]
    if r["kind"] in ("trace", "glsl"):
        assert r["errors"] is not None and r["errors"]["uv_error_p95"] >= 0, r["id"]
    # A GLSL row names its renderer (the default path here: OSMesa) and keeps both of its draws' clocks.
    assert (r["gl"] is not None) == (r["kind"] == "glsl"), r["id"]
    if r["kind"] == "glsl":
        assert r["gl"]["path"] == "osmesa" and "llvmpipe" in r["gl"]["renderer"] and r["gl"]["software"], r["gl"]
        assert r["gl"]["label"].startswith("glsl (llvmpipe, LLVM ") and r["gl"]["label"].endswith("; OSMesa)"), r["gl"]
        assert len(s["gl_wall_seconds"]) == s["repetitions"] and s["gl_wall_seconds"] == s["seconds"], r["id"]
        assert s["gl_timer_seconds"] is None or len(s["gl_timer_seconds"]) == s["repetitions"], r["id"]
for r in rows:
    if r["images"]:
        for path in filter(None, r["images"].values()):
            assert os.path.getsize(os.path.join(run, path)) > 100, path
timed = {r["id"] for r in rows if r["speed"]}
bench = json.load(gzip.open(run + "/bench.json.gz"))
names = {b["name"] for b in bench["benchmarks"]}
assert all("min_time" not in n and "/view:around:256x256/depth_map:256x256/manual_time" in n for n in names), sorted(names)[:3]
assert any(n.startswith("BM_GLSL/heightfield:bricks/technique:pom/layers:32/isa:glsl/threads:1/gl:osmesa/") for n in names)
assert bench["context"]["heightmarch_gl"].startswith("glsl (llvmpipe, "), bench["context"]
iterations = [b for b in bench["benchmarks"] if b["run_type"] == "iteration"]
medians = [b for b in bench["benchmarks"] if b["run_type"] == "aggregate" and b["aggregate_name"] == "median"]
assert len(iterations) == sum(r["speed"]["repetitions"] for r in rows if r["speed"])
assert len(medians) == len(timed) and len(bench["benchmarks"]) == len(iterations) + len(medians)
assert all(b["time_unit"] == "ns" and b["real_time"] >= 1000 for b in bench["benchmarks"])  # compare.py prints no decimals
assert bench["context"]["heightmarch_view"] == "around:256x256" and bench["context"]["heightmarch_build_type"]
claims = json.load(open(run + "/claims.json"))["claims"]
declared = [line.split("\t")[0] for line in open(sys.argv[2]).read().splitlines()]
assert len(declared) >= 13 and [c["id"] for c in claims] == declared, ([c["id"] for c in claims], declared)
assert all(c["verdict"] in ("holds", "mostly holds", "holds partly", "mostly refuted", "refuted", "not measured")
           for c in claims)
assert all(c["summary"] and c["passed"] <= c["checked"] == len(c["checks"]) for c in claims)
print("ok: %d rows (%d timed, each with >= 5 repetitions and its spread), bench.json of %d repetitions and their "
      "medians in ns, claims %s" % (len(rows), len(timed), len(iterations), ", ".join(declared)))
PY

grep -q "## Techniques x layers" "$run/tables.md" || fail "tables.md lacks the technique table"
grep -Eq "\| pom \| 32 \| [0-9.]+ \([0-9.]+-[0-9.]+\) \|" "$run/tables.md" || fail "tables.md shows no speed with its spread"
grep -q "## What to ship" "$run/report.md" || fail "report.md lacks the recommendation"
grep -q "claims.md" "$run/report.md" || fail "report does not link claims.md"
echo "ok: report.md has the recommendation and links; tables.md its tables, speeds with their spread"

# The result files against their JSON Schemas (docs/schemas/); metrics.json as trace --json prints it.
"$build/heightmarch" trace --res 32 --size 16x16 --repetitions 1 --json > "$tmp/metrics.json" || fail "trace --json"
gzip -dc "$run/measurements.json.gz" > "$tmp/measurements.json" || fail "measurements.json.gz is no whole gzip file"
/usr/bin/python3 "$root/tests/scripts/check_schemas.py" measurements "$tmp/measurements.json" claims "$run/claims.json" \
  recommendation "$run/recommendation.json" metrics "$tmp/metrics.json" || fail "a result file does not conform to its schema"
sed 's/"uv_error_p95"/"uv_p95"/' "$tmp/measurements.json" > "$tmp/old-names.json"
! /usr/bin/python3 "$root/tests/scripts/check_schemas.py" measurements "$tmp/old-names.json" > /dev/null \
  || fail "the schema accepts a measure under its format 1 name"
echo "ok: measurements.json, claims.json, recommendation.json and metrics.json conform to their schemas"

# report.html in headless Chromium: no console error, one point per configuration, hover, click.
PYTHONPATH="$root/scripts" /usr/bin/python3 "$root/tests/scripts/check_report_page.py" "$run" "$build/report_page.png" || fail "report.html"

# A second run into the same directory is refused, and so is one while another holds its lock.
if "$build/heightmarch" suite --quick --no-glsl --out "$run" > "$tmp/again.out" 2>&1; then fail "a second run into a complete run's directory was accepted"; fi
grep -q "already holds a run" "$tmp/again.out" || { cat "$tmp/again.out"; fail "no clear message for a second run"; }
echo "ok: a second run into the same directory is refused"

"$root/scripts/report" "$run" --history "$tmp/history.csv" > /dev/null
sed '0,/"commit": "[^"]*"/s//"commit": "second"/' "$tmp/measurements.json" | gzip > "$run/measurements.json.gz"
"$root/scripts/report" "$run" --history "$tmp/history.csv" > /dev/null
runs=$(tail -n +2 "$tmp/history.csv" | cut -d, -f2 | sort -u | wc -l)
[ "$runs" -eq 2 ] || fail "history holds $runs runs, expected 2"
[ -s "$run/plots/history.png" ] || fail "no history plot with two runs"
echo "ok: history has one set of rows per run and is plotted"
