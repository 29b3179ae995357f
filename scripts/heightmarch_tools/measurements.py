"""A run directory's files as the report and its page read them: measurements.json (formats 1 and
2), claims.json, recommendation.json and alerts.json; the rows of a run and their figures with
spreads.

Every speed is the median of a row's repetitions with their min and max; every ratio of two rows
is taken per round (rounds are interleaved, so round i of two rows forms a pair) and summarised as
the median of the per-round ratios with their min and max (docs/measurements.md).
"""
import csv
import io
import os

from .errors import Unusable
from .readers import read_json
from .spreads import per_round

MEASUREMENTS_FORMAT = "heightmarch-measurements"
MEASUREMENTS_VERSION = 2  # the newest this reads; 1: the measures were named uv_mean, uv_p95, ...
CLAIMS_VERSION = 2        # 1: a bare list of claims
KINDS = ("trace", "glsl", "roofline", "ceiling", "naive", "autovec", "exact")
NON_ISA_BACKENDS = ("glsl", "naive", "exact")
# The configuration every backend runs (ISA sweep, naive port, roofline, thread scaling).
HEADLINE_TECHNIQUE, HEADLINE_LAYERS = "pom", "32"
ANY = object()  # a field that `Run.partner` does not compare
# The docs the report links to, two levels above this package: the repository's docs/ beside
# scripts/ in a checkout, share/heightmarch/docs beside share/heightmarch/python/ where installed.
DOCS = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__)))), "docs")
# Sections of the docs the report points at (docs/techniques.md's are measured there).
SHADOW_COUNTS = ("techniques.md", "shadow-sample-counts-cpu-vs-glsl")
MAXMIP_PEAK = ("techniques.md", "maxmip-at-a-grazing-one-texel-peak")


# ---------------------------------------------------------------------------------------------
# Files

def require(condition, what):
    if not condition:
        raise Unusable(what)


def upgrade(data):
    """A format 1 measurements.json as format 2: its measures under their one name (uv_p95 ->
    uv_error_p95), as bench.json and every newer file name them."""
    if data.get("schema") != MEASUREMENTS_FORMAT + "/1":
        return data
    data = dict(data, format=MEASUREMENTS_FORMAT, format_version=1)
    for row in data.get("rows") or []:
        errors = row.get("errors") if isinstance(row, dict) else None
        if isinstance(errors, dict):
            row["errors"] = {("uv_error_" + k[3:] if k.startswith("uv_") else k): v for k, v in errors.items()}
    return data


def validate(data):
    """Checks the fields the report reads, so a malformed file fails with one line, not a trace."""
    require(isinstance(data, dict) and data.get("format") == MEASUREMENTS_FORMAT
            and isinstance(data.get("format_version"), int) and 1 <= data["format_version"] <= MEASUREMENTS_VERSION,
            "not a %s file of format 1 to %d" % (MEASUREMENTS_FORMAT, MEASUREMENTS_VERSION))
    for key in ("provenance", "plan", "load"):
        require(isinstance(data.get(key), dict), "%s is missing" % key)
    require(isinstance(data.get("techniques"), list) and
            all(isinstance(t, dict) and {"name", "layered", "color", "marker"} <= set(t) for t in data["techniques"]),
            "techniques must list {name, layered, color, marker}")
    require(isinstance(data.get("backends"), list) and data["backends"], "backends is missing")
    require(isinstance(data.get("rows"), list), "rows is missing")
    names = {t["name"] for t in data["techniques"]}
    for row in data["rows"]:
        require(isinstance(row, dict), "a row is not an object")
        where = "row %s" % row.get("id", "?")
        require(row.get("kind") in KINDS, "%s: kind %r is none of %s" % (where, row.get("kind"), ", ".join(KINDS)))
        require(row.get("backend") in data["backends"], "%s: backend %r is not in backends" % (where, row.get("backend")))
        require(row.get("technique") is None or row["technique"] in names or row["technique"] == "shader",
                "%s: technique %r is not in techniques" % (where, row.get("technique")))
        require(isinstance(row.get("threads"), int), "%s: threads is not an integer" % where)
        hf, view = row.get("heightfield"), row.get("view")
        require(isinstance(hf, dict) and {"label", "width", "height"} <= set(hf), "%s: heightfield needs label, width, height" % where)
        require(isinstance(view, dict) and {"kind", "width", "height"} <= set(view), "%s: view needs kind, width, height" % where)
        require(row.get("errors") is None or isinstance(row["errors"], dict), "%s: errors is not an object" % where)
        speed = row.get("speed")
        if speed is not None:
            seconds = speed.get("seconds") or []
            rounds = (speed.get("rays_per_second") or {}).get("rounds") or []
            require(seconds and len(rounds) == len(seconds) and all(s > 0 for s in seconds) and all(r > 0 for r in rounds),
                    "%s: speed needs as many positive rays_per_second.rounds as seconds" % where)


def read_claims(path):
    """claims.json's claims (a list), whichever format; None without the file."""
    if not os.path.exists(path):
        return None
    data = read_json(path)
    claims = data if isinstance(data, list) else data.get("claims") if isinstance(data, dict) else None
    require(isinstance(claims, list) and all(isinstance(c, dict) and {"id", "claim", "verdict"} <= set(c) for c in claims),
            "%s: not a list of claims with id, claim and verdict" % path)
    return claims


def read_optional(path, format_name):
    """A run's recommendation.json or alerts.json, None without it."""
    if not os.path.exists(path):
        return None
    data = read_json(path)
    require(isinstance(data, dict) and "format_version" in data and data.get("format", format_name) == format_name,
            "%s: not a %s file" % (path, format_name))
    return data


def load_run(run_dir):
    path = os.path.join(run_dir, "measurements.json")
    data = read_json(path)
    require(isinstance(data, dict), "%s: not a JSON object" % path)
    data = upgrade(data)
    try:
        validate(data)
    except Unusable as e:
        raise Unusable("%s: %s" % (path, e))
    return Run(data, run_dir)


# ---------------------------------------------------------------------------------------------
# Figures with their spread

def rays_rounds(row):
    return row["speed"]["rays_per_second"]["rounds"] if row and row.get("speed") else None


def ns_per_ray_rounds(row):
    """The time of one ray per round, in nanoseconds (what a recommendation ranks by)."""
    rounds = rays_rounds(row)
    return [1e9 / r for r in rounds] if rounds else None


def samples_rounds(row):
    """Samples/s per repetition: the samples of one trace are the same in every repetition."""
    if not row or not row.get("speed") or not row.get("samples_known"):
        return None
    return [row["samples"] / s for s in row["speed"]["seconds"]]


def speedup(row, reference):
    """row's rays/s over reference's, per round (None when either is missing)."""
    return per_round(rays_rounds(row), rays_rounds(reference))


# ---------------------------------------------------------------------------------------------
# Rows

def view_name(view, angles=True):
    name = "%s %dx%d" % (view["kind"], view["width"], view["height"])
    if view.get("near_angle") is not None and (view["near_angle"], view["far_angle"]) != (30, 80):
        name = "%s:%g-%g %dx%d" % (view["kind"], view["near_angle"], view["far_angle"], view["width"], view["height"])
    if angles and view.get("theta") is not None:
        name += " theta %g phi %g" % (view["theta"], view.get("phi") or 0)
    return name


def depth_map(row):
    return "%dx%d" % (row["heightfield"]["width"], row["heightfield"]["height"])


def backend_label(row):
    """The backend as a reader tells rows apart: 'avx2', or 'avx2 autovec' for the auto-vectorised port."""
    return row["backend"] + (" autovec" if row["kind"] == "autovec" else "")


def config(row):
    """Every field that names a configuration; two rows with equal configs are the same measurement."""
    view = row["view"]
    return {"kind": row["kind"], "backend": row["backend"], "threads": row["threads"],
            "technique": row.get("technique"), "layers": row.get("layers"),
            "heightfield": row["heightfield"]["label"], "depth_map": depth_map(row),
            "view": (view["kind"], view["width"], view["height"], view.get("theta"), view.get("phi"),
                     view.get("near_angle"), view.get("far_angle")),
            "scene": (row.get("scale"), row.get("wrap"), row.get("discard"))}


def csv_value(value):
    """JSON's values as CSV text: numbers as they read back (repr: 0.1, not 0.100000001), true/false, empty for null."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value) if isinstance(value, float) else str(value)


def flat_row(row, prefix=""):
    """A row as flat (column, value) pairs: nested fields joined by '.', lists by ';'."""
    out = []
    for key, value in row.items():
        name = prefix + key
        if isinstance(value, dict):
            out += flat_row(value, name + ".")
        elif isinstance(value, list):
            out.append((name, ";".join(csv_value(v) for v in value)))
        else:
            out.append((name, csv_value(value)))
    return out


def measurements_csv(rows):
    """measurements.csv: one flat row per configuration, every field of measurements.json's rows
    (columns in first-seen order; empty where a row has no such field, or has it null)."""
    flat = [dict(flat_row(r)) for r in rows]
    columns = list(dict.fromkeys(k for f in flat for k in f))
    # an object null in some rows (errors, speed, images) is its fields' columns, left empty there
    columns = [c for c in columns if not any(other.startswith(c + ".") for other in columns)]
    out = io.StringIO()
    writer = csv.DictWriter(out, columns, lineterminator="\n", extrasaction="ignore")  # the nulls of those objects
    writer.writeheader()
    writer.writerows(flat)
    return out.getvalue()


class Run:
    def __init__(self, data, run_dir):
        self.dir = run_dir
        self.data = data
        self.provenance, self.plan, self.load = data["provenance"], data["plan"], data["load"]
        self.rows = data["rows"]
        self.by_id = {r.get("id"): r for r in self.rows}
        self.timed = [r for r in self.rows if r.get("speed")]
        self.techniques = [t["name"] for t in data["techniques"]]
        self.style = {t["name"]: t for t in data["techniques"]}
        self.backends = data["backends"]
        self.isas = [b for b in self.backends if b not in NON_ISA_BACKENDS]
        self.best_isa = self.provenance.get("best_isa") or (self.isas[-1] if self.isas else None)
        self.heightfields = list(dict.fromkeys(r["heightfield"]["label"] for r in self.rows))
        self.configs = [(config(r), r) for r in self.timed]
        # the technique x layers matrix: technique rows only (an exact row may serve the matrix too)
        self.matrix = sorted((r for r in self.with_purpose("matrix") if r.get("technique")), key=self.order)

    def with_purpose(self, purpose):
        return [r for r in self.rows if purpose in r.get("purposes", [])]

    def partner(self, row, **changes):
        """The timed row measured like `row` except for `changes` (ANY: not compared)."""
        want = dict(config(row), **changes)
        for c, r in self.configs:
            if all(v is ANY or c[k] == v for k, v in want.items()):
                return r
        return None

    def order(self, row):
        """Heightfield, technique (registry order; none first), layers (fixed counts, then ranges), threads."""
        technique = row.get("technique")
        lo, hi = row.get("min_layers") or 0, row.get("max_layers") or 0
        return (self.heightfields.index(row["heightfield"]["label"]),
                -1 if technique not in self.techniques else self.techniques.index(technique),
                lo != hi, hi, lo, self.backends.index(row["backend"]), row["threads"])

    def label(self, row):
        """'pom 32', 'parallax' (techniques without a layer spec need none), or the kind for rows without technique."""
        technique = row.get("technique")
        if technique not in self.style:
            return technique or row["kind"]
        return technique + (" " + row["layers"] if self.style[technique]["layered"] else "")

    def is_headline(self, row):
        return row.get("technique") == HEADLINE_TECHNIQUE and row.get("layers") == HEADLINE_LAYERS

    def backend_names(self):
        """Every backend as backend_label names it: the list's, each ISA followed by its autovec form."""
        names = []
        for b in self.backends:
            names.append(b)
            if b in self.isas:
                names.append(b + " autovec")
        return names

    def describe(self, row):
        return "%s %s, %s, %d thread%s, %s" % (row["heightfield"]["label"], self.label(row), backend_label(row),
                                                row["threads"], "" if row["threads"] == 1 else "s", view_name(row["view"]))


def counted(n, word):
    return "%d %s%s" % (n, word, "" if n == 1 else "s")


def groups(rows, key):
    """Rows grouped by key(row), in first-seen order."""
    out = {}
    for r in rows:
        out.setdefault(key(r), []).append(r)
    return out


def backend_colours(names):
    """One colour per backend name, for every plot and the page: an ISA and its autovec form ('avx2
    autovec' or, as the history writes it, 'avx2-autovec') a dark and light pair of tab20, the other
    backends the dark colour of a pair of their own, so no two of ten share a colour."""
    import matplotlib  # only the plots and the page need it
    cmap = matplotlib.colormaps["tab20"]  # a ListedColormap: an integer picks that colour
    colours, pairs = {}, {}
    for name in names:
        base = name[:-len("autovec") - 1] if name.endswith("autovec") else None
        if base in pairs:
            colours[name] = matplotlib.colors.to_hex(cmap(2 * pairs[base] + 1))
        else:
            pairs[name] = len(pairs) % 10
            colours[name] = matplotlib.colors.to_hex(cmap(2 * pairs[name]))
    return colours


def machine_rows(run):
    """Where a run's figures come from, as (name, text) rows: the machine, the build, the plan, the
    views and depth maps, the load."""
    p, plan, load = run.provenance, run.plan, run.load
    averages = lambda values: "/".join("%.2f" % x for x in values or []) or "?"
    views = sorted({view_name(r["view"], angles=False) for r in run.rows})
    maps = list(dict.fromkeys("%s %s" % (r["heightfield"]["label"], depth_map(r)) for r in run.rows))
    return [("CPU", p.get("cpu", "?")), ("cores", p.get("cores", "?")), ("best ISA", run.best_isa or "?"),
            ("threads", p.get("threads", "?")), ("compiler", p.get("compiler", "?")),
            ("commit", "%s%s" % (p.get("commit", "?"), " (dirty worktree)" if p.get("dirty") else "")),
            ("build type", p.get("build_type", "?")), ("date", p.get("date", "?")),
            ("plan", "%s, %s repetitions of at least %s s per timed row" % (
                plan.get("name", "?"), plan.get("repetitions", "?"), plan.get("min_seconds_per_repetition", "?"))),
            ("views", ", ".join(views) or "-"), ("depth maps", ", ".join(maps) or "-"),
            ("load averages (1/5/15 min)", "before %s, after %s" % (averages(load.get("before")), averages(load.get("after")))),
            ("other processes' CPU share", "%.1f%%" % (100 * (load.get("other_cpu_share") or 0)))]


def docs_link(run, page, anchor=None):
    """A link from the run directory to a page of docs/, relative to wherever the run was written
    (results/<run>/ or any --out), so it holds in a checkout."""
    target = os.path.relpath(os.path.join(DOCS, page), os.path.abspath(run.dir))
    return target + ("#" + anchor if anchor else "")


def glsl_pairs(run):
    """(CPU row at the best ISA, GLSL row) at the same configuration and threads, for every GLSL row."""
    return [(run.partner(g, kind="trace", backend=run.best_isa), g) for g in sorted(
        (r for r in run.timed if r["kind"] == "glsl"), key=run.order)]


def searches_per_isa(run):
    """[(heightfield, technique label, threads, GLSL row, {isa: row})] of the searches timed at every ISA."""
    rows = sorted((r for r in run.timed if "isa" in r.get("purposes", []) and r["kind"] == "trace"
                   and r.get("technique")), key=run.order)
    out = []
    for (hf, technique, threads), group in groups(rows, lambda r: (r["heightfield"]["label"], run.label(r),
                                                                    r["threads"])).items():
        out.append((hf, technique, threads, run.partner(group[0], kind="glsl", backend="glsl"),
                    {r["backend"]: r for r in group}))
    return out
