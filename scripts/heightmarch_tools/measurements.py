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
import re

from .escape import csv_cell, terminal
from .readers import Where, quoted, read_json, run_file
from .spreads import per_round

MEASUREMENTS_FORMAT = "heightmarch-measurements"
MEASUREMENTS_VERSION = 3  # the newest this reads; 1: the measures were named uv_mean, uv_p95, ...; 3 added
                          # the errors in pixels, the search error and the filter's bias
CLAIMS_VERSION = 2        # 1: a bare list of claims
KINDS = ("trace", "glsl", "roofline", "ceiling", "naive", "autovec", "exact", "calibration")
GL_FIELDS = ("path", "device", "renderer", "version", "driver", "label")  # a GLSL row's renderer (its "gl")
NON_ISA_BACKENDS = ("glsl", "naive", "exact", "calibration")
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

# The measures of a file written before measurements.json listed them (docs/measurements.md: "the
# ten above"); a newer file's own list ("measures") is read instead.
FORMER_MEASURES = [{"name": n, "label": label} for n, label in (
    ("uv_error_mean", "mean uv error (texels)"), ("uv_error_rms", "RMS uv error (texels)"),
    ("uv_error_p50", "p50 uv error (texels)"), ("uv_error_p95", "p95 uv error (texels)"),
    ("uv_error_p99", "p99 uv error (texels)"), ("uv_error_max", "max uv error (texels)"),
    ("wrong_surface_rate", "wrong surface (share of rays)"), ("depth_error_mean", "mean depth error"),
    ("shadow_error_mean", "mean shadow factor error"), ("shadow_mismatch_rate", "shadow mismatch (share)"))]
MEASURE_NAME = re.compile(r"[a-z][a-z0-9_]*")


def upgrade(data):
    """An older measurements.json as the newest: the measures of format 1 under their one name
    (uv_p95 -> uv_error_p95), as bench.json and every newer file name them; the list of measures
    where the file has none."""
    if isinstance(data, dict) and "measures" not in data:
        data = dict(data, measures=FORMER_MEASURES)
    if data.get("schema") != MEASUREMENTS_FORMAT + "/1":
        return data
    data = dict(data, format=MEASUREMENTS_FORMAT, format_version=1)
    for row in data.get("rows") or []:
        errors = row.get("errors") if isinstance(row, dict) else None
        if isinstance(errors, dict):
            row["errors"] = {("uv_error_" + k[3:] if k.startswith("uv_") else k): v for k, v in errors.items()}
    return data


MARKERS = set("osDd^v<>P+XxphH8*")  # matplotlib's marker codes the plots and the page draw
COLOUR = re.compile(r"#[0-9a-fA-F]{6}")
LAYERS = re.compile(r"[1-9][0-9]{0,3}(-[1-9][0-9]{0,3})?")  # a layer spec as the tool writes it: N or A-B
IMAGE = re.compile(r"gallery/[A-Za-z0-9_+][A-Za-z0-9._+-]*\.(?:png|webp)")  # a file in the run's gallery/, nothing else
MAX_ID = 2 ** 31 - 1
MAX_SIZE = 2 ** 30
MAX_THREADS = 2 ** 20
MAX_SECONDS = 7 * 24 * 3600.0  # a repetition of a week: beyond any run, and no figure of it overflows
LARGEST = 1e30                 # errors, samples and rates far beyond any map, still finite in any formula


def validate(data, where):
    """Checks every field the report and the page read, its type and range, so that a malformed
    or hostile file fails with one line naming the field, never with a traceback or a figure made
    of a bad value (NaN, 1e308 seconds, -1 rays, an id of 1e20, a uv error of -5)."""
    where.object(data)
    where["format_version"].check(data.get("format") == MEASUREMENTS_FORMAT and isinstance(data.get("format_version"), int)
                                  and 1 <= data["format_version"] <= MEASUREMENTS_VERSION,
                                  "not a %s file of format 1 to %d" % (MEASUREMENTS_FORMAT, MEASUREMENTS_VERSION))
    provenance = where["provenance"].object(data.get("provenance"))
    for key in ("commit", "cpu", "compiler", "build_type", "date", "best_isa"):
        where["provenance"][key].text(provenance.get(key), none=True)
    for key in ("cores", "threads"):
        where["provenance"][key].integer(provenance.get(key), 1, MAX_THREADS, none=True)
    plan = where["plan"].object(data.get("plan"))
    where["plan"]["name"].text(plan.get("name"), none=True)
    where["plan"]["repetitions"].integer(plan.get("repetitions"), 1, 10 ** 6, none=True)
    where["plan"]["min_seconds_per_repetition"].number(plan.get("min_seconds_per_repetition"), 0, MAX_SECONDS, none=True)
    load = where["load"].object(data.get("load"))
    for key in ("before", "after"):
        where["load"][key].numbers(load.get(key) or [], 0, LARGEST)
    where["load"]["other_cpu_share"].number(load.get("other_cpu_share"), 0, LARGEST, none=True)
    reasons = where["load"]["busy_reasons"]
    for i, r in enumerate(reasons.list(load.get("busy_reasons") or [])):
        reasons[i].text(r)
    techniques = where["techniques"].list(data.get("techniques"))
    for i, t in enumerate(techniques):
        w = where["techniques"][i]
        w.object(t, ("name", "layered", "color", "marker"))
        w["name"].text(t["name"])
        w["layered"].boolean(t["layered"])
        w["color"].check(isinstance(t["color"], str) and COLOUR.fullmatch(t["color"]), "is not a colour #rrggbb")
        w["marker"].one_of(t["marker"], sorted(MARKERS))
        w["description"].text(t.get("description", ""))
    for i, m in enumerate(where["measures"].list(data.get("measures"))):
        where["measures"][i].object(m, ("name", "label"))
        where["measures"][i]["name"].check(isinstance(m["name"], str) and MEASURE_NAME.fullmatch(m["name"]),
                                           "is not a measure's name (lower case, digits, _)")
        where["measures"][i]["label"].text(m["label"])
    backends = where["backends"].list(data.get("backends"))
    where["backends"].check(backends, "is empty")
    for i, b in enumerate(backends):
        where["backends"][i].text(b)
    names = {t["name"] for t in techniques}
    rows = where["rows"].list(data.get("rows"))
    ids = set()
    for i, row in enumerate(rows):
        validate_row(row, where["rows"][i], names, backends)
        where["rows"][i]["id"].check(row["id"] not in ids, "is %d, the id of an earlier row" % row["id"])
        ids.add(row["id"])


def validate_row(row, where, techniques, backends):
    where.object(row, ("id", "kind", "backend", "threads", "heightfield", "view"))
    row["id"] = where["id"].integer(row["id"], 0, MAX_ID)
    where["kind"].one_of(row["kind"], KINDS)
    where["backend"].one_of(row["backend"], backends)
    if row.get("technique") is not None and row["technique"] != "shader":
        where["technique"].one_of(row["technique"], sorted(techniques))
    for key in ("failure", "wrap", "shader"):
        if not isinstance(row.get(key), dict):
            where[key].text(row.get(key), none=True)
    if row.get("layers") is not None:  # shown as it is in every table: its form checked as recommend's reader does
        where["layers"].check(isinstance(row["layers"], str) and LAYERS.fullmatch(row["layers"]),
                              "is %s, not a layer count N or range A-B" % quoted(row["layers"]))
    for i, p in enumerate(where["purposes"].list(row.get("purposes", []))):
        where["purposes"][i].text(p)
    row["threads"] = where["threads"].integer(row["threads"], 1, MAX_THREADS)
    for key in ("min_layers", "max_layers", "refine"):
        where[key].integer(row.get(key), 0, MAX_SIZE, none=True)
    hf = where["heightfield"].object(row["heightfield"], ("label", "width", "height"))
    where["heightfield"]["label"].text(hf["label"])
    view = where["view"].object(row["view"], ("kind", "width", "height"))
    where["view"]["kind"].text(view["kind"])
    for thing, w in ((hf, where["heightfield"]), (view, where["view"])):
        for key in ("width", "height"):
            thing[key] = w[key].integer(thing[key], 1, MAX_SIZE)
    for key in ("theta", "phi", "near_angle", "far_angle"):
        where["view"][key].number(view.get(key), -360, 360, none=True)
    where["rays"].integer(row.get("rays"), 0, 2 ** 53, none=True)
    for key in ("samples", "samples_per_ray", "simd_utilization", "scale"):
        where[key].number(row.get(key), 0, LARGEST, none=True)
    for key in ("precompute_seconds", "precompute_ms_per_frame"):
        where[key].number(row.get(key), 0, MAX_SECONDS * 1e3, none=True)
    errors = row.get("errors")
    if errors is not None:
        for key, value in where["errors"].object(errors).items():
            if key == "confidence":  # each measure's 95% interval, and the effective rays
                for name, interval in where["errors"][key].object(value).items():
                    w = where["errors"][key][name]
                    if name == "effective_rays" or name.endswith("_effective_rays"):  # the uv error's, another's
                        w.number(interval, 0, LARGEST)
                    else:
                        w.numbers(interval, 0, LARGEST, least=2)
                        w.check(len(interval) == 2, "is not a pair of numbers")
            elif key in ("by_azimuth", "by_view_angle"):  # over a view set: its groups' figures
                for i, group in enumerate(where["errors"][key].list(value)):
                    w = where["errors"][key][i]
                    w.object(group, ("from", "to", "rays", "uv_error_p99", "wrong_surface_rate", "wrong_surface_ci"))
                    for name in ("from", "to"):
                        w[name].number(group[name], -360, 360)
                    w["rays"].integer(group["rays"], 0, 2 ** 53)
                    w["uv_error_p99"].number(group["uv_error_p99"], 0, LARGEST)
                    w["wrong_surface_rate"].number(group["wrong_surface_rate"], 0, 1)
                    w["wrong_surface_ci"].numbers(group["wrong_surface_ci"], 0, 1, least=2)
            else:
                where["errors"][key].number(value, 0, LARGEST, none=True)
    gl = row.get("gl")  # a GLSL row's renderer (absent before rows recorded it)
    if gl is not None:
        where["gl"].object(gl, GL_FIELDS)
        for key in GL_FIELDS:
            where["gl"][key].text(gl[key])
    speed = row.get("speed")
    if speed is not None:
        w = where["speed"]
        w.object(speed, ("seconds", "rays_per_second"))
        seconds = w["seconds"].numbers(speed["seconds"], 0, MAX_SECONDS, low_open=True, least=1)
        rates = w["rays_per_second"].object(speed["rays_per_second"], ("rounds",))
        rounds = w["rays_per_second"]["rounds"].numbers(rates["rounds"], 0, LARGEST, low_open=True, least=1)
        w["rays_per_second"]["rounds"].check(len(rounds) == len(seconds), "has %d values for %d repetitions' seconds" % (
            len(rounds), len(seconds)))
    image_error = row.get("image_error")  # the shaded image's (absent before runs compared one)
    if image_error is not None:
        w = where["image_error"]
        w.object(image_error, ("mean", "p99", "visible_share"))
        for key in ("mean", "p99"):
            w[key].number(image_error[key], 0, LARGEST)
        w["visible_share"].number(image_error["visible_share"], 0, 1)
    images = row.get("images")
    if images is not None:
        for key, path in where["images"].object(images).items():
            if path is not None:
                where["images"][key].check(isinstance(path, str) and IMAGE.fullmatch(path),
                                           "is %s, not a PNG in the run's gallery/" % quoted(path))


def wrong_ci_name(wrong):
    """The interval of a wrong rate: wrong_pixel_rate -> wrong_pixel_ci (as metrics.hpp names it)."""
    return wrong[:-len("_rate")] + "_ci"


def upgrade_recommendation(data):
    """An older recommendation.json (formats 1 and 2: one filter, a target in texels on the uv error) as
    the newest: the target's measures under their names, each backend with the file's filter."""
    target = data.get("target")
    if not isinstance(target, dict) or "wrong_measure" in target:
        return
    target.update(wrong_measure="wrong_surface_rate", unit="texels", max_error=target.get("uv_error_texels"),
                  max_wrong_rate=target.get("wrong_surface_rate"))
    for b in data.get("backends") or []:
        if isinstance(b, dict):
            b.setdefault("filter", data.get("filter", "bilinear"))


def validate_recommendation(data, where):
    """recommendation.json: the fields report.md and the page show (an older file upgraded in place)."""
    where.object(data, ("target", "backends"))
    upgrade_recommendation(data)
    target = where["target"].object(data["target"], ("measure", "wrong_measure", "unit", "max_error",
                                                     "max_wrong_rate", "frames", "description"))
    for key in ("measure", "wrong_measure"):
        where["target"][key].check(isinstance(target[key], str) and MEASURE_NAME.fullmatch(target[key]),
                                   "is not a measure's name")
    where["target"]["unit"].check(target["unit"] in ("texels", "pixels"), "is neither texels nor pixels")
    where["target"]["max_error"].number(target["max_error"], 0, LARGEST)
    where["target"]["max_wrong_rate"].number(target["max_wrong_rate"], 0, 1)
    where["target"]["frames"].integer(target["frames"], 1, 2 ** 31)
    where["target"]["description"].text(target["description"])
    for i, b in enumerate(where["backends"].list(data["backends"])):
        w = where["backends"][i]
        w.object(b, ("backend", "threads", "filter", "name", "all_heightfields", "per_heightfield"))
        w["backend"].text(b["backend"])
        w["name"].text(b["name"])
        w["filter"].check(b["filter"] in ("bilinear", "trilinear"), "is neither bilinear nor trilinear")
        w["threads"].integer(b["threads"], 1, MAX_THREADS)
        validate_answer(b["all_heightfields"], w["all_heightfields"], target)
        for j, a in enumerate(w["per_heightfield"].list(b["per_heightfield"])):
            validate_answer(a, w["per_heightfield"][j], target)


def validate_answer(answer, where, target):
    where.object(answer)
    where["heightfield"].text(answer.get("heightfield"), none=True)
    where["settings"].integer(answer.get("settings", 0), 0, 2 ** 31)
    for key in ("choice", "closest", "runner_up"):
        if answer.get(key) is not None:
            validate_pick(answer[key], where[key], target)
    for i, pick in enumerate(where["failed_held_out"].list(answer.get("failed_held_out", []))):
        validate_pick(pick, where["failed_held_out"][i], target)
    near = answer.get("near_miss")
    if near is not None:  # format 2
        where["near_miss"].object(near, ("setting", "margin", "measure"))
        where["near_miss"]["margin"].number(near["margin"], 0, LARGEST)
        where["near_miss"]["measure"].text(near["measure"])
        validate_pick(near["setting"], where["near_miss"]["setting"], target)
    ratio = answer.get("runner_up_time_ratio")
    if ratio is not None and "per_round" in ratio:  # format 2: the ratio of the medians, the rounds' spread
        where["runner_up_time_ratio"].object(ratio, ("ratio", "per_round", "distinguishable"))
        where["runner_up_time_ratio"]["ratio"].number(ratio["ratio"], 0, LARGEST)
        validate_spread(ratio["per_round"], where["runner_up_time_ratio"]["per_round"])
    elif ratio is not None:
        validate_spread(ratio, where["runner_up_time_ratio"])


def validate_pick(pick, w, target):
    measure, wrong = target["measure"], target["wrong_measure"]
    w.object(pick, ("label", "ns_per_ray", "rows"))
    w["label"].text(pick["label"])
    validate_spread(pick["ns_per_ray"], w["ns_per_ray"])
    for i, r in enumerate(w["rows"].list(pick["rows"])):
        wr = w["rows"][i]
        wr.object(r, ("id", measure, wrong, "samples_per_ray"))
        wr["id"].integer(r["id"], 0, MAX_ID)
        wr["heightfield"].text(r.get("heightfield", ""))
        wr[measure].number(r[measure], 0, LARGEST)
        wr[wrong].number(r[wrong], 0, 1)
        wr["samples_per_ray"].number(r["samples_per_ray"], 0, LARGEST)
        for key in ("precompute_seconds", "precompute_ms_per_frame"):
            wr[key].number(r.get(key), 0, LARGEST, none=True)
        for key in ("selection", "held_out"):  # format 2: the figures on each view set, with their intervals
            figures = r.get(key)
            if figures is None:
                continue
            wf = wr[key]
            wrong_ci = wrong_ci_name(wrong)
            wf.object(figures, (measure, measure + "_ci", wrong, wrong_ci))
            wf[measure].number(figures[measure], 0, LARGEST)
            wf[wrong].number(figures[wrong], 0, 1)
            for ci, high in ((measure + "_ci", LARGEST), (wrong_ci, 1)):
                wf[ci].check(isinstance(figures[ci], list) and len(figures[ci]) == 2, "is not a pair of numbers")
                for x in figures[ci]:
                    wf[ci].number(x, 0, high)
    w["rows"].check(pick["rows"], "is empty")


def validate_spread(s, where):
    where.object(s, ("median", "min", "max"))
    for key in ("median", "min", "max"):
        where[key].number(s[key], 0, LARGEST)


def validate_alerts(data, where):
    """alerts.json, as record_run writes it."""
    where["machine"].text(data.get("machine"))
    where["rule"].text(data.get("rule"))
    where["series_tested"].integer(data.get("series_tested"), 0, 2 ** 31)
    for i, a in enumerate(where["alerts"].list(data.get("alerts"))):
        w = where["alerts"][i]
        w.object(a, ("series", "kind", "metric", "message"))
        for key in ("series", "kind", "metric", "message"):
            w[key].text(a[key])
        for key in ("baseline", "baseline_spread", "new"):
            w[key].number(a.get(key), 0, LARGEST, none=True)
        w["change"].number(a.get("change"), -1, LARGEST, none=True)


def read_claims(path):
    """claims.json's claims (a list, whichever format), checked; None without the file."""
    if not os.path.lexists(path):
        return None
    where = Where(terminal(path))
    data = read_json(path)
    claims = data if isinstance(data, list) else where.object(data, ("claims",))["claims"]
    for i, c in enumerate(where["claims"].list(claims)):
        w = where["claims"][i]
        w.object(c, ("id", "claim", "verdict"))
        for key in ("id", "claim", "verdict", "source", "rule"):
            w[key].text(c.get(key, ""))
        for j, check in enumerate(w["checks"].list(c.get("checks", []))):
            w["checks"][j].object(check)
            for key in ("where", "figures"):
                w["checks"][j][key].text(check.get(key, ""))
            w["checks"][j]["passed"].boolean(check.get("passed", False))
    return claims


def read_optional(path, format_name, validate):
    """A run's recommendation.json or alerts.json, checked by validate(data, where); None without it."""
    if not os.path.lexists(path):
        return None
    where = Where(terminal(path))
    data = where.object(read_json(path), ("format_version",))
    where["format"].check(data.get("format", format_name) == format_name, "is not %s" % format_name)
    validate(data, where)
    return data


def load_run(run_dir):
    """The run of run_dir: its measurements.json (or measurements.json.gz) read (readers.read_json)
    and checked (validate)."""
    path = run_file(run_dir, "measurements.json")
    where = Where(terminal(path))
    data = upgrade(where.object(read_json(path)))
    validate(data, where)
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

def is_view_set(view):
    """Whether a row's figures are over a view set (docs/measures.md#view-sets): the default view or a
    sweep seen around the surface, the tutorial's scene, camera poses or fresh rays; or over a
    held-out draw of a window (a seed of its own). Such figures are another series than the single
    view's."""
    return bool(view.get("around") or view["kind"] in ("tutorial", "poses") or view.get("fresh_rays")
                or view.get("seed"))


def view_name(view, angles=True):
    """'default 1024x1024', 'sweep 128x128 theta 70 phi 270'; a view set as the tool describes it
    ('around 1024x1024', 'around 1024x1024 seed 2', 'tutorial:16 566x425'), a sweep around without
    its angle where angles is false ('sweep around 128x128')."""
    if is_view_set(view):
        if view["kind"] == "sweep" and not angles:
            return "sweep around %dx%d" % (view["width"], view["height"])
        return view["description"]
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


def gl_label(row):
    """What a GLSL row ran on, as results name it: its renderer's label ('glsl (llvmpipe, LLVM 15.0.6,
    256 bits; OSMesa)'), or 'glsl' for a run from before rows recorded their renderer."""
    return row["gl"]["label"] if row.get("gl") else row["backend"]


def gl_renderers(rows):
    """The GL renderers of a run's GLSL rows, each once in the rows' order, for the text that names
    them: 'glsl (llvmpipe, LLVM 15.0.6, 256 bits; OSMesa)', or 'glsl' for a run that did not record it."""
    return list(dict.fromkeys(gl_label(r) for r in rows if r["kind"] == "glsl"))


def config(row):
    """Every field that names a configuration; two rows with equal configs are the same measurement."""
    view = row["view"]
    return {"kind": row["kind"], "backend": row["backend"], "threads": row["threads"],
            "technique": row.get("technique"), "layers": row.get("layers"),
            "heightfield": row["heightfield"]["label"], "depth_map": depth_map(row),
            "view": (view["kind"], view["width"], view["height"], view.get("theta"), view.get("phi"),
                     view.get("near_angle"), view.get("far_angle"), view.get("around"), view.get("seed"),
                     view.get("views")),
            "scene": (row.get("scale"), row.get("wrap"), row.get("discard")),
            # null for the exact reference (every filter's); absent before filters: bilinear
            "filter": row.get("filter", "bilinear")}


def csv_value(value):
    """JSON's values as CSV text: numbers as they read back (repr: 0.1, not 0.100000001), true/false, empty for null,
    text through escape.csv_cell (no cell a spreadsheet would evaluate)."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return csv_cell(value)
    return repr(value) if isinstance(value, float) else str(value)


def flat_row(row, prefix=""):
    """A row as flat (column, value) pairs: nested fields joined by '.', lists by ';', lists of objects
    (a view set's groups) by their index ('errors.by_azimuth.0.wrong_surface_rate')."""
    out = []
    for key, value in row.items():
        name = prefix + key
        if isinstance(value, dict):
            out += flat_row(value, name + ".")
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            for i, v in enumerate(value):
                out += flat_row(v, "%s.%d." % (name, i))
        elif isinstance(value, list):
            text = ";".join(csv_value(v) for v in value)
            out.append((name, csv_cell(text) if any(isinstance(v, str) for v in value) else text))
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
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(csv_cell(c) for c in columns)  # a field's name is text from the file, as its values are
    writer.writerows([f.get(c, "") for c in columns] for f in flat)
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
        self.measures = data["measures"]  # [{"name", "label"}], the run's own list
        self.style = {t["name"]: t for t in data["techniques"]}
        self.backends = data["backends"]
        self.isas = [b for b in self.backends if b not in NON_ISA_BACKENDS]
        self.best_isa = self.provenance.get("best_isa") or (self.isas[-1] if self.isas else None)
        self.heightfields = list(dict.fromkeys(r["heightfield"]["label"] for r in self.rows))
        self.configs = [(config(r), r) for r in self.timed]
        # the technique x layers matrix: technique rows only (an exact row may serve the matrix too)
        self.matrix = sorted((r for r in self.with_purpose("matrix") if r.get("technique")), key=self.order)
        # the filter the run's figures are read with (docs/conventions.md#filters): its rows' but the
        # comparison's; runs before filters read level 0
        self.filter = next((r["filter"] for r in self.rows if r.get("filter") and r.get("technique")
                            and "filters" not in r.get("purposes", [])), "bilinear")
        # The window the answer was measured over (its timed candidates' view) and its held-out set.
        window = next((r for p in ("matrix", "claims", "glsl") for r in self.with_purpose(p) if r.get("speed")), None)
        held_out = next(iter(self.with_purpose("held-out")), None)
        self.window = view_name(window["view"]) if window else None
        self.held_out_window = view_name(held_out["view"]) if held_out else None

    def with_purpose(self, purpose):
        return [r for r in self.rows if purpose in r.get("purposes", [])]

    def partner(self, row, **changes):
        """The timed row measured like `row` except for `changes` (ANY: not compared)."""
        want = dict(config(row), **changes)
        for c, r in self.configs:
            if all(v is ANY or c[k] == v or (k == "filter" and None in (v, c[k])) for k, v in want.items()):
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

    def averages(values):
        return "/".join("%.2f" % x for x in values or []) or "?"
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
            ("other processes' CPU share", "%.1f%%" % (100 * (load.get("other_cpu_share") or 0))),
            ("GL renderer", "; ".join(list(dict.fromkeys(
                "%s: %s, %s, device %s" % (r["gl"]["label"], r["gl"]["version"], r["gl"]["driver"], r["gl"]["device"])
                if r.get("gl") else "not recorded (before renderers were)" for r in run.rows if r["kind"] == "glsl")))
             or "no GLSL rows")]


def docs_link(run, page, anchor=None):
    """A link from the run directory to a page of docs/, relative to wherever the run was written
    (results/<run>/ or any --out), so it holds in a checkout."""
    target = os.path.relpath(os.path.join(DOCS, page), os.path.abspath(run.dir))
    return target + ("#" + anchor if anchor else "")


def glsl_pairs(run):
    """(CPU row at the best ISA, GLSL row) at the same configuration and threads, for every GLSL row."""
    return [(run.partner(g, kind="trace", backend=run.best_isa), g) for g in sorted(
        (r for r in run.timed if r["kind"] == "glsl"), key=run.order)]


def filter_pairs(run):
    """(the run's row, the same configuration under another filter) for every row of the matrix the
    run also measured under a compared filter (purpose "filters", accuracy only)."""
    pairs = [(run.partner(r, filter=ANY), r) for r in sorted(run.with_purpose("filters"), key=run.order)]
    return [(own, other) for own, other in pairs if own is not None]


def walks_per_isa(run):
    """searches_per_isa's entries of the walks: the techniques of shape "walk" (measurements.json's
    techniques say; none in a run from before they did), whose SIMD use is their own measure."""
    walks = {t["name"] for t in run.data["techniques"] if t.get("shape") == "walk"}
    return [f for f in searches_per_isa(run) if any(r["technique"] in walks for r in f[4].values())]


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
