"""Change-point alerts: a recorded run's headline series tested against its machine's own past.

- Speed, on the headline series (every search at 1 thread at the best ISA, POM-32 at every ISA at
  1 thread): the run's fastest repetition (rays/s; load only ever slows a trace down, so the
  fastest repetition is the steadiest figure of a run) against the median of the same series'
  fastest repetitions over the machine's last RUNS earlier runs (at least MIN_RUNS of them). An
  alert when it differs from that baseline by more than MIN_CHANGE and by more than SPREADS
  times their spread (1.4826 x the median absolute deviation, a standard deviation where the
  runs are normal).
- Behaviour, on every series of the run: samples per ray, the uv error measures and the packet
  kernels' SIMD use are deterministic, so any change against the machine's previous run of the
  series (beyond float printing) is an alert.

The alerts go to RUN/alerts.json and are kept, one line each, in results/alerts.csv.
"""
import json
import os
import statistics

from . import history
from .writers import atomic_write

RUNS, MIN_RUNS = 5, 3
MIN_CHANGE = 0.10
SPREADS = 3.0
MAD_TO_SIGMA = 1.4826
REL_TOL = 1e-6  # measures are printed with 9 digits
CSV_COLUMNS = ["date", "commit", "machine", "series", "kind", "metric", "baseline", "baseline_spread", "new", "change",
               "message"]
ALERTS = history.Table(CSV_COLUMNS, {"baseline": 0.0, "baseline_spread": 0.0, "new": 0.0, "change": -1.0},
                       may_be_empty=("baseline", "baseline_spread", "new", "change"))
RULE = ("speed: the fastest repetition's rays/s of each headline series against the median of its last %d "
        "runs on this machine (at least %d), an alert beyond %d%% and %g x their spread (1.4826 MAD); behaviour: "
        "any change of samples per ray, uv error or SIMD use against the machine's previous run of the series"
        % (RUNS, MIN_RUNS, round(100 * MIN_CHANGE), SPREADS))


def headline(data):
    """The series of the run's headline rows: the searches timed at every ISA (purpose "isa") at
    1 thread, at the best ISA, and POM-32 at every ISA."""
    best = data["provenance"].get("best_isa")
    out = set()
    for r in data["rows"]:
        if (r.get("speed") and r["kind"] == "trace" and "isa" in r.get("purposes", []) and r["threads"] == 1
                and (r["backend"] == best or (r.get("technique") == "pom" and r.get("layers") == "32"))):
            out.add(tuple(history.series_fields(r)[k] for k in history.SERIES_FIELDS))
    return out


def speed_alert(key, new, past):
    """The speed alert of one series, or None: new and past are history rows, past oldest first."""
    fastest = [float(r["rays_per_second_max"]) for r in past[-RUNS:]]
    baseline = statistics.median(fastest)
    spread = MAD_TO_SIGMA * statistics.median(abs(x - baseline) for x in fastest)
    value = float(new["rays_per_second_max"])
    change = value / baseline - 1
    if abs(change) <= MIN_CHANGE or abs(value - baseline) <= SPREADS * spread:
        return None
    return {"series": history.series_name(key), "kind": "speed", "metric": "rays_per_second_max",
            "baseline": baseline, "baseline_spread": spread, "new": value, "change": change,
            "message": "%s %.0f%% %s: fastest repetition %.4g rays/s against %.4g (spread %.2g) over the last %d runs"
                       % (history.series_name(key), 100 * abs(change), "slower" if change < 0 else "faster", value,
                          baseline, spread, len(fastest))}


def behaviour_alert(key, new, previous):
    """The behaviour alert of one series (its first changed measure; the message names all), or None."""
    changed = []
    for m in history.MEASURES:
        a, b = previous[m], new[m]
        if a and b and abs(float(b) - float(a)) > REL_TOL * max(abs(float(a)), abs(float(b))):
            changed.append((m, float(a), float(b)))
    if not changed:
        return None
    m, a, b = changed[0]
    return {"series": history.series_name(key), "kind": "behaviour", "metric": m, "baseline": a, "baseline_spread": 0.0,
            "new": b, "change": b / a - 1 if a else None,  # no relative change from 0
            "message": "%s: %s (commit %s before)" % (history.series_name(key), ", ".join(
                "%s %.6g -> %.6g" % c for c in changed), previous["commit"])}


def check(data, rows, new):
    """The alerts of the run whose history rows are `new`, against the earlier rows of its machine."""
    machine = new[0]["machine"] if new else history.machine_key(history.machine_parts(data["provenance"]))
    date = new[0]["date"] if new else ""
    past = {}
    for r in rows:
        if r["machine"] == machine and r["date"] < date:
            past.setdefault(history.series(r), []).append(r)
    for runs in past.values():
        runs.sort(key=lambda r: r["date"])
    heads = headline(data)
    found, tested = [], 0
    for r in new if history.is_known(machine) else []:
        key = history.series(r)
        earlier = past.get(key, [])
        if not earlier:
            continue
        tested += 1
        alert = behaviour_alert(key, r, earlier[-1])
        if alert:
            found.append(alert)
        if key in heads and len(earlier) >= MIN_RUNS:
            alert = speed_alert(key, r, earlier)
            if alert:
                found.append(alert)
    return {"format_version": 1, "machine": machine, "series_tested": tested, "rule": RULE, "alerts": found}


def write_json(run_dir, found):
    """RUN/alerts.json."""
    atomic_write(os.path.join(run_dir, "alerts.json"), json.dumps(found, indent=1) + "\n")


def keep(csv_path, rows, new, found):
    """alerts.csv: its rows (as read, checked) with the run's alerts, replacing an earlier record of
    the same run; the caller holds the history's lock."""
    date, commit = (new[0]["date"], new[0]["commit"]) if new else ("", "")
    kept = [r for r in rows if (r["date"], r["commit"], r["machine"]) != (date, commit, found["machine"])]
    kept += [{"date": date, "commit": commit, "machine": found["machine"],
              **{k: ("%.6g" % a[k] if isinstance(a[k], float) else a[k]) for k in CSV_COLUMNS[3:]}} for a in found["alerts"]]
    history.write(csv_path, kept, ALERTS)
