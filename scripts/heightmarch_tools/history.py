"""The record across runs: results/history.csv, one row per timed row of every recorded run, each
row naming its machine (record_run.py appends a run; alerts.py and history_plot.py read it).
"""
import csv
import io
import os
import re

from .errors import Unusable
from .measurements import depth_map, view_name
from .spreads import spread
from .writers import atomic_write

MACHINE_PARTS = ["cpu", "cores", "best_isa", "compiler", "build_type"]
SERIES_FIELDS = ["backend", "threads", "heightfield", "technique", "layers", "view", "depth_map"]
# Deterministic measures: any change at the same configuration is a behaviour change.
MEASURES = ["samples_per_ray", "uv_error_mean", "uv_error_p95", "wrong_surface_rate"]
COLUMNS = (["date", "commit", "machine"] + MACHINE_PARTS + SERIES_FIELDS
           + ["rays_per_second_median", "rays_per_second_min", "rays_per_second_max"] + MEASURES)
UNKNOWN_PREFIX = "unknown-"


# ---------------------------------------------------------------------------------------------
# Machines

def slug(text):
    return re.sub(r"[^a-z0-9.]+", "-", text.lower()).strip("-")


def machine_parts(provenance):
    """The parts that name a machine, as text ("" where the run does not say)."""
    return {k: "" if provenance.get(k) is None else str(provenance[k]) for k in MACHINE_PARTS}


def machine_key(parts):
    """A stable short name of the machine: 'amd-epyc-f25m17-2c-avx512-gnu-12.2.0-release'. A CPU
    named without family and model, or a part missing, makes it an unknown machine
    ('unknown-amd-epyc-2c-avx2-...', '?' for a missing part): series are never joined across
    machines, and an unknown machine is never a new run's past."""
    m = re.fullmatch(r"(.*?) \(family (\d+), model (\d+)\)", parts["cpu"])
    cpu = "%s-f%sm%s" % (slug(m.group(1)), m.group(2), m.group(3)) if m else slug(parts["cpu"]) or "?"
    key = "-".join([cpu, (parts["cores"] or "?") + "c", parts["best_isa"] or "?", slug(parts["compiler"]) or "?",
                    slug(parts["build_type"]) or "?"])
    return key if m and all(parts.values()) else UNKNOWN_PREFIX + key


def is_known(machine):
    return not machine.startswith(UNKNOWN_PREFIX)


# ---------------------------------------------------------------------------------------------
# Rows

def backend(row):
    """The backend as history tells rows apart: 'avx2', or 'avx2-autovec' for the auto-vectorised port."""
    return row["backend"] + ("-autovec" if row["kind"] == "autovec" else "")


def series_fields(row):
    """A measurements.json row's series: what it ran, where and at which sizes."""
    return {"backend": backend(row), "threads": str(row["threads"]), "heightfield": row["heightfield"]["label"],
            # rows without a technique (roofline, exact) are named by their kind
            "technique": row.get("technique") or row["kind"], "layers": row.get("layers") or "",
            "view": view_name(row["view"]), "depth_map": depth_map(row)}


def series(row):
    """A history row's series key."""
    return tuple(row[k] for k in SERIES_FIELDS)


def series_name(key):
    f = dict(zip(SERIES_FIELDS, key))
    return "%s%s, %s, %s thread%s, %s %s, %s view" % (
        f["technique"], " " + f["layers"] if f["layers"] not in ("", "1") else "", f["backend"],
        f["threads"], "" if f["threads"] == "1" else "s", f["heightfield"], f["depth_map"], f["view"])


def measure(row, name):
    """A deterministic measure of a measurements.json row as text ("" where not measured)."""
    errors = row.get("errors") or {}
    if name == "samples_per_ray":
        value = row.get("samples_per_ray") if row.get("samples_known") else None
    else:
        # measurements.json names them as bench.json does (uv_error_mean) or, before, without "error_"
        value = errors.get(name, errors.get(name.replace("uv_error_", "uv_")))
    return "" if value is None else "%.9g" % value


def rows_of_run(data):
    """One history row per timed row of a run's measurements.json."""
    p = data["provenance"]
    parts = machine_parts(p)
    head = {"date": p.get("date", ""), "commit": p.get("commit", ""), "machine": machine_key(parts), **parts}
    out = []
    for r in data["rows"]:
        if not r.get("speed"):
            continue
        s = spread(r["speed"]["rays_per_second"]["rounds"])
        out.append({**head, **series_fields(r),
                    "rays_per_second_median": "%.6g" % s[0], "rays_per_second_min": "%.6g" % s[1],
                    "rays_per_second_max": "%.6g" % s[2], **{m: measure(r, m) for m in MEASURES}})
    return out


def read(path, columns=COLUMNS):
    """The rows of a history file (or of alerts.csv with its columns); [] where it does not exist yet."""
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        if reader.fieldnames != columns:
            raise Unusable("%s: columns are not %s" % (path, ",".join(columns)))
        return list(reader)


def write(path, rows, columns=COLUMNS):
    out = io.StringIO()
    writer = csv.DictWriter(out, columns, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    atomic_write(path, out.getvalue())


def append(path, data):
    """Appends a run's rows (replacing an earlier record of the same date, commit and machine);
    all rows, and the run's."""
    new = rows_of_run(data)
    run = {(r["date"], r["commit"], r["machine"]) for r in new}
    rows = [r for r in read(path) if (r["date"], r["commit"], r["machine"]) not in run] + new
    write(path, rows)
    return rows, new
