#!/usr/bin/env bash
# scripts/report.py on a small synthetic measurements.json (no build needed): the report opens with
# its summary (cheapest configuration per error target, headline ratios, claims' verdicts), speeds
# and ratios show their spread as `x (a-b)`, a planted roofline fraction above 100% is a fault and
# not a result, a busy run says so at the top, every plot is drawn and no wider than 1600 px, a
# gallery cost image is shown beside the error image, the POM table shows the compute ceiling's
# fraction and the ratios to llvmpipe and the auto-vectorised port, --history appends rows with the machine's
# columns (replacing a rerun's) and the report opens with the alerts, and a missing measurements.json is a
# one-line error with exit status 2.
# Usage: test_report.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

/usr/bin/python3 - "$tmp/run" <<'PY'
import json, os, sys
run = sys.argv[1]
os.makedirs(run)
view = {"kind": "default", "width": 64, "height": 64, "theta": None, "phi": None}
rows = []


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
                 "errors": None if kind == "roofline" else {"uv_mean": uv, "uv_p95": 2 * uv, "uv_max": 9 * uv,
                                                             "wrong_surface_rate": 0.1},
                 "speed": speed, "images": images})


add("trace", ["matrix"], "parallax", "1", "avx2", 2, [100e6, 101e6, 99e6, 100e6, 102e6], 1.0, uv=20)
add("trace", ["matrix", "isa"], "pom", "32", "avx2", 2, [40e6, 41e6, 39e6, 40e6, 42e6])
# p95 = 2 uv: pom 32 reaches p95 <= 1 exactly; pom 64 (more samples, p95 0.2) is the cheapest for 0.25
add("trace", ["matrix"], "pom", "64", "avx2", 2, [30e6, 31e6, 29e6, 30e6, 32e6], 20.0, uv=0.1)
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
json.dump([{"id": "C7", "claim": "POM is much more accurate than steep parallax", "verdict": "holds partly"}],
          open(os.path.join(run, "claims.json"), "w"))
techniques = [{"name": "parallax", "layered": False, "color": "#7f7f7f", "marker": "o", "description": "one sample"},
              {"name": "pom", "layered": True, "color": "#d62728", "marker": "s", "description": "interpolated"}]
data = {"schema": "heightmarch-measurements/1",
        "provenance": {"commit": "abc123", "dirty": False, "cpu": "Test CPU", "cores": 2, "compiler": "GNU 12",
                       "build_type": "Release", "date": "2026-01-01T00:00:00Z", "best_isa": "avx2", "threads": 2},
        "plan": {"name": "test", "repetitions": 5, "min_seconds_per_repetition": 0.01},
        "load": {"before": [1.5, 0.5, 0.2], "after": [1.9, 0.6, 0.3], "other_cpu_share": 0.25, "busy": True,
                 "busy_reasons": ["other processes used 25% of the CPU time"]},
        "techniques": techniques, "backends": ["scalar", "avx2", "glsl", "naive", "exact"], "rows": rows}
json.dump(data, open(os.path.join(run, "measurements.json"), "w"))
PY

"$root/scripts/report.py" "$tmp/run" --history "$tmp/history.csv" > "$tmp/out" 2>&1 || { cat "$tmp/out"; fail "report.py exited non-zero"; }
report="$tmp/run/report.md"
[ "$(stat -c %a "$report")" = 644 ] || fail "report.md is not mode 0644"
for png in error_vs_layers error_vs_angle error_vs_speed isa_speedup history; do
  [ -s "$tmp/run/plots/$png.png" ] || fail "missing plots/$png.png"
  width=$(/usr/bin/python3 -c 'import struct, sys; print(struct.unpack(">I", open(sys.argv[1], "rb").read()[16:20])[0])' \
          "$tmp/run/plots/$png.png")
  [ "$width" -le 1600 ] || fail "plots/$png.png is $width px wide"
  grep -q "(plots/$png.png)" "$report" || fail "report.md does not show plots/$png.png"
done
echo "ok: report.md (0644) and its plots, at most 1600 px wide"

[ "$(grep '^## ' "$report" | sed -n 2p)" = "## Summary" ] || fail "the summary does not follow the alerts: $(grep '^## ' "$report" | head -2)"
summary="$(sed -n '/^## Summary/,/^## /p' "$report")"
grep -q '| bricks | \*\*pom 32\*\*: 10.0 samples/ray, 40.0 (39.0-42.0) Mrays/s, p95 1.000 | \*\*pom 64\*\*: 20.0 samples/ray, 30.0 (29.0-32.0) Mrays/s, p95 0.200 | none (best: pom 64, p95 0.200) |' \
  <<< "$summary" || fail "the summary's cheapest configurations per error target"
grep -q '| bricks | 4.00x (3.80-4.20) | 5.00x (4.75-5.25) | 2.00x (1.95-2.11) | 4.00x (3.82-4.33) |' <<< "$summary" \
  || fail "the summary's headline ratios"
grep -q '^- \*\*C7 holds partly\*\*: POM is much more accurate than steep parallax$' <<< "$summary" \
  || fail "the summary's claim verdicts"
echo "ok: the summary comes first: cheapest configuration per target, headline ratios, claims"

grep -q '| pom 32 | !\[\](gallery/bricks-pom-32-render.png) | !\[\](gallery/bricks-pom-32-error.png) | !\[\](gallery/bricks-pom-32-cost.png) |' \
  "$report" || fail "the gallery's cost image is not beside the error image"
echo "ok: the gallery shows the cost image beside the error image"

grep -q '| pom | 32 | 40.0 (39.0-42.0) |' "$report" || fail "a speed lacks its spread"
# per-round ratios: 40/20, 41/21, 39/20, 40/19, 42/20 (not median over median with min over max)
grep -q '| 2.00x (1.95-2.11) |' "$report" || fail "the thread speed-up is not the per-round ratio with its spread"
grep -q '| 4.00x (3.82-4.33) |' "$report" || fail "CPU/GLSL is not the per-round ratio with its spread"
grep -q '| 4.00x (3.80-4.20) | 5.00x (4.75-5.25) |' "$report" || fail "x scalar and x naive are not per-round ratios"
echo "ok: speeds and ratios show median (min-max)"

grep -q 'fault (>100%: timing disturbed)' "$report" || fail "the planted roofline fraction is not a fault"
grep -q -i 'measurement faults' "$report" || fail "no measurement faults note"
grep -q '| 50% (50-50) |' "$report" || fail "scalar's roofline fraction is not a result"
echo "ok: a roofline fraction above 100% is a measurement fault"

# avx2 1 thread: 20 Mrays/s, ceiling 400 Msamples/s (kernel 200: 50%), 2.5x its autovec, 4x llvmpipe
grep -q '| bricks | avx2 | 1 | 20.0 (19.0-21.0) | 200 (190-210) | 150 (150-150) | fault (>100%: timing disturbed) | 50% (48-52) | 4.00x (3.80-4.20) | 5.00x (4.75-5.25) | 4.00x (3.80-4.20) | 2.50x (2.38-2.62) |' "$report" \
  || fail "the POM table's ceiling fraction, x llvmpipe and x autovec"
grep -q '| bricks | avx2 autovec | 1 | 8.0 (8.0-8.0) |' "$report" || fail "the auto-vectorised port's row"
echo "ok: the POM table shows the ceiling fraction, x llvmpipe and x the auto-vectorised port"

grep -q 'Warning: the machine was busy' "$report" || fail "no busy warning"
grep -q 'other processes used 25% of the CPU time' "$report" || fail "the busy warning lacks its reasons"
[ "$(grep -n 'Warning: the machine was busy' "$report" | cut -d: -f1)" -lt "$(grep -n '^## Machine' "$report" | cut -d: -f1)" ] \
  || fail "the busy warning is not at the top"
echo "ok: a busy run says so at the top"

columns='date,commit,machine,cpu,cores,best_isa,compiler,build_type,backend,threads,heightfield,technique,layers,view,depth_map,rays_per_second_median,rays_per_second_min,rays_per_second_max,samples_per_ray,uv_error_mean,uv_error_p95,wrong_surface_rate'
[ "$(head -1 "$tmp/history.csv")" = "$columns" ] || fail "history columns: $(head -1 "$tmp/history.csv")"
[ "$(tail -n +2 "$tmp/history.csv" | wc -l)" = 12 ] || fail "history rows: expected one per timed row (12)"
grep -q '^2026-01-01T00:00:00Z,abc123,unknown-test-cpu-2c-avx2-gnu-12-release,Test CPU,2,avx2,GNU 12,Release,avx2-autovec,1,bricks,pom,32,' "$tmp/history.csv" \
  || fail "the auto-vectorised port's history row is not told apart from avx2's"
grep -q '^2026-01-01T00:00:00Z,abc123,unknown-test-cpu-2c-avx2-gnu-12-release,Test CPU,2,avx2,GNU 12,Release,avx2,2,bricks,pom,32,default 64x64,32x32,4e+07,3.9e+07,4.2e+07,10,0.5,1,0.1$' "$tmp/history.csv" \
  || fail "history row of POM-32 at avx2"
"$root/scripts/report.py" "$tmp/run" --history "$tmp/history.csv" > "$tmp/out" 2>&1 || { cat "$tmp/out"; fail "rerun failed"; }
[ "$(tail -n +2 "$tmp/history.csv" | wc -l)" = 12 ] || fail "a rerun of the same date and commit was appended, not replaced"
[ "$(grep -m1 '^## ' "$report")" = "## Alerts" ] && grep -q '^\*\*No change beyond noise\*\* in 0 series' "$report" \
  || fail "a recorded run's report does not open with its alerts"
echo "ok: --history appends one row per timed row with the machine's columns; the report opens with the alerts"

rm "$tmp/run/measurements.json"
status=0
"$root/scripts/report.py" "$tmp/run" > "$tmp/out" 2>&1 || status=$?
[ "$status" = 2 ] && [ "$(wc -l < "$tmp/out")" = 1 ] || { cat "$tmp/out"; fail "missing measurements.json: status $status"; }
echo "ok: a missing measurements.json is a one-line error, status 2"
