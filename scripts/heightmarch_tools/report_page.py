"""RUN_DIR/report.html: the run to explore, a page that opens offline.

The page is the run's data (the rows of measurements.json that carry a technique, the
recommendation, the claims, the alerts and the recorded history of its machine; gzip'd and base64'd,
a tenth of the JSON, unpacked by the browser's DecompressionStream) and the page's own script and
style (page/), inlined. Plotly (vendor/plotly.js-basic-dist-min/, MIT, 1.2 MB) is one file beside
the runs, RUN_DIR/../plotly-basic.min.js, written there once (shared_plotly) rather than into every
page; where that directory cannot be written to, the page inlines it. The gallery's images are the
run's own files beside it (gallery/*.webp). Nothing is fetched from the network when it opens.
report.py calls write_page().
"""
import base64
import gzip
import os

from .measurements import (HEADLINE_LAYERS, HEADLINE_TECHNIQUE, MAXMIP_PEAK, SHADOW_COUNTS, backend_label, depth_map,
                          docs_link, filter_pairs, gl_label, glsl_pairs, machine_rows, ns_per_ray_rounds, rays_rounds,
                          searches_per_isa, speedup, view_name)
from .errors import CannotWrite
from .readers import run_file
from .escape import csv_cell, html as esc, script_json
from .report_content import (FILTER_DOCS, alerts_summary, breakdown_lines, filter_table, filters_intro, filters_title,
                             fmt_ratio, fmt_spread, recommendation_columns, recommendation_intro, recommendation_rows,
                             walks_table, WALKS_INTRO)
from .spreads import spread
from .writers import atomic_write

HERE = os.path.dirname(os.path.abspath(__file__))
PLOTLY = os.path.join(HERE, "vendor", "plotly.js-basic-dist-min", "plotly-basic.min.js")
PAGE_SCRIPT = os.path.join(HERE, "page", "page.js")
PAGE_STYLE = os.path.join(HERE, "page", "page.css")


SHARED_PLOTLY = "plotly-basic.min.js"  # the name beside the runs: report.html loads ../SHARED_PLOTLY


def read(path):
    """A file of the page's own (its script, style, Plotly), beside this module."""
    with open(path, encoding="utf-8") as f:
        return f.read()


def shared_plotly(run_dir):
    """Plotly where the page loads it, RUN_DIR/../plotly-basic.min.js, written there where it is
    missing or another version (a repository's results/ keeps one, a link to vendor/): True; False
    where that directory cannot be written to (the page then inlines Plotly)."""
    path = os.path.join(os.path.dirname(os.path.abspath(run_dir)), SHARED_PLOTLY)
    plotly = read(PLOTLY)
    try:
        with open(path, encoding="utf-8") as f:
            if f.read() == plotly:
                return True
    except (OSError, UnicodeDecodeError):
        pass
    try:
        atomic_write(path, plotly)
    except CannotWrite:
        return False
    return True


def packed_json(data):
    """data as the page carries it: JSON (escape.script_json), gzip'd (no time stamp: the same run
    writes the same page) and base64'd, which no HTML parser reads into."""
    return base64.b64encode(gzip.compress(script_json(data).encode("utf-8"), compresslevel=9, mtime=0)).decode("ascii")


def heightfield_keys(run):
    """Each row's heightfield as the page names it: its label, with the depth map's size where the
    run has that label at several sizes (the large maps of claim P2)."""
    sizes = {}
    for r in run.rows:
        sizes.setdefault(r["heightfield"]["label"], set()).add(depth_map(r))
    return {id(r): r["heightfield"]["label"] + (" (%s)" % depth_map(r) if len(sizes[r["heightfield"]["label"]]) > 1 else "")
            for r in run.rows}


def rounded(value, digits=6):
    """A figure for the page, to `digits` significant digits (the page shows three or four)."""
    return None if value is None else float("%.*g" % (digits, value))


def rounded_figures(entry):
    """A breakdown entry's figures (and intervals) rounded as the page's other figures are: two
    thirds of the page's data were digits it never shows."""
    def one(v):
        return rounded(v) if isinstance(v, float) else [one(x) for x in v] if isinstance(v, list) else v
    return {k: one(v) for k, v in entry.items()}


def page_rows(run):
    """The rows that have a technique and error measures: every point the frontier can show."""
    keys = heightfield_keys(run)
    out = []
    for r in run.rows:
        if r.get("technique") not in run.style or not r.get("errors") or r.get("failure"):
            continue
        if r.get("filter") not in (None, run.filter):  # the other filter's rows: their own table
            continue
        if r.get("purposes") == ["held-out"]:  # read through the recommendation, not a point of its own
            continue
        rays, ns = spread(rays_rounds(r)), spread(ns_per_ray_rounds(r))
        out.append({
            "id": r["id"], "heightfield": keys[id(r)], "label": r["heightfield"]["label"], "depth_map": depth_map(r),
            "technique": r["technique"], "layers": r["layers"], "kind": r["kind"], "backend": backend_label(r),
            "renderer": gl_label(r) if r["kind"] == "glsl" else backend_label(r),
            "threads": r["threads"], "view": view_name(r["view"]), "purposes": r.get("purposes", []),
            "rays_per_second": [rounded(x) for x in rays] if rays else None,
            "ns_per_ray": [rounded(x) for x in ns] if ns else None,
            "samples_per_ray": rounded(r.get("samples_per_ray")),
            "precompute_seconds": rounded(r.get("precompute_seconds")),
            "errors": {m["name"]: rounded(r["errors"][m["name"]]) for m in run.measures
                       if r["errors"].get(m["name"]) is not None},
            "breakdown": {k: [rounded_figures(b) for b in r["errors"][k]] for k in ("by_azimuth", "by_view_angle")
                          if r["errors"].get(k)} or None,
            "images": r.get("images")})
    return out


# ---------------------------------------------------------------------------------------------
# Static tables, as HTML

def cell(value, cls=None):
    return "<td%s>%s</td>" % (' class="%s"' % cls if cls else "", value)


def table(columns, rows, cls=""):
    """columns: [(title, numeric)]; rows: lists of cells already escaped (HTML)."""
    head = "".join("<th%s>%s</th>" % (' class="num"' if num else "", esc(t)) for t, num in columns)
    body = "".join("<tr>%s</tr>" % "".join(cell(c, "num" if num else None) for c, (_, num) in zip(cells, columns))
                   for cells in rows)
    return '<table class="%s"><thead><tr>%s</tr></thead><tbody>%s</tbody></table>' % (cls, head, body)


def link(href, text):
    return '<a href="%s">%s</a>' % (esc(href), esc(text))


def glsl_table(run, pairs):
    rows = [[esc(g["heightfield"]["label"]), esc(g["technique"]), esc(g["layers"]), g["threads"],
             fmt_spread(spread(rays_rounds(c)), 1, 1e-6), fmt_spread(spread(rays_rounds(g)), 1, 1e-6),
             fmt_ratio(speedup(c, g))] for c, g in pairs]
    return table([("heightfield", False), ("technique", False), ("layers", False), ("threads", True),
                  ("CPU %s Mrays/s" % run.best_isa, True), ("GLSL Mrays/s", True), ("CPU/GLSL", True)], rows)


def isa_table(run, found):
    rows = [[esc(hf), esc(technique), threads, fmt_spread(spread(rays_rounds(glsl)), 1, 1e-6)] + [
        c for isa in run.isas for c in (
            (fmt_spread(spread(rays_rounds(by_isa[isa])), 1, 1e-6), fmt_ratio(speedup(by_isa[isa], glsl)))
            if isa in by_isa else ("-", "-"))] for hf, technique, threads, glsl, by_isa in found]
    return table([("heightfield", False), ("technique", False), ("threads", True), ("GLSL Mrays/s", True)] + [
        c for isa in run.isas for c in (("%s Mrays/s" % isa, True), ("x GLSL", True))], rows)


def isa_bars(found):
    """The per-ISA chart's data: per heightfield, threads and search, Mrays/s (median, min, max) per backend."""
    out = []
    for hf, technique, threads, glsl, by_isa in found:
        bars = {isa: spread(rays_rounds(r)) for isa, r in by_isa.items()}
        if glsl:
            bars["glsl"] = spread(rays_rounds(glsl))
        out.append({"heightfield": hf, "technique": technique, "threads": threads,
                    "bars": {b: [rounded(x * 1e-6, 4) for x in s] for b, s in bars.items()}})
    return out


def filters_html(run, recommendation):
    """The matrix under both filters (report_content's table, as report.md shows it), or a line
    saying it was not measured."""
    pairs = filter_pairs(run)
    if not pairs:
        return ("<p>Not measured in this run: every row is read with %s filtering (suite --filter bilinear,trilinear "
                "measures both).</p>" % esc(run.filter))
    target = (recommendation or {}).get("target")
    columns, rows = filter_table(run, pairs, target)
    return ("<h3>%s</h3><p>%s What each error means: %s; the filters: %s.</p>" % (
        esc(filters_title(run, pairs)), esc(filters_intro(run, pairs, target)),
        link(docs_link(run, "measures.md"), "docs/measures.md"), link(docs_link(run, *FILTER_DOCS), "docs/conventions.md"))
            + table(columns, [[esc(c) for c in cells] for cells in rows]))


def claims_html(claims, maxmip_link):
    if not claims:
        return "<p>No claims in this run.</p>"
    parts = []
    for c in claims:
        checks = c.get("checks") or []
        passed = sum(1 for k in checks if k.get("passed"))
        rows = [[esc(k.get("where", "")), esc(k.get("figures", "")),
                 "yes" if k.get("passed") else "<b>no</b>"] for k in checks]
        note = (" Maxmip at a grazing one-texel peak: %s." % maxmip_link) if c["id"] == "P2" else ""
        previous = c.get("previous")
        if previous:  # claims.json format 3: a rule revised in this release, the previous verdict beside it
            note += " Revised in this release, because %s. The previous rule: %s Its verdict: %s (%s)." % (
                esc(previous["reason"]), esc(previous["rule"]), esc(previous["verdict"]), esc(previous["summary"]))
        parts.append('<details><summary><b>%s</b> <span class="verdict v-%s">%s</span> %s (%d / %d checks)%s</summary>'
                     '<p>Source: %s. Rule: %s%s</p>%s</details>' % (
                         esc(c["id"]), esc(c["verdict"].replace(" ", "-")), esc(c["verdict"]),
                         esc(c["claim"]), passed, len(checks), ": " + esc(c["summary"]) if c.get("summary") else "",
                         esc(c.get("source", "?")), esc(c.get("rule", "?")), note,
                         table([("where", False), ("figures", False), ("passes", False)], rows) if rows else ""))
    return "".join(parts)


def machine_html(run):
    return table([("", False), ("", False)], [[esc(k), esc(v)] for k, v in machine_rows(run)], "machine")


def warnings_html(warnings):
    """The warnings on the page's first screen, as report.md has them (report_content.warnings)."""
    if not warnings:
        return ""
    return '<section id="warnings">%s</section>' % "".join(
        '<p class="warning"><b>%s</b> %s</p>' % (esc(head), esc(text)) for head, text in warnings)


def history_series(run, recorded):
    """The headline configuration (POM-32, 1 thread, default view, the first heightfield, the run's
    filter) over the recorded runs, per machine (the history's machine column; the CPU where it has none) and backend.
    The history holds names as CSV cells (escape.csv_cell): the heightfield is matched so."""
    if recorded is None:
        return None
    hf = run.heightfields[0] if run.heightfields else ""
    series = {}
    for r in recorded:
        if (r.get("technique"), r.get("layers"), r.get("threads"), r.get("heightfield"), r.get("filter")) != (
                HEADLINE_TECHNIQUE, HEADLINE_LAYERS, "1", csv_cell(hf), run.filter) or \
                not r.get("view", "").startswith("default"):
            continue
        machine = r.get("machine") or r.get("cpu") or "?"
        series.setdefault(machine, {}).setdefault(r["backend"], []).append(
            {"date": r["date"], "commit": r["commit"],
             "mrays": [float(r[c]) * 1e-6 for c in ("rays_per_second_median", "rays_per_second_min", "rays_per_second_max")]})
    return {"heightfield": hf, "machines": series}


def write_page(run, claims, recommendation, alerts, recorded, warnings, faults, backend_colours):
    found = searches_per_isa(run)
    walks = walks_table(run)
    data = {
        "title": "%s run of %s, commit %s" % (run.plan.get("name", "?"), run.provenance.get("date", "?"),
                                               run.provenance.get("commit", "?")),
        "techniques": run.data["techniques"],
        "measures": run.measures,
        "backend_colours": backend_colours,
        "rows": page_rows(run),
        "recommendation": recommendation,
        # the table report.md shows, cell for cell (report_content), and the row each line opens
        "recommendation_table": None if recommendation is None else {
            "intro": recommendation_intro(recommendation, run),
            "columns": [title for title, _ in recommendation_columns(recommendation["target"])],
            "rows": recommendation_rows(recommendation),
            "varies": breakdown_lines(run, recommendation)},
        "alerts": alerts,
        "alerts_summary": alerts_summary(alerts),
        "history": history_series(run, recorded),
        "isa_bars": isa_bars(found),
        "isas": run.isas,
        "gallery": [{"label": r["heightfield"]["label"], "kind": r["kind"], "technique": r.get("technique"),
                     "layers": r.get("layers"), "view": view_name(r["view"]), "images": r["images"]}
                    for r in run.rows if r.get("images")],
        "faults": faults,
        "docs": {"recommendation": docs_link(run, "recommendation.md"), "measures": docs_link(run, "measures.md")},
    }
    shadow_link = link(docs_link(run, *SHADOW_COUNTS), "why the shadow's sample counts differ between the CPU and GLSL")
    maxmip_link = link(docs_link(run, *MAXMIP_PEAK), "docs/techniques.md")
    static = {
        "claims": claims_html(claims, maxmip_link),
        "isa_table": isa_table(run, found) if found else "<p>Not measured in this run.</p>",
        "walk_table": ("<p>%s</p>" % esc(WALKS_INTRO) + table(walks[0], [[esc(c) for c in row] for row in walks[1]])
                       if walks else "<p>Not measured in this run.</p>"),
        "glsl_table": ("<p>The same rays and parameters on both sides; CPU at the best ISA (%s); CPU/GLSL: median "
                       "(min-max) of the per-round ratios. See %s.</p>" % (esc(run.best_isa or "?"), shadow_link)
                       + glsl_table(run, glsl_pairs(run))) if glsl_pairs(run) else "<p>Not measured in this run.</p>",
        "machine": machine_html(run),
        "warnings": warnings_html(warnings),
        "filters": filters_html(run, recommendation),
        "filter": esc(run.filter),
    }
    plotly = ('<script src="../%s"></script>' % SHARED_PLOTLY if shared_plotly(run.dir)
              else "<script>\n%s\n</script>" % read(PLOTLY).replace("</script", "<\\/script"))
    text = TEMPLATE % {
        "title": esc(data["title"]),
        "style": read(PAGE_STYLE),
        "plotly": plotly,
        "data": packed_json(data),
        "rows_file": esc(os.path.basename(run_file(run.dir, "measurements.json"))),
        "script": read(PAGE_SCRIPT),
        **static}
    atomic_write(os.path.join(run.dir, "report.html"), text)


TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<link rel="icon" href="data:,">
<title>heightmarch: %(title)s</title>
<style>
%(style)s
</style>
</head>
<body>
<header>
<h1>heightmarch: %(title)s</h1>
<nav><a href="#alerts">alerts</a> <a href="#recommendation">what to ship</a> <a href="#frontier">frontier</a>
<a href="#claims">claims</a> <a href="#filters-compared">filters</a> <a href="#speed">speed per ISA and GLSL</a>
<a href="#history">history</a>
<a href="#provenance">provenance</a> <a href="report.md">report.md</a> <a href="tables.md">tables.md</a>
<a href="%(rows_file)s">%(rows_file)s</a></nav>
</header>
<main>
%(warnings)s
<section id="alerts"><h2>Alerts</h2><div id="alerts-body"></div></section>
<section id="recommendation"><h2>What to ship</h2><div id="recommendation-body"></div></section>
<section id="frontier"><h2>Error against cost, per heightfield</h2>
<p>Every measured configuration of the selection, one point each in its technique's colour and marker: hover for
its figures, click for its images. Filled markers keep the wrong surface within the recommendation's bound, hollow
ones do not; grey steps: the Pareto front (nothing is both cheaper and more accurate); rings: the recommendation
(thick: on this heightfield, thin: one setting for all); dashed: the error bound. Exact results (an error of 0) sit
in the grey band at the bottom.</p>
<div id="filters"></div>
<div id="frontier-charts"></div>
<div id="detail"><p>Click a point to see its configuration, its render, its error map and the exact render.</p></div>
</section>
<section id="claims"><h2>The claims</h2>%(claims)s</section>
<section id="filters-compared"><h2>Bilinear against trilinear filtering</h2>
<p>This run's figures are read with %(filter)s filtering.</p>%(filters)s</section>
<section id="speed"><h2>Speed per ISA, and CPU against GLSL</h2>
<div id="isa-filters"></div><div id="isa-chart"></div>
<details><summary>The searches at every ISA, against GLSL (table)</summary>%(isa_table)s</details>
<details><summary>The walks' samples/s and SIMD use at every ISA (table)</summary>%(walk_table)s</details>
<details><summary>CPU against GLSL (table)</summary>%(glsl_table)s</details>
</section>
<section id="history"><h2>History of this machine</h2><div id="history-body"></div><div id="history-chart"></div></section>
<section id="provenance"><h2>Provenance</h2>%(machine)s</section>
</main>
%(plotly)s
<script id="report-data" type="application/gzip+base64">%(data)s</script>
<script>
%(script)s
</script>
</body>
</html>
"""
