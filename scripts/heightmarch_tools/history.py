"""The record across runs: results/history.csv, one row per timed row of every recorded run, each
row naming its machine (record_run.py records a run; alerts.py and history_plot.py read it). Its
rows are read checked, a malformed one refused with its line number; repair() drops those,
naming each.
"""
import csv
import io
import os
import re

from .cli import Parser
from .errors import Unusable
from .escape import csv_cell, terminal
from .measurements import depth_map, gl_label, view_name
from .readers import Where, read_csv, read_text
from .spreads import spread
from .writers import atomic_write, locked

MACHINE_PARTS = ["cpu", "cores", "best_isa", "compiler", "build_type"]
SERIES_FIELDS = ["backend", "threads", "heightfield", "technique", "layers", "view", "depth_map", "filter"]
# Deterministic measures: any change at the same configuration is a behaviour change. SIMD use
# (the packet kernels' share of busy lanes) came last: older files lack its column.
MEASURES = ["samples_per_ray", "uv_error_mean", "uv_error_p95", "wrong_surface_rate", "simd_utilization"]
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
    """The backend as history tells rows apart: 'avx2', 'avx2-autovec' for the auto-vectorised port,
    and GLSL by its renderer ('glsl (llvmpipe, LLVM 15.0.6, 256 bits; OSMesa)'): another renderer, or
    another GL path to it, is another series, as another machine is."""
    if row["kind"] == "glsl":
        return gl_label(row)
    return row["backend"] + ("-autovec" if row["kind"] == "autovec" else "")


def series_fields(row):
    """A measurements.json row's series: what it ran, where and at which sizes, as the history
    holds them (as_written)."""
    return as_written({"backend": backend(row), "threads": str(row["threads"]), "heightfield": row["heightfield"]["label"],
                       # rows without a technique (roofline, exact) are named by their kind
                       "technique": row.get("technique") or row["kind"], "layers": row.get("layers") or "",
                       "view": view_name(row["view"]), "depth_map": depth_map(row),
                       # the exact reference is every filter's: its one series; runs before filters read level 0
                       "filter": row.get("filter", "bilinear") or ""})


def series(row):
    """A history row's series key."""
    return tuple(row[k] for k in SERIES_FIELDS)


def series_name(key):
    f = dict(zip(SERIES_FIELDS, key))
    return "%s%s, %s, %s thread%s, %s %s, %s view%s" % (
        f["technique"], " " + f["layers"] if f["layers"] not in ("", "1") else "", f["backend"],
        f["threads"], "" if f["threads"] == "1" else "s", f["heightfield"], f["depth_map"], f["view"],
        ", " + f["filter"] if f["filter"] not in ("", "bilinear") else "")


def measure(row, name):
    """A deterministic measure of a measurements.json row as text ("" where not measured)."""
    errors = row.get("errors") or {}
    if name == "samples_per_ray":
        value = row.get("samples_per_ray") if row.get("samples_known") else None
    elif name == "simd_utilization":
        value = row.get("simd_utilization")
    else:
        # measurements.json names them as bench.json does (uv_error_mean) or, before, without "error_"
        value = errors.get(name, errors.get(name.replace("uv_error_", "uv_")))
    return "" if value is None else "%.9g" % value


def rows_of_run(data):
    """One history row per timed row of a run's measurements.json, as the history holds it."""
    p = data["provenance"]
    parts = machine_parts(p)
    head = {"date": p.get("date", ""), "commit": p.get("commit", ""), "machine": machine_key(parts), **parts}
    out = []
    for r in data["rows"]:
        if not r.get("speed"):
            continue
        s = spread(r["speed"]["rays_per_second"]["rounds"])
        out.append(as_written({**head, **series_fields(r),
                               "rays_per_second_median": "%.6g" % s[0], "rays_per_second_min": "%.6g" % s[1],
                               "rays_per_second_max": "%.6g" % s[2], **{m: measure(r, m) for m in MEASURES}}))
    return out


# ---------------------------------------------------------------------------------------------
# The files: history.csv and alerts.csv, each a header and rows checked cell by cell

class Table:
    """A CSV file of the record: its columns, the numeric ones with their lowest value (empty
    cells allowed or not); every other column is text, written through escape.csv_cell."""

    def __init__(self, columns, numbers, may_be_empty=(), integers=()):
        self.columns, self.numbers, self.may_be_empty, self.integers = columns, numbers, may_be_empty, integers

    def text_columns(self):
        return [c for c in self.columns if c not in self.numbers]

    def check(self, where, cells):
        """The row of `cells` as {column: text}, or Unusable naming its line and what is wrong."""
        where.check(len(cells) == len(self.columns), "%d cells, not %d%s" % (
            len(cells), len(self.columns),
            " (a merge conflict's marker)" if cells and cells[0].startswith(("<<<<<<<", "=======", ">>>>>>>")) else ""))
        row = dict(zip(self.columns, cells))
        for column, low in self.numbers.items():
            value = where[column].decimal(row[column], low, empty=column in self.may_be_empty)
            if column in self.integers:
                where[column].integer(value, int(low))
        for column in ("date", "machine"):
            where[column].check(row[column] != "", "is empty")
        return row


HISTORY = Table(COLUMNS, dict({"threads": 1, "rays_per_second_median": 0.0, "rays_per_second_min": 0.0,
                               "rays_per_second_max": 0.0}, **{m: 0.0 for m in MEASURES}),
                may_be_empty=MEASURES, integers=("threads",))


def without(*names):
    """HISTORY without some of its columns: a history written before they existed."""
    return Table([c for c in COLUMNS if c not in names], {k: v for k, v in HISTORY.numbers.items() if k not in names},
                 may_be_empty=[m for m in MEASURES if m not in names], integers=("threads",))


# Histories written before a column existed, and what their rows were: before SIMD use was
# recorded, its cell is empty; before filters, every row read level 0.
EARLIER = [(without("simd_utilization"), {"simd_utilization": ""}),
           (without("filter"), {"filter": "bilinear"}),
           (without("filter", "simd_utilization"), {"filter": "bilinear", "simd_utilization": ""})]
REPAIR = "scripts/repair-history drops the rows it cannot read, naming each"


def as_written(row, table=HISTORY):
    """A row as the file holds it: text cells through escape.csv_cell (idempotent)."""
    return {k: csv_cell(v) if k in table.text_columns() else v for k, v in row.items()}


def header(path):
    """The first row of a CSV file; None where it does not exist or is empty."""
    if not os.path.lexists(path):
        return None
    return next(csv.reader(io.StringIO(read_text(path), newline="")), None)


def layout(path, table=HISTORY):
    """The table a file was written with and what its rows lack: a history's of today, or of before
    a column (EARLIER) by its header."""
    if table is HISTORY:
        found = header(path)
        for earlier, implied in EARLIER:
            if found == earlier.columns:
                return earlier, implied
    return table, {}


def read(path, table=HISTORY):
    """The rows of a history file (or of alerts.csv, alerts.ALERTS), every cell checked; []
    where it does not exist yet. A malformed row is refused with its line number."""
    written, implied = layout(path, table)
    rows = []
    for line, cells in read_csv(path, written.columns):
        try:
            rows.append(dict(written.check(Where("%s: line %d" % (terminal(path), line)), cells), **implied))
        except Unusable as e:
            raise Unusable("%s (%s)" % (e, REPAIR) if table is HISTORY else str(e))
    return rows


def write(path, rows, table=HISTORY):
    """The whole file, atomically (the caller holds its lock: writers.locked)."""
    out = io.StringIO()
    writer = csv.DictWriter(out, table.columns, lineterminator="\n")
    writer.writeheader()
    writer.writerows(as_written(r, table) for r in rows)
    atomic_write(path, out.getvalue())


def merged(rows, new):
    """The history with a run's rows: an earlier record of the same date, commit and machine (the
    same run recorded again) replaced."""
    run = {(r["date"], r["commit"], r["machine"]) for r in new}
    return [r for r in rows if (r["date"], r["commit"], r["machine"]) not in run] + new


def repair(argv=None):
    """scripts/repair-history HISTORY.csv [--dry-run]: writes the history back without the rows
    it cannot read, each named on stdout with its line and why (so none is lost unseen)."""
    parser = Parser(prog="repair-history", description=repair.__doc__.splitlines()[0])
    parser.add_argument("history")
    parser.add_argument("--dry-run", action="store_true", help="name the rows it would drop, change nothing")
    args = parser.parse_args(argv)
    with locked(args.history):
        kept, dropped = [], 0
        written, implied = layout(args.history)
        for line, cells in read_csv(args.history, written.columns):
            try:
                kept.append(dict(written.check(Where("line %d" % line), cells), **implied))
            except Unusable as e:
                dropped += 1
                print("drops %s: %s" % (e, terminal(",".join(cells))[:200]))
        if dropped and not args.dry_run:
            write(args.history, kept)
    print("%s: %d rows kept, %d %s" % (terminal(args.history), len(kept), dropped,
                                       "would be dropped" if args.dry_run else "dropped"))
    return 0
