#!/usr/bin/env bash
# The history per machine and its change-point alerts (heightmarch_tools's record_run,
# history, alerts and history_plot) on synthetic runs, no build needed: every row names its machine
# (a CPU without family and model is an unknown machine), a rerun replaces its rows, five quiet
# runs then a 20% step in one headline series raise exactly that speed alert, noise within the
# rule raises none, a change of samples per ray is a behaviour alert, another machine's runs are
# never its past, alerts.json has the agreed shape and alerts.csv keeps the alerts across runs,
# and the plot is drawn with a panel per machine.
# Usage: test_history.sh [BUILD_DIR] (unused)
set -euo pipefail
source "$(dirname "$0")/prelude.sh"
export PYTHONPATH="$root/scripts"  # the package heightmarch_tools

/usr/bin/python3 - "$tmp" <<'PY'
import json, os, sys
from heightmarch_tools import alerts, history, record_run
tmp = sys.argv[1]
hist = os.path.join(tmp, "history.csv")
ZEN4 = "AMD EPYC (family 25, model 17)"


def fail(what):
    print("FAIL: " + what)
    sys.exit(1)


def run(day, cpu=ZEN4, speed=None, samples=None):
    """A recorded run: POM-32 and steep-32 at scalar and avx512 (1 thread, the searches at every ISA),
    plus a matrix row; speed {(technique, isa): rays/s}, samples {(technique, isa): samples per ray}."""
    view = {"kind": "default", "width": 64, "height": 64, "theta": None, "phi": None}
    rows = []
    for technique in ("pom", "steep"):
        for isa in ("scalar", "avx512"):
            r = (speed or {}).get((technique, isa), 10e6 if isa == "scalar" else 80e6)
            # a round-to-round spread of a few percent, and a run-to-run wobble of 2%
            rounds = [r * f * (1 + 0.02 * ((day * 7) % 3 - 1)) for f in (0.96, 1.0, 0.98, 0.99, 0.97)]
            rows.append({"kind": "trace", "purposes": ["isa"], "technique": technique, "layers": "32", "backend": isa,
                         "threads": 1, "heightfield": {"label": "bricks", "width": 32, "height": 32}, "view": view,
                         "samples_known": True, "samples_per_ray": (samples or {}).get((technique, isa), 12.5),
                         "errors": {"uv_error_mean": 0.25, "uv_error_p95": 1.5, "wrong_surface_rate": 0.01},
                         "speed": {"rays_per_second": {"rounds": rounds}}})
    rows.append(dict(rows[0], purposes=["matrix"], threads=2))
    data = {"provenance": {"date": "2026-12-%02dT10:00:00Z" % day, "commit": "c%02d" % day, "cpu": cpu, "cores": 2,
                           "best_isa": "avx512", "compiler": "GNU 12.2.0", "build_type": "Release"},
            "backends": ["scalar", "avx512", "glsl", "naive", "exact"], "rows": rows}
    d = os.path.join(tmp, "run-%02d-%s" % (day, cpu[:3]))
    os.makedirs(d, exist_ok=True)
    json.dump(data, open(os.path.join(d, "measurements.json"), "w"))
    drawn, found = record_run.record(data, d, hist)
    on_disk = json.load(open(os.path.join(d, "alerts.json")))
    if on_disk != found or set(on_disk) != {"format_version", "machine", "series_tested", "rule", "alerts"} \
            or on_disk["format_version"] != 1 or not drawn:
        fail("alerts.json: %s" % on_disk)
    for a in found["alerts"]:
        if set(a) != {"series", "kind", "metric", "baseline", "baseline_spread", "new", "change", "message"} \
                or a["kind"] not in ("speed", "behaviour") or "\n" in a["message"]:
            fail("an alert's shape: %s" % a)
    return found


for day in range(1, 6):  # five quiet runs
    found = run(day)
    if found["alerts"]:
        fail("quiet run %d raised %s" % (day, found["alerts"]))
rows = history.read(hist)
if {r["machine"] for r in rows} != {"amd-epyc-f25m17-2c-avx512-gnu-12.2.0-release"} or len(rows) != 25:
    fail("history rows or machine key: %d rows, %s" % (len(rows), {r["machine"] for r in rows}))
run(5)  # a rerun of the same date and commit replaces its rows
if len(history.read(hist)) != 25:
    fail("a rerun was appended, not replaced")
print("ok: five quiet runs raise no alert; each row names its machine; a rerun replaces its rows")

found = run(6, speed={("pom", "avx512"): 64e6})
speed = [a for a in found["alerts"] if a["kind"] == "speed"]
if len(found["alerts"]) != 1 or len(speed) != 1 or "pom 32, avx512, 1 thread" not in speed[0]["series"] \
        or not -0.22 < speed[0]["change"] < -0.18 or "slower" not in speed[0]["message"]:
    fail("a 20%% step raised %s" % found["alerts"])
print("ok: a 20%% step in one headline series is that series' speed alert alone: %s" % speed[0]["message"])

found = run(7, speed={("pom", "avx512"): 64e6, ("steep", "avx512"): 80e6 * 0.93})
if any("steep" in a["series"] for a in found["alerts"]):
    fail("a 7%% change, within the rule's 10%%, raised %s" % found["alerts"])
print("ok: a 7% change (within the rule) raises no alert")

found = run(8, samples={("steep", "scalar"): 12.75})
behaviour = [a for a in found["alerts"] if a["kind"] == "behaviour"]
if len(behaviour) != 1 or "steep 32, scalar" not in behaviour[0]["series"] or behaviour[0]["metric"] != "samples_per_ray" \
        or "12.5 -> 12.75" not in behaviour[0]["message"]:
    fail("a change of samples per ray raised %s" % found["alerts"])
print("ok: a change of samples per ray is a behaviour alert: %s" % behaviour[0]["message"])

found = run(9, cpu="AMD EPYC (family 26, model 2)", speed={("pom", "avx512"): 40e6})
if found["alerts"] or found["series_tested"] != 0 or found["machine"] != "amd-epyc-f26m2-2c-avx512-gnu-12.2.0-release":
    fail("another machine's first run was judged against this one's: %s" % found)
found = run(10, cpu="AMD EPYC", speed={("pom", "avx512"): 20e6})
if found["alerts"] or found["series_tested"] != 0 or found["machine"] != "unknown-amd-epyc-2c-avx512-gnu-12.2.0-release":
    fail("an unknown machine's run was judged: %s" % found)
print("ok: another machine's runs and an unknown machine's are never judged against this machine's")

kept = history.read(os.path.join(tmp, "alerts.csv"), alerts.ALERTS)
if [(r["commit"], r["kind"]) for r in kept] != [("c06", "speed"), ("c07", "speed"), ("c08", "behaviour")]:
    fail("alerts.csv: %s" % [(r["commit"], r["kind"]) for r in kept])
print("ok: alerts.csv keeps every run's alerts")
PY
