"""Writes a run's report from RUN_DIR/measurements.json: report.md (what a person reads first),
tables.md (the long tables), plots/*.png and report.html (report_page.py); with --csv,
measurements.csv too (not kept in a run by default: the same rows as measurements.json.gz, 1.2 MB
compressed of a full run's 5 MB budget, docs/measurements.md).

Usage: scripts/report RUN_DIR [--history results/history.csv] [--csv]

Inputs: measurements.json (the run's typed rows, docs/measurements.md; format 1 or 2) and, where
the run has them, claims.json, recommendation.json and alerts.json. Every speed is the median of
the repetitions with their min-max; every ratio of two rows is taken per round and shown as the
median of the per-round ratios with their min-max. With --history, the run, once complete, is
recorded (record_run.py: RUN_DIR/alerts.json against its machine's earlier runs, the history plot,
then its rows into the history CSV, under the history's lock); a run's alerts.json opens the
report.
"""
import os

from . import cli, record_run, report_page
from .measurements import (ANY, HEADLINE_LAYERS, HEADLINE_TECHNIQUE, MAXMIP_PEAK, SHADOW_COUNTS, backend_label,  # noqa: E402
                           gl_label, gl_renderers,
                          config, counted, depth_map, machine_rows, docs_link, filter_pairs, glsl_pairs, groups, load_run,
                          measurements_csv,
                          rays_rounds, read_claims, read_optional, samples_rounds, searches_per_isa,
                          speedup, validate_alerts, validate_recommendation, view_name, backend_colours)
from .escape import markdown as md, markdown_target
from .readers import run_file
from .report_content import (FILTER_DOCS, alerts_summary, breakdown_lines, filter_table, filters_intro, filters_title,
                             fmt, fmt_change, fmt_error, fmt_number, fmt_ratio, fmt_spread, recommendation_columns,
                             recommendation_intro, recommendation_rows, walks_table, warnings, WALKS_INTRO)
from .report_plots import plot_error_vs_angle, plot_error_vs_layers, plot_error_vs_speed, plot_isa_speedup
from .spreads import per_round, spread
from .writers import atomic_write, subdirectory

NOT_MEASURED = "Not measured in this run."


# ---------------------------------------------------------------------------------------------
# Text

class Markup(str):
    """Markdown this module wrote on purpose (bold, a link, an image), whose data went through md()
    already; any other cell of md_table is text and is escaped there."""


def md_table(columns, rows):
    """columns: [(title, right-aligned)]; rows: lists of cells, text (escaped here) or Markup."""
    cell = lambda c: c if isinstance(c, Markup) else md(c)  # noqa: E731
    lines = ["| " + " | ".join(cell(t) for t, _ in columns) + " |",
             "|" + "|".join("---:" if right else "---" for _, right in columns) + "|"]
    return lines + ["| " + " | ".join(cell(c) for c in cells) + " |" for cells in rows]


def mrays(row):
    return fmt_spread(spread(rays_rounds(row)), 1, 1e-6)


def msamples(row):
    return fmt_spread(spread(samples_rounds(row)), 0, 1e-6)


def section(title, body, level="##"):
    return ["", level + " " + title, ""] + (body or [NOT_MEASURED])


# ---------------------------------------------------------------------------------------------
# report.md: the first screen

def section_alerts(alerts):
    """alerts.json of a recorded run (the regression tracking), or why there is none."""
    body = [md(alerts_summary(alerts))]
    found = (alerts or {}).get("alerts") or []
    if found:
        body += [""] + md_table([("series", False), ("kind", False), ("measure", False), ("baseline", True), ("new", True),
                                 ("change", True), ("", False)],
                                [[a["series"], a["kind"], a["metric"],
                                  "%s (spread %s)" % (fmt_number(a.get("baseline")), fmt_number(a.get("baseline_spread"))),
                                  fmt_number(a.get("new")), fmt_change(a.get("change")), a["message"]] for a in found])
    return section("Alerts", body)


def section_recommendation(run, recommendation):
    title = "What to ship"
    if recommendation is None:
        return section(title, ["No recommendation.json in this run (computed by `heightmarch suite`, `claims` and "
                               "`recommend` since measurements format 2; `heightmarch recommend RUN_DIR` computes it)."])
    body = [md(recommendation_intro(recommendation, run)) + " Why this target, and how to choose yours: "
            "[docs/recommendation.md](%s). The same from any run at another target: `heightmarch recommend RUN_DIR "
            "--percentile p99 --max-error 1 --max-wrong-surface 1`." % markdown_target(docs_link(run, "recommendation.md")), ""]
    cells = []
    for r in recommendation_rows(recommendation):
        cells.append([r["cells"][0], Markup("**%s**" % md(r["cells"][1])) if r["every"] else r["cells"][1],
                      Markup("**%s**" % md(r["cells"][2])) if r["chosen"] else r["cells"][2]] + r["cells"][3:])
    varying = breakdown_lines(run, recommendation)
    if varying:  # where the choice's figures vary over the window: the page shows each row's groups
        varying = ["", md("Where a choice's wrong-surface rate varies over the window beyond its 95% intervals:"),
                   ""] + ["- " + md(line) for line in varying]
    return section(title, body + md_table(recommendation_columns(recommendation["target"]), cells) + varying)


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
               "%s over %s, %s" % (best, " / ".join(gl_renderers(run.rows)) or "GLSL", counted(threads, "thread"))]
    return columns, ratios


def section_ratios(run):
    columns, ratios = headline_ratios(run)
    # A filtered run (one ISA, one thread count, no GLSL) measures some ratios nowhere: their
    # columns go, and the section too when none is left.
    kept = [i for i in range(len(columns)) if any(spreads[i] is not None for _, spreads in ratios)]
    if not kept:
        return []
    return section("Headline speed ratios", [
        "%s-%s, default view: median (min-max) of the per-round ratios of rays/s." % (
            HEADLINE_TECHNIQUE.upper(), HEADLINE_LAYERS), ""] + md_table(
        [("heightfield", False)] + [(columns[i], True) for i in kept],
        [[hf] + [fmt_ratio(spreads[i]) for i in kept] for hf, spreads in ratios]))


def section_claims(run, claims):
    if not claims:
        return []
    body = ["Each claim's reading, rule, figures and checks: [claims.md](claims.md); the claims themselves: "
            "[docs/claims.md](%s)." % markdown_target(docs_link(run, "claims.md")), ""]
    for c in claims:
        line = "- **%s %s**: %s" % (md(c["id"]), md(c["verdict"]), md(c["claim"]))
        if c.get("summary"):  # claims.json format 3: the count and where it fails
            line += ". " + md(c["summary"][0].upper() + c["summary"][1:] + (
                "; under the previous rule: %s" % c["previous"]["verdict"] if c.get("previous") else ""))
        if c["id"] == "P2":
            line += " (maxmip at a grazing one-texel peak: [docs/techniques.md](%s))" % markdown_target(
                docs_link(run, *MAXMIP_PEAK))
        body.append(line)
    return section("The claims: the tutorials' (C1-C10) and the papers' (P1-P3)", body)


def section_filters(run, recommendation):
    pairs = filter_pairs(run)
    if not pairs:
        return []
    target = (recommendation or {}).get("target")
    columns, rows = filter_table(run, pairs, target)
    return section(filters_title(run, pairs), [
        "%s What each error means: [docs/measures.md](%s); the filters: [docs/conventions.md](%s)." % (
            md(filters_intro(run, pairs, target)), markdown_target(docs_link(run, "measures.md")),
            markdown_target(docs_link(run, *FILTER_DOCS))), ""] + md_table(columns, rows))


def section_machine(run):
    return section("Machine and provenance", md_table([("", False), ("", False)], machine_rows(run)))


def section_warnings(run, faults):
    body = []
    for head, text in warnings(run, faults):
        body += ["> **%s** %s" % (md(head), md(text)), ">"]
    return section("Warnings", body[:-1]) if body else []


# ---------------------------------------------------------------------------------------------
# tables.md: the long tables

def error_cells(row):
    e = row.get("errors") or {}
    return [fmt_error(e.get("uv_error_mean")), fmt_error(e.get("uv_error_p95")), fmt_error(e.get("uv_error_p99")),
            fmt_error(e.get("uv_error_max")), fmt(e.get("wrong_surface_rate"), 2, 100, "%")]


ERROR_COLUMNS = [("uv mean", True), ("p95", True), ("p99", True), ("max", True), ("wrong surface", True)]


def section_matrix(run):
    body = ["CPU packet kernels. Mrays/s: median (min-max) of %s repetitions. uv errors in texels against the exact "
            "intersection; wrong surface = uv error above 1 texel." % run.plan.get("repetitions", "the")]
    rows = run.matrix
    if not rows:
        return section("Techniques x layers, per heightfield", [])
    for (hf, backend, threads, view), group in groups(rows, lambda r: (r["heightfield"]["label"], r["backend"], r["threads"],
                                                                          view_name(r["view"]))).items():
        body += ["", "### %s (%s)" % (md(hf), depth_map(group[0])), "",
                 "%s, %s, %s view." % (md(backend), counted(threads, "thread"), md(view)), ""]
        body += md_table([("technique", False), ("layers", False), ("Mrays/s", True), ("samples/ray", True)] + ERROR_COLUMNS,
                         [[r["technique"], r["layers"], mrays(r), fmt(r.get("samples_per_ray"), 2)] + error_cells(r)
                          for r in group])
    return section("Techniques x layers, per heightfield", body)


def section_glsl(run):
    pairs = glsl_pairs(run)
    if not pairs:
        return section("CPU against GLSL", [])
    body = ["The GLSL rows: %s. The same rays and parameters on both sides; CPU at the best ISA (%s). CPU/GLSL is the "
            "median (min-max) of the per-round ratios. Where the shadow technique's sample counts differ between "
            "the CPU and llvmpipe, and why: [docs/techniques.md](%s)." % (
                md(" and ".join(gl_renderers(run.rows))), md(run.best_isa),
                markdown_target(docs_link(run, *SHADOW_COUNTS))), ""]
    body += md_table([("heightfield", False), ("technique", False), ("layers", False), ("threads", True),
                      ("CPU %s Mrays/s" % run.best_isa, True), ("GLSL Mrays/s", True), ("CPU/GLSL", True)],
                     [[g["heightfield"]["label"], g["technique"], g["layers"], g["threads"], mrays(c), mrays(g),
                       fmt_ratio(speedup(c, g))] for c, g in pairs])
    return section("CPU against GLSL", body)


def section_every_backend(run, faults):
    """POM-32 at every backend; appends roofline and ceiling fractions above 100% to `faults`."""
    title = "Every backend"
    rows = sorted((r for r in run.timed if run.is_headline(r) and r["kind"] in ("trace", "glsl", "naive", "autovec")),
                  key=run.order)
    if not rows:
        return section(title, [])
    base = run.isas[0] if run.isas else None
    body = ["%s, %s layers. Roofline = the backend's bilinear sampler alone at the positions of the same march; "
            "ceiling = POM's march and bilinear arithmetic on taps held in registers, no memory access; each "
            "fraction = the technique's samples/s over it. x GLSL: over the GLSL row (%s) at the same threads; x autovec: "
            "over the naive port vectorised by the compiler for the same ISA. Every ratio is the median (min-max) of "
            "the per-round ratios." % (HEADLINE_TECHNIQUE.upper(), HEADLINE_LAYERS,
                                       md(" and ".join(gl_renderers(run.rows)) or "not measured")), ""]
    cells = []
    for r in rows:
        fractions = []
        for kind in ("roofline", "ceiling"):
            # a trace row's anchors: its backend's sampler alone, or its arithmetic alone, same scene and threads
            anchor = run.partner(r, kind=kind, technique=None, layers=ANY) if r["kind"] == "trace" else None
            fraction = per_round(samples_rounds(r), samples_rounds(anchor))
            if fraction and fraction[0] > 1.0:
                faults.append("%s: %s %s" % (run.describe(r), kind, fmt_spread(fraction, 0, 100, "%")))
                fractions.append("fault (above 100%: timing disturbed)")
            else:
                fractions.append(fmt_spread(fraction, 0, 100, "%"))
            if kind == "roofline":
                fractions.insert(0, msamples(anchor))
        over = [run.partner(r, kind="trace", backend=base), run.partner(r, kind="naive", backend="naive"),
                run.partner(r, kind="glsl", backend="glsl"),
                run.partner(r, kind="autovec") if r["kind"] == "trace" else None]
        cells.append([r["heightfield"]["label"], gl_label(r) if r["kind"] == "glsl" else backend_label(r), r["threads"],
                      mrays(r), msamples(r)] + fractions
                     + [fmt_ratio(speedup(r, o)) if o is not r else "-" for o in over])
    body += md_table([("heightfield", False), ("backend", False), ("threads", True), ("Mrays/s", True),
                      ("Msamples/s", True), ("roofline Msamples/s", True), ("roofline fraction", True),
                      ("ceiling fraction", True), ("x %s" % base, True), ("x naive", True), ("x GLSL", True),
                      ("x autovec", True)], cells)
    if faults:
        body += ["", "**Measurement faults** (a fraction above 100% means the anchor or the kernel was "
                 "timed while the machine was disturbed; not a result):", ""] + ["- " + md(f) for f in faults]
    return section(title, body)


def section_searches_per_isa(run):
    """The searches the plan times at every ISA (32 layers), each ISA against GLSL."""
    title = "The searches at every ISA, against GLSL"
    found = searches_per_isa(run)
    if not found:
        return section(title, [])
    cells = [[hf, technique, threads, mrays(glsl)] + [
        cell for isa in run.isas for cell in (
            (mrays(by_isa[isa]), fmt_ratio(speedup(by_isa[isa], glsl))) if isa in by_isa else ("-", "-"))]
        for hf, technique, threads, glsl, by_isa in found]
    body = ["Each search at %s layers (maxmip: its one spec) at every ISA and the same as GLSL (%s) at the "
            "same threads. Mrays/s: median (min-max); x GLSL: median (min-max) of the per-round ratios."
            % (HEADLINE_LAYERS, md(" and ".join(gl_renderers(run.rows)))), ""]
    body += md_table([("heightfield", False), ("technique", False), ("threads", True), ("GLSL Mrays/s", True)] + [
        column for isa in run.isas for column in (("%s Mrays/s" % isa, True), ("x GLSL", True))], cells)
    return section(title, body)


def section_walks(run):
    """The walks' samples/s with their SIMD use, at every ISA."""
    title = "The walks' lanes at every ISA"
    walks = walks_table(run)
    return section(title, [WALKS_INTRO, ""] + md_table(*walks) if walks else [])


def section_exact_speed(run):
    """The exact reference's own speed, against POM-32 on the same rays, ISA and threads."""
    rows = sorted((r for r in run.timed if r["kind"] == "exact"), key=run.order)
    title = "The exact reference's speed"
    if not rows:
        return section(title, [])
    body = ["The exact intersection of every ray (conservative float pass of the min-depth pyramid walk at "
            "%s, each hit cell solved in double): Mrays/s median (min-max); cells/ray: texel cells tested in "
            "the float pass, then solved in double; x POM-32: the median (min-max) of the per-round ratios over POM-32 at the "
            "same ISA and threads." % md(run.best_isa), ""]
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


def image(path):
    return Markup("![](%s)" % markdown_target(path))


def shipped(recommendation):
    """(heightfield, technique, layers) -> the backends that recommend it there."""
    out = {}
    for b in (recommendation or {}).get("backends", []):
        for a in b["per_heightfield"]:
            if a.get("choice"):
                out.setdefault((a["heightfield"], a["choice"]["technique"], a["choice"]["layers"]), []).append(b["name"])
    return out


def image_error_cells(row):
    """The shaded image's error (CIEDE2000 against the exact render supersampled): mean, p99, share seen."""
    e = row.get("image_error") or {}
    return [fmt(e.get("mean"), 2), fmt(e.get("p99"), 1), fmt(e.get("visible_share"), 1, 100, "%")]


IMAGE_ERROR_COLUMNS = [("dE00 mean", True), ("dE00 p99", True), ("seen (dE00 > 2)", True)]


def section_gallery(run, recommendation):
    rows = sorted((r for r in run.with_purpose("gallery") if r.get("images")), key=run.order)
    ships = shipped(recommendation)
    body = [md("Each map's recommended configuration (what to ship) beside its exact render, and on the first map "
               "each technique at the layer counts asked (10 unless --layers said otherwise; POM at 32 too), on the "
               "run's window as a picture, drawn by the CPU kernel. The shaded image is compared with the exact one "
               "at n x n subpixel rays a pixel (box-resolved in linear light) by CIEDE2000; the exact row's own "
               "difference is the resolve's floor (docs/measures.md#the-shaded-image)."), ""]
    for (hf, view), group in groups(rows, lambda r: (r["heightfield"]["label"], view_name(r["view"]))).items():
        costs = [cost_image(run.dir, r["images"]) for r in group]
        with_cost = any(costs)
        with_difference = any(r["images"].get("difference") for r in group)
        body += ["%s, %s view. Shaded render at the technique's uv; uv error on one log scale (0.01 to 10 texels)%s%s." % (
            md(hf), md(view),
            "; cost: height samples per pixel, on one log scale for every image (1 to 1024)" if with_cost else "",
            "; difference: CIEDE2000 against the exact render supersampled, 0 to 10" if with_difference else ""), ""]
        body += md_table([("technique", False), ("render", False), ("error", False)] + ([("cost", False)] if with_cost else [])
                         + ([("difference", False)] if with_difference else []) + ERROR_COLUMNS
                         + (IMAGE_ERROR_COLUMNS if with_difference else []),
                         [[run.label(r) + "".join(" (what to ship, %s)" % b for b in ships.get(
                             (r["heightfield"]["label"], r.get("technique"), r.get("layers")), [])),
                           image(r["images"]["render"]), image(r["images"]["error"])]
                          + ([image(c) if c else "-"] if with_cost else [])
                          + ([image(r["images"]["difference"]) if r["images"].get("difference") else "-"]
                             if with_difference else [])
                          + error_cells(r) + (image_error_cells(r) if with_difference else [])
                          for r, c in zip(group, costs)]) + [""]
        references = [r["images"]["reference"] for r in group if r["images"].get("reference")]
        if references:
            body += ["The exact render supersampled, what the differences are taken against:", "",
                     image(references[0]), ""]
    return section("Gallery", body[:-1])


# ---------------------------------------------------------------------------------------------
# Output

def section_plots(run, recommendation, history_drawn):
    plots = subdirectory(run.dir, "plots")
    body = []

    def add(drawn, name, alt, missing):
        if drawn:
            body.extend(["![%s](plots/%s)" % (alt, name), ""])
            return
        body.extend(["%s: %s" % (alt.capitalize(), missing), ""])
        if os.path.exists(os.path.join(plots, name)):  # a plot of an earlier report of this directory
            os.remove(os.path.join(plots, name))

    add(plot_error_vs_speed(run, recommendation, os.path.join(plots, "error_vs_speed.png")), "error_vs_speed.png",
        "error against time per ray", "no recommendation to draw it for.")
    add(plot_error_vs_layers(run, os.path.join(plots, "error_vs_layers.png")), "error_vs_layers.png",
        "error against layers", "not measured in this run.")
    add(plot_error_vs_angle(run, os.path.join(plots, "error_vs_angle.png")), "error_vs_angle.png",
        "error against view angle", "not measured in this run.")
    add(plot_isa_speedup(run, os.path.join(plots, "isa_speedup.png")), "isa_speedup.png",
        "speed-up per ISA", "not measured in this run.")
    if history_drawn is not None:
        add(history_drawn, "history.png", "history", "the headline configuration is not in the history.")
    return section("Plots", body[:-1])


TABLES = [("Techniques x layers, per heightfield", "techniques-x-layers-per-heightfield"),
          ("CPU against GLSL", "cpu-against-glsl"),
          ("Every backend", "every-backend"),
          ("The searches at every ISA, against GLSL", "the-searches-at-every-isa-against-glsl"),
          ("The walks' lanes at every ISA", "the-walks-lanes-at-every-isa"),
          ("The exact reference's speed", "the-exact-references-speed"),
          ("Thread scaling (%s-%s)" % (HEADLINE_TECHNIQUE.upper(), HEADLINE_LAYERS), "thread-scaling-pom-32"),
          ("Gallery", "gallery")]


def main(argv=None):
    parser = cli.Parser(prog="report", description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--history", help="record the run (a complete one) into this history CSV, and plot it")
    parser.add_argument("--csv", action="store_true", help="also measurements.csv: every row flat, for a spreadsheet")
    args = parser.parse_args(argv)
    run = load_run(args.run_dir)
    claims = read_claims(os.path.join(args.run_dir, "claims.json"))
    recommendation = read_optional(os.path.join(args.run_dir, "recommendation.json"), "heightmarch-recommendation",
                                   validate_recommendation)
    if args.history:  # the report is written while the run is recorded, before the history is
        record_run.record(run.data, args.run_dir, args.history,
                          lambda rows, drawn, found: write_report(run, claims, recommendation, found, rows, drawn,
                                                                  args.csv))
    else:
        alerts = read_optional(os.path.join(args.run_dir, "alerts.json"), "heightmarch-alerts", validate_alerts)
        write_report(run, claims, recommendation, alerts, None, None, args.csv)
    print("report: %s" % os.path.join(args.run_dir, "report.md"))
    return 0


def write_report(run, claims, recommendation, alerts, recorded, history_drawn, csv=False):
    """report.md, tables.md, plots/ and report.html (with csv, measurements.csv); recorded: the
    history's rows when the run is being recorded (history_drawn: whether its plot was drawn)."""
    faults = []  # the tables find them, the warnings on the first screen name them
    tables = (section_matrix(run) + section_glsl(run) + section_every_backend(run, faults)
              + section_searches_per_isa(run) + section_walks(run) + section_exact_speed(run) + section_threads(run)
              + section_gallery(run, recommendation))
    plots = section_plots(run, recommendation, history_drawn)
    p = run.provenance
    json_file = os.path.basename(run_file(run.dir, "measurements.json"))
    title = "%s run of %s, commit %s" % (run.plan.get("name", "?"), p.get("date", "?"), p.get("commit", "?"))
    lines = ["# heightmarch report: " + md(title), "",
          "Parallax-mapping techniques on the CPU (packet kernels per ISA) and as GLSL (its rows: %s), reading the "
          "depth map with %s filtering ([docs/conventions.md](%s)), measured "
          "against the exact ray/heightfield intersection on %s (%s cores, %s). Explore it: [report.html](report.html) "
          "(every configuration on its error-against-cost frontier, with filters and images); the long tables: "
          "[tables.md](tables.md); the rows: [%s](%s) (`heightmarch report RUN --csv` writes them flat as "
          "measurements.csv, for a spreadsheet). What every measure means: [docs/measures.md](%s); the files: "
          "[docs/measurements.md](%s)." % (md(" and ".join(gl_renderers(run.rows)) or "none in this run"),
                                           md(run.filter), markdown_target(docs_link(run, *FILTER_DOCS)),
                                           md(p.get("cpu", "?")), md(p.get("cores", "?")), md(run.best_isa),
                                           md(json_file), markdown_target(json_file),
                                           markdown_target(docs_link(run, "measures.md")),
                                           markdown_target(docs_link(run, "measurements.md")))]
    if run.load.get("busy"):  # the speeds below carry it; the warnings after the summary say why
        lines += ["", "*The machine was busy during this run: speeds and ratios may be disturbed (see the warnings below). "
                   "Errors and samples per ray are deterministic and unaffected.*"]
    lines += section_alerts(alerts) + section_recommendation(run, recommendation)
    lines += section_claims(run, claims) + section_filters(run, recommendation) + section_ratios(run)
    lines += section_warnings(run, faults)
    lines += section("The tables", ["In [tables.md](tables.md): " + "; ".join(
        "[%s](tables.md#%s)" % (t, anchor) for t, anchor in TABLES) + "."])
    lines += plots + section_machine(run)
    tables_md = ["# heightmarch tables: " + md(title), "",
                 "The long tables of [report.md](report.md). Speeds: median (min-max) of the repetitions; ratios: "
                 "median (min-max) of the per-round ratios."] + tables
    if csv:
        atomic_write(os.path.join(run.dir, "measurements.csv"), measurements_csv(run.rows))
    atomic_write(os.path.join(run.dir, "tables.md"), "\n".join(tables_md) + "\n")
    atomic_write(os.path.join(run.dir, "report.md"), "\n".join(lines) + "\n")
    report_page.write_page(run, claims, recommendation, alerts, recorded, warnings(run, faults), faults,
                           backend_colours(run.backend_names()))

