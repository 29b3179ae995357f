#!/usr/bin/env bash
# scripts/report on a small synthetic run (no build needed): report.md opens with the alerts
# (alerts.json's, "no change beyond noise", or why there are none), then what to ship
# (recommendation.json: the choice per backend and heightfield with its time, errors,
# preprocessing and the next fastest), the claims' verdicts and the headline ratios; the long
# tables go to tables.md; speeds and ratios show their spread as `x (a-b)`, a planted roofline
# fraction above 100% is a fault and not a result, a busy run says so at the top, every plot is
# drawn and no wider than 1600 px, zero errors read 0, a gallery cost image is shown beside the
# error image, a '|' in a cell is escaped, the links to docs/ resolve from the run directory,
# with --csv measurements.csv has a row per configuration with the measures' one names (none
# without), report.html carries its rows gzip'd and loads Plotly from beside the run (written there
# once, inlined where that directory cannot be written to), --history appends rows with the machine's columns (replacing a rerun's) and
# writes alerts.json, a filtered run's headline
# ratios keep only the columns it measured, a format 1
# measurements.json still reads, and a missing measurements.json is a one-line error, status 2.
# Usage: test_report.sh [BUILD_DIR]
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
export PYTHONPATH="$root/scripts"  # the package heightmarch_tools

/usr/bin/python3 - "$tmp/run" <<'PY'
import json, os, sys
run = sys.argv[1]
os.makedirs(run)
view = {"kind": "default", "width": 64, "height": 64, "theta": None, "phi": None}
rows = []


GL = {"path": "osmesa", "device": "software", "renderer": "llvmpipe (LLVM 15.0.6, 256 bits)",
      "version": "4.5 (Core Profile) Mesa 22.3.6", "driver": "Mesa/X.org", "software": True,
      "label": "glsl (llvmpipe, LLVM 15.0.6, 256 bits; OSMesa)"}


def add(kind, purposes, technique, layers, backend, threads, rates, samples_per_ray=10.0, view=view, uv=0.5,
        images=None):
    rays = view["width"] * view["height"]
    n = int(rays * samples_per_ray)
    speed = None
    if rates:
        s = sorted(rates)
        speed = {"repetitions": len(rates), "seconds": [rays / r for r in rates],
                 "rays_per_second": {"median": s[len(s) // 2], "min": s[0], "max": s[-1], "rounds": rates},
                 "samples_per_second": {"median": s[len(s) // 2] * samples_per_ray, "min": s[0] * samples_per_ray,
                                        "max": s[-1] * samples_per_ray}}
    layered = layers not in (None, "1")
    rows.append({"id": len(rows), "kind": kind, "purposes": purposes,
                 "heightfield": {"label": "bricks", "source": "builtin:bricks", "width": 32, "height": 32},
                 "technique": technique, "layers": layers, "min_layers": int(layers) if layers else None,
                 "max_layers": int(layers) if layers else None, "refine": 5, "backend": backend, "threads": threads,
                 "view": view, "scale": 0.1, "wrap": "repeat", "discard": False, "rays": rays, "samples": n,
                 "samples_known": backend != "glsl", "samples_per_ray": samples_per_ray, "simd_utilization": 1.0,
                 "errors": None if kind in ("roofline", "ceiling") else {
                     "uv_error_mean": uv, "uv_error_p95": 2 * uv, "uv_error_p99": 3 * uv, "uv_error_max": 9 * uv,
                     "wrong_surface_rate": 0.1 if uv else 0.0},
                 "speed": speed, "images": images, "gl": GL if kind == "glsl" else None})


add("trace", ["matrix"], "parallax", "1", "avx2", 2, [100e6, 101e6, 99e6, 100e6, 102e6], 1.0, uv=20)
add("trace", ["matrix", "isa"], "pom", "32", "avx2", 2, [40e6, 41e6, 39e6, 40e6, 42e6])
# p95 = 2 uv: pom 32 reaches p95 <= 1 exactly; pom 64 (more samples, p95 0.2) is the cheapest for 0.25
add("trace", ["matrix"], "pom", "64", "avx2", 2, [30e6, 31e6, 29e6, 30e6, 32e6], 20.0, uv=0.1)
add("trace", ["matrix", "isa"], "maxmip", "1", "avx2", 2, [25e6, 25e6, 24e6, 25e6, 26e6], 12.0, uv=0.0)
rows[-1]["simd_utilization"] = 0.9714
add("trace", ["isa"], "pom", "32", "avx2", 1, [20e6, 21e6, 20e6, 19e6, 20e6])
add("trace", ["isa"], "pom", "32", "scalar", 1, [5e6, 5e6, 5e6, 5e6, 5e6])
add("naive", ["naive"], "pom", "32", "naive", 1, [4e6, 4e6, 4e6, 4e6, 4e6])
add("glsl", ["glsl"], "pom", "32", "glsl", 2, [10e6, 10e6, 9e6, 10e6, 11e6])
# planted fault: avx2's 1-thread roofline (samples/s) below the kernel's own samples/s
add("roofline", ["roofline"], None, "32", "avx2", 1, [15e6, 15e6, 15e6, 15e6, 15e6])
add("roofline", ["roofline"], None, "32", "scalar", 1, [10e6, 10e6, 10e6, 10e6, 10e6])
# the compute ceiling (samples/s = 10 x rays/s here) and the auto-vectorised port of avx2 at 1 thread
add("ceiling", ["roofline"], None, "32", "avx2", 1, [40e6, 40e6, 40e6, 40e6, 40e6])
add("autovec", ["naive"], "pom", "32", "avx2", 1, [8e6, 8e6, 8e6, 8e6, 8e6])
add("glsl", ["glsl"], "pom", "32", "glsl", 1, [5e6, 5e6, 5e6, 5e6, 5e6])
for theta in (0.0, 40.0, 80.0):
    add("trace", ["sweep"], "pom", "32", "avx2", 2, None,
        view={"kind": "sweep", "width": 16, "height": 16, "theta": theta, "phi": 0.0}, uv=0.1 + theta / 100)
add("trace", ["gallery"], "pom", "32", "avx2", 2, None,
    images={"render": "gallery/bricks-pom-32-render.png", "error": "gallery/bricks-pom-32-error.png"})
os.makedirs(os.path.join(run, "gallery"))
open(os.path.join(run, "gallery", "bricks-pom-32-cost.png"), "w").close()
json.dump({"format": "heightmarch-claims", "format_version": 2,
           "claims": [{"id": "C7", "claim": "POM is much more accurate than steep parallax", "verdict": "holds partly"}]},
          open(os.path.join(run, "claims.json"), "w"))
techniques = [{"name": "parallax", "layered": False, "color": "#7f7f7f", "marker": "o", "description": "one sample"},
              {"name": "pom", "layered": True, "color": "#d62728", "marker": "s", "description": "interpolated"},
              {"name": "maxmip", "layered": False, "color": "#8c564b", "marker": "h", "description": "a pyramid walk",
               "shape": "walk"}]
pick = lambda row_id, label, ns, hf="bricks": {
    "technique": label.split()[0], "layers": label.split()[1] if " " in label else "1", "label": label,
    "ns_per_ray": {"median": ns, "min": ns * 0.9, "max": ns * 1.1},
    "rays_per_second": {"median": 1e9 / ns, "min": 1e9 / ns / 1.1, "max": 1e9 / ns / 0.9},
    "rows": [{"id": row_id, "heightfield": hf, "uv_error_p99": 0.0 if "maxmip" in label else 0.3,
              "wrong_surface_rate": 0.0 if "maxmip" in label else 0.004, "samples_per_ray": 12.0, "rays": 4096,
              "ms_per_frame": {"median": 0.1, "min": 0.09, "max": 0.11},
              "precompute_seconds": 0.5 if "maxmip" in label else None,
              "precompute_ms_per_frame": 0.5 / 3600 * 1e3 if "maxmip" in label else None}]}
answer = {"heightfield": "bricks", "settings": 3, "meeting": 2, "choice": pick(3, "maxmip", 40.0),
          "runner_up": pick(2, "pom 64", 33.3), "runner_up_time_ratio": {"median": 0.83, "min": 0.8, "max": 1.2},
          "closest": None}
recommendation = {"format": "heightmarch-recommendation", "format_version": 1,
                  "target": {"measure": "uv_error_p99", "uv_error_texels": 0.5, "wrong_surface_rate": 0.005, "frames": 3600,
                             "description": "p99 <= 0.5 texel, wrong surface <= 0.5%"},
                  "backends": [{"backend": "avx2", "threads": 2, "name": "avx2, 2 threads",
                                "all_heightfields": dict(answer, heightfield=None), "per_heightfield": [answer]}]}
json.dump(recommendation, open(os.path.join(run, "recommendation.json"), "w"))
data = {"format": "heightmarch-measurements", "format_version": 2,
        "provenance": {"commit": "abc123", "dirty": False, "cpu": "Test CPU", "cores": 2, "compiler": "GNU 12",
                       "build_type": "Release", "date": "2026-01-01T00:00:00Z", "best_isa": "avx2", "threads": 2},
        "plan": {"name": "test", "repetitions": 5, "min_seconds_per_repetition": 0.01},
        "load": {"before": [1.5, 0.5, 0.2], "after": [1.9, 0.6, 0.3], "other_cpu_share": 0.25, "busy": True,
                 "busy_reasons": ["other processes used 25% of the CPU time"]},
        "techniques": techniques, "backends": ["scalar", "avx2", "glsl", "naive", "exact"], "rows": rows}
json.dump(data, open(os.path.join(run, "measurements.json"), "w"))
PY

"$root/scripts/report" "$tmp/run" --history "$tmp/history.csv" > "$tmp/out" 2>&1 || { cat "$tmp/out"; fail "report exited non-zero"; }
report="$tmp/run/report.md"
tables="$tmp/run/tables.md"
[ "$(stat -c %a "$report")" = 644 ] || fail "report.md is not mode 0644"
for png in error_vs_layers error_vs_angle error_vs_speed isa_speedup history; do
  [ -s "$tmp/run/plots/$png.png" ] || fail "missing plots/$png.png"
  width=$(/usr/bin/python3 -c 'import struct, sys; print(struct.unpack(">I", open(sys.argv[1], "rb").read()[16:20])[0])' \
          "$tmp/run/plots/$png.png")
  [ "$width" -le 1600 ] || fail "plots/$png.png is $width px wide"
  grep -q "(plots/$png.png)" "$report" || fail "report.md does not show plots/$png.png"
done
echo "ok: report.md (0644) and its plots, at most 1600 px wide"

# Recording the run wrote its alerts.json (the agreed shape; its machine is unknown, a CPU without
# family and model, so no series is tested), and the report opens with them.
/usr/bin/python3 - "$tmp/run/alerts.json" <<'PY' || fail "the recorded run's alerts.json"
import json, sys
a = json.load(open(sys.argv[1]))
assert sorted(a) == ["alerts", "format_version", "machine", "rule", "series_tested"], sorted(a)
assert a["format_version"] == 1 and a["machine"] == "unknown-test-cpu-2c-avx2-gnu-12-release" and a["alerts"] == [], a
assert a["series_tested"] == 0 and a["rule"], a
PY
[ "$(grep -m1 '^## ' "$report")" = "## Alerts" ] && grep -q 'No series tested: this machine has too few earlier recorded runs' "$report" \
  || fail "a recorded run's report does not open with its alerts"
echo "ok: recording writes alerts.json; the report opens with it"

# A run's alerts (as regression tracking writes them when a series moved) open the report.
cat > "$tmp/run/alerts.json" <<'JSON'
{"format_version": 1, "machine": "test-machine", "series_tested": 7, "rule": "median beyond the last runs' spread",
 "alerts": [{"series": "BM_Trace/pom/32", "kind": "speed", "metric": "rays_per_second", "baseline": 40e6,
             "baseline_spread": 1e6, "new": 30e6, "change": -0.25, "message": "POM-32 at avx2 25% slower"}]}
JSON
[ ! -e "$tmp/run/measurements.csv" ] || fail "measurements.csv written without --csv"
"$root/scripts/report" "$tmp/run" --csv > "$tmp/out" 2>&1 || { cat "$tmp/out"; fail "report exited non-zero"; }
sections="$(grep '^## ' "$report" | head -5 | tr '\n' '/')"
[ "$sections" = "## Alerts/## What to ship/## The claims: the tutorials' (C1-C10) and the papers' (P1-P3)/## Headline speed ratios/## Warnings/" ] \
  || fail "report.md's first sections: $sections"
grep -qF '| avx2, 2 threads | **every heightfield** | **maxmip** | 40.00 (36.00-44.00) | not measured | not measured | 0; 0% | - | 12.0 | 0.5 s once (0.139 ms a frame) | pom 64: 0.83x (0.80-1.20) the time (not distinguishable) | - |' \
  "$report" || fail "the recommendation for every heightfield"
grep -q '| avx2, 2 threads | bricks | \*\*maxmip\*\* |' "$report" || fail "the recommendation per heightfield"
grep -qF 'p99 \<= 0.5 texel, wrong surface \<= 0.5%' "$report" || fail "the recommendation's target"
grep -q '| bricks | 4.00x (3.80-4.20) | 5.00x (4.75-5.25) | 2.00x (1.95-2.11) | 4.00x (3.82-4.33) |' "$report" \
  || fail "the headline ratios"
grep -q '^- \*\*C7 holds partly\*\*: POM is much more accurate than steep parallax$' "$report" || fail "the claims' verdicts"
# The GLSL figures name their renderer: the ratio's column, the provenance, the tables' rows.
grep -q '| avx2 over glsl (llvmpipe, LLVM 15.0.6, 256 bits; OSMesa), 2 threads |' "$report" || fail "the GLSL ratio names no renderer"
grep -q '| GL renderer | glsl (llvmpipe, LLVM 15.0.6, 256 bits; OSMesa): 4.5 (Core Profile) Mesa 22.3.6, Mesa/X.org, device software |' \
  "$report" || fail "the provenance names no GL renderer"
grep -q '^| bricks | glsl (llvmpipe, LLVM 15.0.6, 256 bits; OSMesa) | 2 |' "$tables" || fail "the GLSL row of every backend names no renderer"
grep -q 'glsl (llvmpipe, LLVM 15.0.6, 256 bits; OSMesa)' "$tmp/run/report.html" || fail "report.html names no GL renderer"
[ "$(wc -l < "$report")" -lt 120 ] || fail "report.md is $(wc -l < "$report") lines: the long tables belong in tables.md"
echo "ok: report.md opens with the alerts, what to ship, the claims and the ratios; $(wc -l < "$report") lines"

sed -n '/^## Alerts/,/^## What/p' "$report" | grep -q '^1 alert in 7 series' || fail "the alert is not at the top"
grep -qF '| BM\_Trace/pom/32 | speed | rays\_per\_second | 4e+07 (spread 1e+06) | 3e+07 | -25.0% | POM-32 at avx2 25% slower |' \
  "$report" || fail "the alert's row"
/usr/bin/python3 - "$tmp/run/alerts.json" <<'PY' || fail "no line for a run without alerts, or without alerts.json"
import json, sys
from heightmarch_tools import report
alerts = dict(json.load(open(sys.argv[1])), alerts=[])
assert "No change beyond noise in 7 series." in "\n".join(report.section_alerts(alerts))
assert "No alerts.json: this run was not recorded" in "\n".join(report.section_alerts(None))
PY
rm "$tmp/run/alerts.json"
echo "ok: alerts.json's alerts open the report; 'no change beyond noise in N series'; or why there are none"

grep -q '| pom 32 | !\[\](gallery/bricks-pom-32-render.png) | !\[\](gallery/bricks-pom-32-error.png) | !\[\](gallery/bricks-pom-32-cost.png) |' \
  "$tables" || fail "the gallery's cost image is not beside the error image"
grep -q '| maxmip | 1 | 25.0 (24.0-26.0) | 12.00 | 0 | 0 | 0 | 0 | 0.00% |' "$tables" || fail "zero errors do not read 0"
echo "ok: the gallery shows the cost image beside the error image; zero errors read 0"

grep -q '| pom | 32 | 40.0 (39.0-42.0) |' "$tables" || fail "a speed lacks its spread"
# per-round ratios: 40/20, 41/21, 39/20, 40/19, 42/20 (not median over median with min over max)
grep -q '| 2.00x (1.95-2.11) |' "$tables" || fail "the thread speed-up is not the per-round ratio with its spread"
grep -q '| 4.00x (3.82-4.33) |' "$tables" || fail "CPU/GLSL is not the per-round ratio with its spread"
grep -q '| 4.00x (3.80-4.20) | 5.00x (4.75-5.25) |' "$tables" || fail "x scalar and x naive are not per-round ratios"
echo "ok: speeds and ratios show median (min-max)"

grep -q 'fault (above 100%: timing disturbed)' "$tables" || fail "the planted roofline fraction is not a fault"
grep -q -i 'measurement faults' "$tables" || fail "no measurement faults note"
grep -q '| 50% (50-50) |' "$tables" || fail "scalar's roofline fraction is not a result"
grep -q 'roofline or ceiling fraction above 100%' "$report" || fail "report.md does not warn of the fault"
echo "ok: a roofline fraction above 100% is a measurement fault"

# avx2 1 thread: 20 Mrays/s, ceiling 400 Msamples/s (kernel 200: 50%), 2.5x its autovec, 4x llvmpipe
grep -q '| bricks | avx2 | 1 | 20.0 (19.0-21.0) | 200 (190-210) | 150 (150-150) | fault (above 100%: timing disturbed) | 50% (48-52) | 4.00x (3.80-4.20) | 5.00x (4.75-5.25) | 4.00x (3.80-4.20) | 2.50x (2.38-2.62) |' "$tables" \
  || fail "the POM table's ceiling fraction, x llvmpipe and x autovec"
grep -q '| bricks | avx2 autovec | 1 | 8.0 (8.0-8.0) |' "$tables" || fail "the auto-vectorised port's row"
echo "ok: the POM table shows the ceiling fraction, x llvmpipe and x the auto-vectorised port"

grep -q 'Warning: the machine was busy' "$report" || fail "no busy warning"
grep -q 'other processes used 25% of the CPU time' "$report" || fail "the busy warning lacks its reasons"
[ "$(grep -n 'The machine was busy during this run' "$report" | cut -d: -f1)" -lt "$(grep -n '^## Alerts' "$report" | cut -d: -f1)" ] \
  || fail "the busy note is not at the top"
echo "ok: a busy run says so at the top"

/usr/bin/python3 - "$tmp/run" <<'PY' || fail "cells with '|', links to docs/"
import os, re, sys
from heightmarch_tools import report
table = report.md_table([("technique", False), ("figures", True)], [["pom 8", "|dx| + |dy| = 2"]])
assert table[-1] == r"| pom 8 | \|dx\| + \|dy\| = 2 |", table[-1]
run = sys.argv[1]
links = re.findall(r"\]\(([^)]*docs/[^)#]*)", open(os.path.join(run, "report.md")).read())
assert links and all(os.path.exists(os.path.join(run, link)) for link in links), links
print("ok: a '|' in a cell is escaped; %d links to docs/ resolve from the run directory" % len(links))
PY

/usr/bin/python3 - "$tmp/run" <<'PY' || fail "measurements.csv"
import csv, json, os, sys
run = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(run, "measurements.csv"))))
data = json.load(open(os.path.join(run, "measurements.json")))
assert len(rows) == len(data["rows"]), (len(rows), len(data["rows"]))
for key in ("id", "kind", "technique", "layers", "backend", "threads", "heightfield.label", "view.kind",
            "errors.uv_error_p95", "errors.wrong_surface_rate", "speed.rays_per_second.median", "speed.seconds"):
    assert key in rows[0], key
assert rows[1]["errors.uv_error_p95"] == "1.0" and rows[1]["speed.rays_per_second.median"] == "40000000.0", rows[1]
assert rows[0]["discard"] == "false" and rows[8]["errors.uv_error_p95"] == "", (rows[0]["discard"], rows[8])
print("ok: measurements.csv: %d rows, one per configuration, %d columns" % (len(rows), len(rows[0])))
PY

page="$tmp/run/report.html"
grep -q 'plotly.js (basic - minified) v4.1.1' "$tmp/plotly-basic.min.js" || fail "no Plotly 4.1.1 beside the run"
[ "$(grep -Eo '<script[^>]+src="[^"]*"' "$page")" = '<script src="../plotly-basic.min.js"' ] \
  || fail "report.html loads a script other than ../plotly-basic.min.js: $(grep -Eo '<script[^>]+src="[^"]*"' "$page")"
! grep -Eq '<link[^>]+href="http|plotly.js \(basic' "$page" || fail "report.html loads a style from elsewhere, or inlines Plotly"
PYTHONPATH="$root/scripts" /usr/bin/python3 - "$page" <<'PY' || fail "report.html lacks the rows"
import base64, gzip, json, re, sys
packed = re.search(r'<script id="report-data" type="application/gzip\+base64">(.*?)</script>', open(sys.argv[1]).read(), re.S)
assert any(r["technique"] == "maxmip" for r in json.loads(gzip.decompress(base64.b64decode(packed.group(1))))["rows"])
PY
# Where the directory above the run cannot be written to, the page inlines Plotly (root writes anywhere: a file in the way).
mkdir -p "$tmp/blocked/run" && cp -r "$tmp/run/." "$tmp/blocked/run/" && mkdir "$tmp/blocked/plotly-basic.min.js"
"$root/scripts/report" "$tmp/blocked/run" > "$tmp/out" 2>&1 || { cat "$tmp/out"; fail "report exited non-zero"; }
grep -q 'plotly.js (basic - minified) v4.1.1' "$tmp/blocked/run/report.html" && ! grep -q '<script src=' "$tmp/blocked/run/report.html" \
  || fail "report.html neither finds nor inlines Plotly where ../plotly-basic.min.js cannot be written"
echo "ok: report.html: rows gzip'd, Plotly once beside the run (inlined where it cannot be written), nothing loaded from elsewhere"
grep -q "| bricks | maxmip | 2 | .* | 97% |" "$tables" || fail "the walks' table shows maxmip's samples/s with its SIMD use"
grep -q "The walks' samples/s and SIMD use" "$page" || fail "report.html lacks the walks' table"
echo "ok: the walks' samples/s beside their SIMD use, in tables.md and report.html"

# report.html and report.md say the same things: the recommendation's table cell for cell (the
# "(not distinguishable)" caveat with it), in words (no measure's code name as a column), and the
# busy machine's warning on the page's first screen, before the alerts, as at the top of report.md.
/usr/bin/python3 - "$tmp/run" <<'PY' || fail "report.html and report.md differ"
import base64, gzip, json, os, re, sys
run = sys.argv[1]
page = open(os.path.join(run, "report.html")).read()
packed = re.search(r'<script id="report-data" type="application/gzip\+base64">(.*?)</script>', page, re.S).group(1)
data = json.loads(gzip.decompress(base64.b64decode(packed)))
table = data["recommendation_table"]
md = open(os.path.join(run, "report.md")).read()
unescape = lambda cell: re.sub(r"\\(.)", r"\1", cell.strip()).replace("**", "")
section = md[md.index("## What to ship"):md.index("## The claims")]
rows = [line for line in section.splitlines() if line.startswith("| ")]
header, cells = rows[0], [[unescape(c) for c in re.split(r"(?<!\\)\|", line)[1:-1]] for line in rows[1:]]
assert [unescape(c) for c in re.split(r"(?<!\\)\|", header)[1:-1]] == table["columns"], (header, table["columns"])
assert cells == [r["cells"] for r in table["rows"]], (cells, table["rows"])
assert any("(not distinguishable)" in cell for r in table["rows"] for cell in r["cells"])
assert not any("_" in c for c in table["columns"]), table["columns"]
first = page.index('<section id="warnings">')
assert first < page.index('<section id="alerts">') and "the machine was busy during this run" in page[first:page.index("</section>", first)]
print("ok: report.html shows report.md's recommendation table cell for cell, its caveat included, in words; "
      "the busy warning opens the page")
PY

columns='date,commit,machine,cpu,cores,best_isa,compiler,build_type,backend,threads,heightfield,technique,layers,view,depth_map,filter,rays_per_second_median,rays_per_second_min,rays_per_second_max,samples_per_ray,uv_error_mean,uv_error_p95,wrong_surface_rate,simd_utilization'
[ "$(head -1 "$tmp/history.csv")" = "$columns" ] || fail "history columns: $(head -1 "$tmp/history.csv")"
[ "$(tail -n +2 "$tmp/history.csv" | wc -l)" = 13 ] || fail "history rows: expected one per timed row (13)"
grep -q '^2026-01-01T00:00:00Z,abc123,unknown-test-cpu-2c-avx2-gnu-12-release,Test CPU,2,avx2,GNU 12,Release,avx2-autovec,1,bricks,pom,32,' "$tmp/history.csv" \
  || fail "the auto-vectorised port's history row is not told apart from avx2's"
grep -q '^2026-01-01T00:00:00Z,abc123,unknown-test-cpu-2c-avx2-gnu-12-release,Test CPU,2,avx2,GNU 12,Release,avx2,2,bricks,pom,32,default 64x64,32x32,bilinear,4e+07,3.9e+07,4.2e+07,10,0.5,1,0.1,1$' "$tmp/history.csv" \
  || fail "history row of POM-32 at avx2"
"$root/scripts/report" "$tmp/run" --history "$tmp/history.csv" > "$tmp/out" 2>&1 || { cat "$tmp/out"; fail "rerun failed"; }
[ "$(tail -n +2 "$tmp/history.csv" | wc -l)" = 13 ] || fail "a rerun of the same date and commit was appended, not replaced"
echo "ok: --history appends one row per timed row with the machine's columns"

# A filtered run (one ISA, no GLSL, no naive port) shows only the ratios it measured.
/usr/bin/python3 - "$tmp/run" "$tmp/filtered" <<'PY' || fail "a filtered run's headline ratios"
import json, os, sys
from heightmarch_tools import measurements, report
data = json.load(open(os.path.join(sys.argv[1], "measurements.json")))
data["rows"] = [r for r in data["rows"] if r["kind"] == "trace" and r["backend"] == "avx2"]
os.makedirs(sys.argv[2])
json.dump(data, open(os.path.join(sys.argv[2], "measurements.json"), "w"))
table = report.section_ratios(measurements.load_run(sys.argv[2]))
assert table[-3:] == ["| heightfield | 2 threads over 1 at avx2 |", "|---|---:|", "| bricks | 2.00x (1.95-2.11) |"], table
PY
echo "ok: a filtered run's headline ratios have no empty columns"

# A format 1 measurements.json (the committed runs before format 2: uv_p95 for uv_error_p95) still reads.
/usr/bin/python3 - "$tmp/run/measurements.json" <<'PY'
import json, sys
data = json.load(open(sys.argv[1]))
del data["format"], data["format_version"]
data["schema"] = "heightmarch-measurements/1"
for r in data["rows"]:
    if r["errors"]:
        r["errors"] = {k.replace("uv_error_", "uv_"): v for k, v in r["errors"].items()}
json.dump(data, open(sys.argv[1], "w"))
PY
/usr/bin/python3 - "$tmp/run" <<'PY' || fail "a format 1 run does not read"
import sys
from heightmarch_tools import measurements, report
table = "\n".join(report.section_matrix(measurements.load_run(sys.argv[1])))
assert "| pom | 32 | 40.0 (39.0-42.0) | 10.00 | 0.5 | 1 | 1.5 | 4.5 | 10.00% |" in table, table
PY
echo "ok: a format 1 measurements.json reads, its measures under their one names"

rm "$tmp/run/measurements.json"
status=0
"$root/scripts/report" "$tmp/run" > "$tmp/out" 2>&1 || status=$?
[ "$status" = 2 ] && [ "$(wc -l < "$tmp/out")" = 1 ] || { cat "$tmp/out"; fail "missing measurements.json: status $status"; }
echo "ok: a missing measurements.json is a one-line error, status 2"
