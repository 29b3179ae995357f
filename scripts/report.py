#!/usr/bin/python3
"""Writes RUN_DIR/report.md and RUN_DIR/plots/*.png from RUN_DIR/measurements.json.

Usage: scripts/report.py RUN_DIR [--history results/history.csv]

Inputs: measurements.json (the run's typed rows, docs/measurements.md) and, optionally,
claims.json. Every speed is the median of the repetitions with their min-max; every ratio of two
rows is taken per round (rounds are interleaved, so round i of two rows forms a pair) and shown as
the median of the per-round ratios with their min-max. With --history, the run is recorded
(scripts/record_run.py: the history CSV, RUN_DIR/alerts.json, the history plot); a run's
alerts.json opens the report.
"""
import argparse
import math
import os
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FuncFormatter  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import alerts  # noqa: E402
import record_run  # noqa: E402
from benchmark_results import Unusable, atomic_write, per_round, read_json, relative_spread, spread  # noqa: E402

# The configuration that every backend runs (ISA sweep, naive port, roofline, thread scaling) and
# that the history follows.
HEADLINE_TECHNIQUE, HEADLINE_LAYERS = "pom", "32"
NON_ISA_BACKENDS = ("glsl", "naive", "exact")
KINDS = ("trace", "glsl", "roofline", "ceiling", "naive", "autovec", "exact")
# Kinds that run an ISA's code without being its packet kernels: their rows name the ISA as backend.
ANCHOR_KINDS = ("roofline", "ceiling", "autovec")
SPREAD_LIMIT = 0.20  # (max - min) / median above this is flagged as a disturbed timing
ANY = object()  # a field that `partner` does not compare
NOT_MEASURED = "Not measured in this run."
MAX_PLOT_PIXELS = 1600  # widest plot, so a page shows it whole
ERROR_TARGETS = (1.0, 0.25, 0.05)  # p95 uv error targets of the summary, in texels
# Highlights of the cheapest configuration per target: black rings (no technique is black), told
# apart by their size, their target's line style and a label.
TARGET_STYLES = {1.0: "-", 0.25: "--", 0.05: ":"}


class InputError(Exception):
    pass


# ---------------------------------------------------------------------------------------------
# Input

def require(condition, what):
    if not condition:
        raise InputError(what)


def validate(data):
    """Checks the fields the report reads, so a malformed file fails with one line, not a trace."""
    require(isinstance(data, dict) and str(data.get("schema", "")).startswith("heightmarch-measurements/"),
            "schema is not heightmarch-measurements/*")
    for key in ("provenance", "plan", "load"):
        require(isinstance(data.get(key), dict), "%s is missing" % key)
    require(isinstance(data.get("techniques"), list) and
            all({"name", "layered", "color", "marker"} <= set(t) for t in data["techniques"]),
            "techniques must list {name, layered, color, marker}")
    require(isinstance(data.get("backends"), list) and data["backends"], "backends is missing")
    require(isinstance(data.get("rows"), list), "rows is missing")
    names = {t["name"] for t in data["techniques"]}
    for row in data["rows"]:
        where = "row %s" % row.get("id", "?")
        require(row.get("kind") in KINDS, "%s: kind %r is none of %s" % (where, row.get("kind"), ", ".join(KINDS)))
        require(row.get("backend") in data["backends"], "%s: backend %r is not in backends" % (where, row.get("backend")))
        require(row.get("technique") is None or row["technique"] in names,
                "%s: technique %r is not in techniques" % (where, row.get("technique")))
        require(isinstance(row.get("threads"), int), "%s: threads is not an integer" % where)
        hf, view = row.get("heightfield"), row.get("view")
        require(isinstance(hf, dict) and {"label", "width", "height"} <= set(hf), "%s: heightfield needs label, width, height" % where)
        require(isinstance(view, dict) and {"kind", "width", "height"} <= set(view), "%s: view needs kind, width, height" % where)
        speed = row.get("speed")
        if speed is not None:
            seconds = speed.get("seconds") or []
            rounds = (speed.get("rays_per_second") or {}).get("rounds") or []
            require(seconds and len(rounds) == len(seconds) and all(s > 0 for s in seconds) and all(r > 0 for r in rounds),
                    "%s: speed needs as many positive rays_per_second.rounds as seconds" % where)


def load_run(run_dir):
    data = read_json(os.path.join(run_dir, "measurements.json"))
    try:
        validate(data)
    except InputError as e:
        raise InputError("%s: %s" % (os.path.join(run_dir, "measurements.json"), e))
    claims_path = os.path.join(run_dir, "claims.json")
    claims = read_json(claims_path) if os.path.exists(claims_path) else None
    return Run(data), claims


# ---------------------------------------------------------------------------------------------
# Figures with their spread

def fmt_spread(s, digits=1, scale=1.0, unit=""):
    if s is None:
        return "-"
    f = "%%.%df" % digits
    return "%s%s (%s-%s)" % (f % (s[0] * scale), unit, f % (s[1] * scale), f % (s[2] * scale))


def fmt_ratio(s):
    return fmt_spread(s, 2, unit="x")


def fmt(value, digits=3, scale=1.0, unit=""):
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "-"
    return ("%%.%df%%s" % digits) % (value * scale, unit)


def counted(n, word):
    return "%d %s%s" % (n, word, "" if n == 1 else "s")


def load_averages(values):
    return "/".join("%.2f" % x for x in values or []) or "?"


# ---------------------------------------------------------------------------------------------
# Rows

def rays_rounds(row):
    return row["speed"]["rays_per_second"]["rounds"] if row and row.get("speed") else None


def samples_rounds(row):
    """Samples/s per repetition: the samples of one trace are the same in every repetition."""
    if not row or not row.get("speed") or not row.get("samples_known"):
        return None
    return [row["samples"] / s for s in row["speed"]["seconds"]]


def view_name(view, angles=True):
    name = "%s %dx%d" % (view["kind"], view["width"], view["height"])
    if angles and view.get("theta") is not None:
        name += " theta %g phi %g" % (view["theta"], view.get("phi") or 0)
    return name


def depth_map(row):
    return "%dx%d" % (row["heightfield"]["width"], row["heightfield"]["height"])


def config(row):
    """Every field that names a configuration; two rows with equal configs are the same measurement."""
    view = row["view"]
    return {"kind": row["kind"], "backend": row["backend"], "threads": row["threads"],
            "technique": row.get("technique"), "layers": row.get("layers"),
            "heightfield": row["heightfield"]["label"],
            "view": (view["kind"], view["width"], view["height"], view.get("theta"), view.get("phi")),
            "scene": (row.get("scale"), row.get("wrap"), row.get("discard"))}


class Run:
    def __init__(self, data):
        self.provenance, self.plan, self.load = data["provenance"], data["plan"], data["load"]
        self.rows = data["rows"]
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
                -1 if technique is None else self.techniques.index(technique),
                lo != hi, hi, lo, self.backends.index(row["backend"]), row["threads"])

    def label(self, row):
        """'pom 32', 'parallax' (one-sample techniques need no layers), or the kind for rows without technique."""
        technique = row.get("technique")
        if technique is None:
            return row["kind"]
        return technique + (" " + row["layers"] if self.style[technique]["layered"] else "")

    def is_headline(self, row):
        return row.get("technique") == HEADLINE_TECHNIQUE and row.get("layers") == HEADLINE_LAYERS

    def backend_colors(self, extra=()):
        """The one backend palette: a fixed colour per position in `backends`, unknown ones after it."""
        names = list(dict.fromkeys(list(self.backends) + list(extra)))
        cmap = plt.get_cmap("tab10")
        return {b: cmap(i % 10) for i, b in enumerate(names)}

    def describe(self, row):
        return "%s %s, %s, %s, %s" % (row["heightfield"]["label"], self.label(row), row["backend"],
                                       counted(row["threads"], "thread"), view_name(row["view"]))


def backend_label(row):
    """The backend as a reader tells rows apart: 'avx2', or 'avx2 autovec' for the auto-vectorised port."""
    return row["backend"] + (" autovec" if row["kind"] == "autovec" else "")


def mrays(row):
    return fmt_spread(spread(rays_rounds(row)), 1, 1e-6)


def msamples(row):
    return fmt_spread(spread(samples_rounds(row)), 0, 1e-6)


def speedup(row, reference):
    """row's rays/s over reference's, per round (None when either is missing)."""
    return per_round(rays_rounds(row), rays_rounds(reference))


# ---------------------------------------------------------------------------------------------
# Markdown

def md_table(columns, rows):
    """columns: [(title, right-aligned)]; rows: lists of cells."""
    lines = ["| " + " | ".join(t for t, _ in columns) + " |",
             "|" + "|".join("---:" if right else "---" for _, right in columns) + "|"]
    return lines + ["| " + " | ".join(str(c) for c in cells) + " |" for cells in rows]


def section(title, body):
    return ["", "## " + title, ""] + (body or [NOT_MEASURED])


def groups(rows, key):
    """Rows grouped by key(row), in first-seen order."""
    out = {}
    for r in rows:
        out.setdefault(key(r), []).append(r)
    return out


def section_machine(run):
    p, plan, load = run.provenance, run.plan, run.load
    views = sorted({view_name(r["view"], angles=False) for r in run.rows})
    maps = list(dict.fromkeys("%s %s" % (r["heightfield"]["label"], depth_map(r)) for r in run.rows))
    rows = [("CPU", p.get("cpu", "?")), ("cores", p.get("cores", "?")), ("best ISA", run.best_isa or "?"),
            ("threads", p.get("threads", "?")), ("compiler", p.get("compiler", "?")),
            ("commit", "%s%s" % (p.get("commit", "?"), " (dirty worktree)" if p.get("dirty") else "")),
            ("build type", p.get("build_type", "?")), ("date", p.get("date", "?")),
            ("plan", "%s, %s repetitions of at least %s s per timed row" % (
                plan.get("name", "?"), plan.get("repetitions", "?"), plan.get("min_seconds_per_repetition", "?"))),
            ("views", ", ".join(views) or "-"), ("depth maps", ", ".join(maps) or "-"),
            ("load averages (1/5/15 min)", "before %s, after %s" % (load_averages(load.get("before")),
                                                                   load_averages(load.get("after")))),
            ("other processes' CPU share", fmt(load.get("other_cpu_share"), 1, 100, "%"))]
    return ["## Machine and provenance", ""] + md_table([("", False), ("", False)], rows)


def section_warnings(run, faults):
    """The block under the machine table: a busy machine, disturbed timings, roofline and ceiling faults."""
    lines = []
    load = run.load
    if load.get("busy"):
        lines.append("> **Warning: the machine was busy during this run** (%s). Load averages before %s, after %s; "
                     "other processes used %s of the CPU time while timing. Speeds and ratios may be disturbed." % (
                         "; ".join(load.get("busy_reasons") or ["no reason given"]),
                         load_averages(load.get("before")), load_averages(load.get("after")),
                         fmt(load.get("other_cpu_share"), 1, 100, "%")))
    noisy = sorted(((relative_spread(spread(rays_rounds(r))), r) for r in run.timed), key=lambda x: -x[0])
    noisy = [(s, r) for s, r in noisy if s > SPREAD_LIMIT]
    if noisy:
        if lines:
            lines.append(">")
        lines.append("> **Warning: %d of %d timed rows spread by more than %d%%** ((max-min)/median of rays/s); "
                     "the worst: %s." % (len(noisy), len(run.timed), 100 * SPREAD_LIMIT,
                                         "; ".join("%s (%.0f%%)" % (run.describe(r), 100 * s) for s, r in noisy[:5])))
    if faults:
        if lines:
            lines.append(">")
        lines.append("> **Warning: %s above 100%%**: timing disturbed, see the measurement faults under %s-%s." % (
                         counted(len(faults), "roofline or ceiling fraction"), HEADLINE_TECHNIQUE.upper(), HEADLINE_LAYERS))
    return [""] + lines if lines else []


def cheapest(rows, target):
    """The cheapest row with p95 uv error <= target: fewest samples per ray (deterministic), then the
    highest median rays/s; None when no row reaches the target."""
    ok = [r for r in rows if r.get("errors") and r.get("speed") and r.get("samples_per_ray") is not None
          and r["errors"]["uv_p95"] <= target]
    return min(ok, key=lambda r: (r["samples_per_ray"], -spread(rays_rounds(r))[0])) if ok else None


def summary_targets(run):
    """Per heightfield, the cheapest matrix configuration for each error target."""
    rows = [r for r in run.matrix if r.get("errors") and r.get("speed")]
    if not rows:
        return []
    first = rows[0]
    lines = ["### Cheapest configuration per error target", "",
             "Per heightfield, the configuration with the fewest height samples per ray (then the most rays/s) "
             "whose p95 uv error is at most the target, against the exact intersection (%s, %s, %s view). "
             "Mrays/s: median (min-max)." % (first["backend"], counted(first["threads"], "thread"), view_name(first["view"])),
             ""]
    cells = []
    for hf, group in groups(rows, lambda r: r["heightfield"]["label"]).items():
        line = [hf]
        for target in ERROR_TARGETS:
            best = cheapest(group, target)
            if best is None:
                closest = min(group, key=lambda r: r["errors"]["uv_p95"])
                line.append("none (best: %s, p95 %.3f)" % (run.label(closest), closest["errors"]["uv_p95"]))
            else:
                line.append("**%s**: %.1f samples/ray, %s Mrays/s, p95 %.3f" % (
                    run.label(best), best["samples_per_ray"], mrays(best), best["errors"]["uv_p95"]))
        cells.append(line)
    return lines + md_table([("heightfield", False)] + [("p95 <= %g texel" % t, False) for t in ERROR_TARGETS], cells)


def headline_ratios(run):
    """Per heightfield, the headline configuration's speed ratios: (label, [per-heightfield spreads])."""
    base = run.isas[0] if run.isas else None
    best = run.best_isa
    one = [r for r in sorted(run.timed, key=run.order) if run.is_headline(r) and r["kind"] == "trace"
           and r["backend"] == best and r["threads"] == 1 and r["view"]["kind"] == "default"]
    ratios = []
    for r in one:
        most = max((o for o in run.timed if config(o) == dict(config(r), threads=o["threads"])), key=lambda o: o["threads"])
        cpu_glsl = run.partner(most, kind="glsl", backend="glsl")
        ratios.append((r["heightfield"]["label"], [
            speedup(r, run.partner(r, backend=base)) if base != best else None,
            speedup(r, run.partner(r, kind="naive", backend="naive")),
            speedup(most, r) if most is not r else None,
            speedup(most, cpu_glsl)]))
    threads = max((r["threads"] for r in run.timed), default=1)
    columns = ["%s over %s, 1 thread" % (best, base), "%s over the naive port, 1 thread" % best,
               "%s over 1 at %s" % (counted(threads, "thread"), best),
               "%s over GLSL (llvmpipe), %s" % (best, counted(threads, "thread"))]
    return columns, ratios


def summary_ratios(run):
    columns, ratios = headline_ratios(run)
    if not ratios:
        return []
    return ["### Headline speed ratios", "",
            "%s-%s, default view: median (min-max) of the per-round ratios of rays/s." % (
                HEADLINE_TECHNIQUE.upper(), HEADLINE_LAYERS), ""] + md_table(
        [("heightfield", False)] + [(c, True) for c in columns],
        [[hf] + [fmt_ratio(s) for s in spreads] for hf, spreads in ratios])


def summary_claims(claims):
    if not claims:
        return []
    return ["### The claims: the tutorials' (C1-C10) and the papers' (P1-P3)", "",
            "Each claim's reading, rule, figures and checks: [claims.md](claims.md); the claims themselves: "
            "[docs/claims.md](../../docs/claims.md).", ""] + [
        "- **%s %s**: %s" % (c["id"], c["verdict"], c["claim"]) for c in claims]


def section_summary(run, claims):
    parts = [p for p in (summary_targets(run), summary_ratios(run), summary_claims(claims)) if p]
    body = []
    if run.load.get("busy"):  # the speeds below carry it; the warnings after the summary say why
        body += ["*The machine was busy during this run: speeds and ratios may be disturbed (warnings below the "
                 "summary). Errors and samples per ray are deterministic and unaffected.*", ""]
    for p in parts:
        body += p + [""]
    return ["## Summary", ""] + (body[:-1] or [NOT_MEASURED])


def section_matrix(run):
    body = ["CPU packet kernels. Mrays/s: median (min-max) of %s repetitions. uv errors in texels against the exact "
            "intersection; wrong surface = uv error above 1 texel." % run.plan.get("repetitions", "the")]
    rows = run.matrix
    if not rows:
        return section("Techniques x layers, per heightfield", [])
    for (hf, backend, threads, view), group in groups(rows, lambda r: (r["heightfield"]["label"], r["backend"], r["threads"],
                                                                          view_name(r["view"]))).items():
        body += ["", "### %s (%s)" % (hf, depth_map(group[0])), "",
                 "%s, %s, %s view." % (backend, counted(threads, "thread"), view), ""]
        body += md_table([("technique", False), ("layers", False), ("Mrays/s", True), ("samples/ray", True),
                          ("uv mean", True), ("p95", True), ("max", True), ("wrong surface", True)],
                         [[r["technique"], r["layers"], mrays(r), fmt(r.get("samples_per_ray"), 2)] + error_cells(r)
                          for r in group])
    return section("Techniques x layers, per heightfield", body)


def error_cells(row):
    e = row.get("errors") or {}
    return [fmt(e.get("uv_mean")), fmt(e.get("uv_p95")), fmt(e.get("uv_max"), 2), fmt(e.get("wrong_surface_rate"), 2, 100, "%")]


def section_glsl(run):
    pairs = [(run.partner(g, kind="trace", backend=run.best_isa), g) for g in sorted(
        (r for r in run.timed if r["kind"] == "glsl"), key=run.order)]
    if not pairs:
        return section("CPU against GLSL (OSMesa llvmpipe)", [])
    body = ["The same rays and parameters on both sides; CPU at the best ISA (%s). CPU/GLSL is the median "
            "(min-max) of the per-round ratios." % run.best_isa, ""]
    body += md_table([("heightfield", False), ("technique", False), ("layers", False), ("threads", True),
                      ("CPU %s Mrays/s" % run.best_isa, True), ("GLSL Mrays/s", True), ("CPU/GLSL", True)],
                     [[g["heightfield"]["label"], g["technique"], g["layers"], g["threads"], mrays(c), mrays(g),
                       fmt_ratio(speedup(c, g))] for c, g in pairs])
    return section("CPU against GLSL (OSMesa llvmpipe)", body)


def section_every_backend(run, faults):
    """POM-32 at every backend; appends roofline and ceiling fractions above 100% to `faults`."""
    title = "%s, %s layers, every backend" % (HEADLINE_TECHNIQUE.upper(), HEADLINE_LAYERS)
    rows = sorted((r for r in run.timed if run.is_headline(r) and r["kind"] in ("trace", "glsl", "naive", "autovec")),
                  key=run.order)
    if not rows:
        return section(title, [])
    base = run.isas[0] if run.isas else None
    body = ["Roofline = the backend's bilinear sampler alone at the positions of the same march; ceiling = POM's "
            "march and bilinear arithmetic on taps held in registers, no memory access; each fraction = the "
            "technique's samples/s over it. x llvmpipe: over GLSL at the same threads; x autovec: over the naive "
            "port vectorised by the compiler for the same ISA. Every ratio is the median (min-max) of the per-round "
            "ratios.", ""]
    cells = []
    for r in rows:
        fractions = []
        for kind in ("roofline", "ceiling"):
            # a trace row's anchors: its backend's sampler alone, or its arithmetic alone, same scene and threads
            anchor = run.partner(r, kind=kind, technique=None, layers=ANY) if r["kind"] == "trace" else None
            fraction = per_round(samples_rounds(r), samples_rounds(anchor))
            if fraction and fraction[0] > 1.0:
                faults.append("%s: %s %s" % (run.describe(r), kind, fmt_spread(fraction, 0, 100, "%")))
                fractions.append("fault (>100%: timing disturbed)")
            else:
                fractions.append(fmt_spread(fraction, 0, 100, "%"))
            if kind == "roofline":
                fractions.insert(0, msamples(anchor))
        over = [run.partner(r, kind="trace", backend=base), run.partner(r, kind="naive", backend="naive"),
                run.partner(r, kind="glsl", backend="glsl"),
                run.partner(r, kind="autovec") if r["kind"] == "trace" else None]
        cells.append([r["heightfield"]["label"], backend_label(r), r["threads"], mrays(r), msamples(r)] + fractions
                     + [fmt_ratio(speedup(r, o)) if o is not r else "-" for o in over])
    body += md_table([("heightfield", False), ("backend", False), ("threads", True), ("Mrays/s", True),
                      ("Msamples/s", True), ("roofline Msamples/s", True), ("roofline fraction", True),
                      ("ceiling fraction", True), ("x %s" % base, True), ("x naive", True), ("x llvmpipe", True),
                      ("x autovec", True)], cells)
    if faults:
        body += ["", "**Measurement faults** (a fraction above 100% means the anchor or the kernel was "
                 "timed while the machine was disturbed; not a result):", ""] + ["- " + f for f in faults]
    return section(title, body)


def section_searches_per_isa(run):
    """The searches the plan times at every ISA (32 layers), each ISA against llvmpipe."""
    rows = sorted((r for r in run.timed if "isa" in r.get("purposes", []) and r["kind"] == "trace"
                   and r.get("technique")), key=run.order)
    title = "The searches at every ISA, against llvmpipe"
    if not rows:
        return section(title, [])
    cells = []
    for (hf, technique, threads), group in groups(rows, lambda r: (r["heightfield"]["label"], run.label(r),
                                                                    r["threads"])).items():
        glsl = run.partner(group[0], kind="glsl", backend="glsl")
        by_isa = {r["backend"]: r for r in group}
        cells.append([hf, technique, threads, mrays(glsl)] + [
            cell for isa in run.isas for cell in (
                (mrays(by_isa[isa]), fmt_ratio(speedup(by_isa[isa], glsl))) if isa in by_isa else ("-", "-"))])
    body = ["Each search at %s layers (maxmip: its one spec) at every ISA and the same as GLSL (llvmpipe) at the "
            "same threads. Mrays/s: median (min-max); x llvmpipe: median (min-max) of the per-round ratios."
            % HEADLINE_LAYERS, ""]
    body += md_table([("heightfield", False), ("technique", False), ("threads", True), ("GLSL Mrays/s", True)] + [
        column for isa in run.isas for column in (("%s Mrays/s" % isa, True), ("x llvmpipe", True))], cells)
    return section(title, body)


def section_exact_speed(run):
    """The exact reference's own speed, against POM-32 on the same rays, ISA and threads."""
    rows = sorted((r for r in run.timed if r["kind"] == "exact"), key=run.order)
    title = "The exact reference's speed"
    if not rows:
        return section(title, [])
    body = ["The exact intersection of every ray (conservative float pass of the min-depth pyramid walk at "
            "%s, each hit cell solved in double): Mrays/s median (min-max); cells/ray: texel cells tested in "
            "the float pass, then solved in double; x POM-32: the median (min-max) of the per-round ratios over POM-32 at the "
            "same ISA and threads." % run.best_isa, ""]
    cells = []
    for r in rows:
        pom = run.partner(r, kind="trace", backend=run.best_isa, technique=HEADLINE_TECHNIQUE, layers=HEADLINE_LAYERS)
        cells.append([r["heightfield"]["label"], r["threads"], mrays(r), fmt(r.get("samples_per_ray"), 2),
                      fmt_ratio(speedup(r, pom))])
    body += md_table([("heightfield", False), ("threads", True), ("Mrays/s", True), ("cells/ray", True),
                      ("x POM-32", True)], cells)
    return section(title, body)


def thread_pairs(run):
    """(1-thread row, most-threads row) of the headline configuration per heightfield and backend."""
    pairs = []
    for group in groups(sorted((r for r in run.timed if run.is_headline(r) and r["kind"] in ("trace", "glsl", "naive")),
                               key=run.order),
                        lambda r: (r["heightfield"]["label"], r["backend"], view_name(r["view"]))).values():
        one = [r for r in group if r["threads"] == 1]
        most = max(group, key=lambda r: r["threads"])
        if one and most["threads"] > 1:
            pairs.append((one[0], most))
    return pairs


def section_threads(run):
    cells = [[one["heightfield"]["label"], one["backend"], mrays(one), mrays(most), most["threads"],
              fmt_ratio(speedup(most, one))] for one, most in thread_pairs(run)]
    title = "Thread scaling (%s-%s)" % (HEADLINE_TECHNIQUE.upper(), HEADLINE_LAYERS)
    if not cells:
        return section(title, ["Only one thread count measured in this run."])
    return section(title, md_table([("heightfield", False), ("backend", False), ("1 thread Mrays/s", True),
                                    ("N threads Mrays/s", True), ("N", True), ("speed-up", True)], cells))


def cost_image(run_dir, images):
    """The samples-per-pixel image of a gallery entry: its `cost` field, or cost.png beside error.png
    (-cost.png beside -error.png); None when the run has none."""
    if images.get("cost"):
        return images["cost"]
    error = images.get("error") or ""
    for old, new in (("/error.png", "/cost.png"), ("-error.png", "-cost.png")):
        if error.endswith(old) and os.path.exists(os.path.join(run_dir, error[:-len(old)] + new)):
            return error[:-len(old)] + new
    return None


def section_gallery(run, run_dir):
    rows = sorted((r for r in run.with_purpose("gallery") if r.get("images")), key=run.order)
    body = []
    for (hf, view), group in groups(rows, lambda r: (r["heightfield"]["label"], view_name(r["view"]))).items():
        costs = [cost_image(run_dir, r["images"]) for r in group]
        with_cost = any(costs)
        body += ["%s, %s view. Shaded render at the technique's uv; uv error%s." % (
            hf, view, "; cost: height samples per pixel" if with_cost else ""), ""]
        body += md_table([("technique", False), ("render", False), ("error", False)] + ([("cost", False)] if with_cost else [])
                         + [("uv mean", True), ("p95", True), ("max", True), ("wrong surface", True)],
                         [[run.label(r), "![](%s)" % r["images"]["render"], "![](%s)" % r["images"]["error"]]
                          + (["![](%s)" % c if c else "-"] if with_cost else []) + error_cells(r)
                          for r, c in zip(group, costs)]) + [""]
    return section("Gallery", body[:-1])


# ---------------------------------------------------------------------------------------------
# Plots

def panel_grid(n, width=4.2, height=3.4, columns=3):
    """A grid of n panels at most `columns` wide, sized for a page; unused panels hidden."""
    cols = min(n, columns)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(max(width * cols, 7.0), height * rows + 0.9), squeeze=False)
    flat = [ax for line in axes for ax in line]
    for ax in flat[n:]:
        ax.set_visible(False)
    return fig, flat[:n]


def finish(fig, path, title, axes):
    """Suptitle, one legend for the figure (handles of every panel, deduplicated) below the panels, save."""
    handles = {}
    for ax in axes:
        for h, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, h)
    fig.suptitle(title, fontsize=10)
    per_row = max(1, int(fig.get_figwidth() / 1.4))  # legend entries are about 1.4 inches wide
    legend_rows = (len(handles) + per_row - 1) // per_row or 1
    ncol = (len(handles) + legend_rows - 1) // legend_rows or 1
    bottom = 0.02 + 0.035 * legend_rows * 4.0 / fig.get_figheight()
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=ncol, fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, bottom, 1, 0.95))
    fig.savefig(path, dpi=min(130, MAX_PLOT_PIXELS / fig.get_figwidth()))
    plt.close(fig)


def log_axes(ax, x=True, y=True, xticks=None):
    """Log scales labelled with plain numbers (0.1, 2, 50) at 1, 2 and 5 per decade instead of powers;
    with xticks, x is labelled at those values alone (layer counts)."""
    def label(v, _):
        return "%g" % v if v > 0 and round(v / 10 ** math.floor(math.log10(v) + 1e-9)) in (1, 2, 5) else ""
    for use, axis, scale in ((x, ax.xaxis, ax.set_xscale), (y, ax.yaxis, ax.set_yscale)):
        if use:
            scale("log")
            axis.set_major_formatter(FuncFormatter(label))
            axis.set_minor_formatter(FuncFormatter(label))
    if xticks:
        ax.set_xticks(xticks, ["%g" % t for t in xticks], minor=False)
        ax.xaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))


def technique_kw(run, technique):
    t = run.style[technique]
    return {"color": t["color"], "marker": t["marker"]}


def plot_error_vs_layers(run, path):
    by_hf = groups(run.matrix, lambda r: r["heightfield"]["label"])
    if not by_hf:
        return False
    fig, axes = panel_grid(len(by_hf))
    for ax, (hf, rows) in zip(axes, by_hf.items()):
        series = {}  # a technique whose errors equal an earlier one's (shadow shares POM's hit) is named on its line
        for technique, group in groups(rows, lambda r: r["technique"]).items():
            errors = [(r["min_layers"], max(r["errors"]["uv_mean"], 1e-4)) for r in group
                      if r.get("errors") and r.get("min_layers") == r.get("max_layers")]
            same = [t for t, e in series.items() if e == errors]
            if same:
                series[same[0] + " = " + technique] = series.pop(same[0])
            else:
                series[technique] = errors
        for name, errors in series.items():
            technique = name.split(" = ")[0]
            if run.style[technique]["layered"]:
                ax.plot([x for x, _ in errors], [y for _, y in errors], label=name, **technique_kw(run, technique))
            elif errors:
                ax.axhline(errors[0][1], linestyle="--", color=run.style[technique]["color"], label=name,
                           marker=run.style[technique]["marker"], markevery=[0])
        log_axes(ax, xticks=sorted({x for name, errors in series.items() for x, _ in errors
                                    if run.style[name.split(" = ")[0]]["layered"]}))
        ax.set_title("%s (%s)" % (hf, depth_map(rows[0])), fontsize=9)
        ax.set_xlabel("layers")
        ax.set_ylabel("mean uv error (texels)")
        ax.grid(True, which="both", alpha=0.3)
    finish(fig, path, "Error against layer count (default view; dashed: one-sample techniques)", axes)
    return True


def plot_error_vs_angle(run, path):
    rows = [r for r in run.with_purpose("sweep") if r["view"]["kind"] == "sweep" and r.get("errors") and r.get("technique")]
    by_hf = groups(sorted(rows, key=run.order), lambda r: r["heightfield"]["label"])
    if not by_hf:
        return False
    phis = sorted({r["view"].get("phi") or 0 for r in rows})
    fig, axes = panel_grid(len(by_hf))
    styles = ["-", "--", ":", "-."]
    for ax, (hf, hf_rows) in zip(axes, by_hf.items()):
        for technique, t_rows in groups(hf_rows, lambda r: r["technique"]).items():
            for k, (layers, l_rows) in enumerate(groups(t_rows, lambda r: r["layers"]).items()):
                # mean over the azimuths measured at each angle
                by_theta = groups(l_rows, lambda r: r["view"]["theta"])
                thetas = sorted(by_theta)
                errors = [max(statistics.mean(r["errors"]["uv_mean"] for r in by_theta[t]), 1e-4) for t in thetas]
                ax.plot(thetas, errors, linestyle=styles[k % len(styles)], markersize=4,
                        label=run.label(l_rows[0]), **technique_kw(run, technique))
        log_axes(ax, x=False)
        ax.set_title(hf, fontsize=9)
        ax.set_xlabel("view angle from the normal (degrees)")
        ax.set_ylabel("mean uv error (texels)")
        ax.grid(True, which="both", alpha=0.3)
    azimuth = "azimuth %g deg" % phis[0] if len(phis) == 1 else "mean over azimuths %s deg" % ", ".join("%g" % p for p in phis)
    finish(fig, path, "Error against view angle (sweep views, %s)" % azimuth, axes)
    return True


def plot_error_vs_speed(run, path):
    rows = [r for r in run.matrix if r.get("speed") and r.get("errors")]
    by_hf = groups(sorted(rows, key=run.order), lambda r: r["heightfield"]["label"])
    if not by_hf:
        return False
    fig, axes = panel_grid(len(by_hf), 4.6, 3.8)
    for ax, (hf, hf_rows) in zip(axes, by_hf.items()):
        for technique, group in groups(hf_rows, lambda r: r["technique"]).items():
            speeds = [spread(rays_rounds(r)) for r in group]
            xs = [s[0] / 1e6 for s in speeds]
            ys = [max(r["errors"]["uv_p95"], 1e-4) for r in group]
            ax.errorbar(xs, ys, xerr=[[(s[0] - s[1]) / 1e6 for s in speeds], [(s[2] - s[0]) / 1e6 for s in speeds]],
                        linestyle="none", markersize=4, elinewidth=0.8, label=technique, **technique_kw(run, technique))
            if run.style[technique]["layered"]:
                for r, x, y in zip(group, xs, ys):
                    ax.annotate(r["layers"], (x, y), fontsize=5, alpha=0.7, xytext=(2, 2), textcoords="offset points")
        for k, target in enumerate(ERROR_TARGETS):
            linestyle = TARGET_STYLES[target]
            ax.axhline(target, color="black", linestyle=linestyle, linewidth=0.8)
            # the legend names the target's line and ring even where no configuration reaches it
            ax.plot([], [], color="black", linestyle=linestyle, marker="o", markerfacecolor="none",
                    label="p95 <= %g texel (ring: cheapest)" % target)
            best = cheapest(hf_rows, target)
            if best:
                x, y = spread(rays_rounds(best))[0] / 1e6, max(best["errors"]["uv_p95"], 1e-4)
                ax.plot([x], [y], linestyle="none", marker="o", markersize=12 + 4 * k, markerfacecolor="none",
                        markeredgecolor="black", markeredgewidth=1.4)
                ax.annotate("%g" % target, (x, y), xytext=(0, -(7 + 2 * k)), textcoords="offset points",
                            ha="center", va="top", fontsize=6, fontweight="bold",
                            bbox={"boxstyle": "round,pad=0.1", "facecolor": "white", "edgecolor": "none", "alpha": 0.8})
        log_axes(ax)
        ax.set_title(hf, fontsize=9)
        ax.set_xlabel("Mrays/s, median (bars: min-max)")
        ax.set_ylabel("p95 uv error (texels)")
        ax.grid(True, which="both", alpha=0.3)
    finish(fig, path, "Error against speed (matrix rows; labels: layers)\n"
                      "rings: the cheapest configuration (fewest samples/ray) at each p95 target, as in the summary", axes)
    return True


def plot_isa_speedup(run, path):
    rows = sorted((r for r in run.timed if run.is_headline(r) and r["kind"] == "trace"), key=run.order)
    by_group = groups(rows, lambda r: "%s\n%s" % (r["heightfield"]["label"], counted(r["threads"], "thread")))
    base = run.isas[0] if run.isas else None
    references = [("naive", dict(kind="naive", backend="naive")), (base, dict(kind="trace", backend=base))]
    bars = {ref: [] for ref, _ in references}  # ref -> [(group index, isa, spread)]
    for g, group in enumerate(by_group.values()):
        for r in group:
            for ref, changes in references:
                other = run.partner(r, **changes)
                if other and other is not r:  # the reference over itself is 1 by definition
                    bars[ref].append((g, r["backend"], speedup(r, other)))
    references = [(ref, c) for ref, c in references if bars[ref]]
    if not references:
        return False
    colors = run.backend_colors()
    fig, axes = plt.subplots(len(references), 1, figsize=(max(7.0, 1.1 * len(by_group)), 3.0 * len(references) + 0.9),
                             squeeze=False)
    axes = [a[0] for a in axes]
    width = 0.8 / max(len(run.isas), 1)
    for ax, (ref, _) in zip(axes, references):
        for k, isa in enumerate(run.isas):
            mine = [(g, s) for g, b, s in bars[ref] if b == isa]
            if not mine:
                continue
            xs = [g + (k - (len(run.isas) - 1) / 2) * width for g, _ in mine]
            ys = [s[0] for _, s in mine]
            ax.bar(xs, ys, width, color=colors[isa], label=isa,
                   yerr=[[s[0] - s[1] for _, s in mine], [s[2] - s[0] for _, s in mine]], capsize=2, error_kw={"linewidth": 0.8})
            for x, (_, s) in zip(xs, mine):
                ax.text(x, s[2], "%.1f" % s[0], ha="center", va="bottom", fontsize=6)
        ax.axhline(1.0, color="gray", linewidth=1)
        ax.set_xticks(range(len(by_group)))
        ax.set_xticklabels(list(by_group), fontsize=7)
        ax.set_ylabel("rays/s over %s" % ("the naive port" if ref == "naive" else ref))
    finish(fig, path, "%s-%s speed-up per ISA: median of per-round ratios (bars: min-max)" % (
        HEADLINE_TECHNIQUE.upper(), HEADLINE_LAYERS), axes)
    return True


# ---------------------------------------------------------------------------------------------
# Output

def section_plots(run, run_dir, history_drawn):
    plots = os.path.join(run_dir, "plots")
    os.makedirs(plots, exist_ok=True)
    body = []

    def add(drawn, name, alt, missing):
        if drawn:
            body.extend(["![%s](plots/%s)" % (alt, name), ""])
            return
        body.extend(["%s: %s" % (alt.capitalize(), missing), ""])
        if os.path.exists(os.path.join(plots, name)):  # a plot of an earlier report of this directory
            os.remove(os.path.join(plots, name))

    add(plot_error_vs_layers(run, os.path.join(plots, "error_vs_layers.png")), "error_vs_layers.png",
        "error against layers", "not measured in this run.")
    add(plot_error_vs_angle(run, os.path.join(plots, "error_vs_angle.png")), "error_vs_angle.png",
        "error against view angle", "not measured in this run.")
    add(plot_error_vs_speed(run, os.path.join(plots, "error_vs_speed.png")), "error_vs_speed.png",
        "error against speed", "not measured in this run.")
    add(plot_isa_speedup(run, os.path.join(plots, "isa_speedup.png")), "isa_speedup.png",
        "speed-up per ISA", "not measured in this run.")
    if history_drawn is not None:
        add(history_drawn, "history.png", "history", "the headline configuration is not in the history.")
    return section("Plots", body[:-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--history", help="history CSV to append this run's timed rows to, and to plot")
    args = parser.parse_args()
    try:
        run, claims = load_run(args.run_dir)
        history_drawn = record_run.record(args.run_dir, args.history)[0] if args.history else None
        alerts_path = os.path.join(args.run_dir, "alerts.json")
        found_alerts = read_json(alerts_path) if os.path.exists(alerts_path) else None
        faults = []
        # sections first: the warnings at the top name the faults they find
        summary = section_summary(run, claims)
        sections = (section_matrix(run) + section_glsl(run) + section_every_backend(run, faults)
                    + section_searches_per_isa(run) + section_exact_speed(run) + section_threads(run) + section_plots(run, args.run_dir, history_drawn) + section_gallery(run, args.run_dir))
    except (InputError, Unusable) as e:
        print("report.py: %s" % e, file=sys.stderr)
        return 2
    md = ["# heightmarch report", "",
          "Parallax-mapping techniques on the CPU (packet kernels per ISA) and as GLSL (OSMesa llvmpipe), measured "
          "against the exact ray/heightfield intersection. Speeds: median (min-max) of the repetitions; ratios: median "
          "(min-max) of the per-round ratios. What every measure means: [docs/measures.md](../../docs/measures.md); "
          "how to reproduce: [docs/reproducing.md](../../docs/reproducing.md).", ""]
    md += (["## Alerts", ""] + alerts.markdown(found_alerts) + [""] if found_alerts else []) + summary + section_warnings(run, faults) + [""] + section_machine(run) + sections
    atomic_write(os.path.join(args.run_dir, "report.md"), "\n".join(md) + "\n")
    print("report: %s" % os.path.join(args.run_dir, "report.md"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
