"""What report.md (report.py) and report.html (report_page.py) both say, as plain text made once:
the figures' text (a median with its spread, a ratio, an error), the recommendation's table with
its human column names and the "(not distinguishable)" caveat, the warnings (the busy machine
first), the alerts' summary. Each format renders it with its own escaping rule (escape.markdown,
escape.html or the page's textContent), so the two cannot drift apart.
"""
import math
import statistics

from .measurements import HEADLINE_LAYERS, HEADLINE_TECHNIQUE, counted, rays_rounds, samples_rounds, walks_per_isa
from .spreads import relative_spread, spread

SPREAD_LIMIT = 0.20  # (max - min) / median above this is flagged as a disturbed timing


# ---------------------------------------------------------------------------------------------
# Figures as text

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


def fmt_error(value):
    """A uv error in texels: 0 as 0, small ones with their magnitude, never a made-up 0.000."""
    if value is None:
        return "-"
    return "0" if value == 0 else "%.3g" % value


def fmt_number(value):
    return "-" if value is None else "%.4g" % value


def fmt_change(value):
    return "-" if value is None else "%+.1f%%" % (100 * value)


def load_averages(values):
    return "/".join("%.2f" % x for x in values or []) or "?"


# ---------------------------------------------------------------------------------------------
# The walks' table

WALKS_INTRO = ("The techniques that walk the min-depth pyramid, a divergent walk per lane whose lanes take the "
               "tile's next ray as theirs ends: Msamples/s median (min-max) and SIMD use (of the lanes the kernel "
               "read, the share that belonged to a ray still walking) at every ISA.")


def walks_table(run):
    """The walks' samples/s beside their SIMD use at every ISA: ([(title, numeric)], rows of text),
    or None where the run timed no walk."""
    found = walks_per_isa(run)
    if not found:
        return None

    def simd_use(row):
        return fmt(row.get("simd_utilization"), 0, 100, "%")
    columns = [("heightfield", False), ("technique", False), ("threads", True)] + [
        column for isa in run.isas for column in (("%s Msamples/s" % isa, True), ("%s SIMD use" % isa, True))]
    rows = [[hf, technique, str(threads)] + [
        cell for isa in run.isas for cell in (
            (fmt_spread(spread(samples_rounds(by_isa[isa])), 0, 1e-6), simd_use(by_isa[isa])) if isa in by_isa
            else ("-", "-"))] for hf, technique, threads, _, by_isa in found]
    return columns, rows


# ---------------------------------------------------------------------------------------------
# The recommendation's table

def recommendation_columns(measure):
    """[(title, numeric)]: the table's columns, in words."""
    short = measure.replace("uv_error_", "")
    return [("backend", False), ("heightfield", False), ("configuration", False), ("time per ray (ns)", True),
            ("held-out %s uv error (texels, 95%% interval)" % short, True), ("held-out wrong surface", True),
            ("window: %s uv error; wrong surface" % short, True), ("samples per ray", True), ("preprocessing", False),
            ("next fastest", False), ("notes", False)]


def fmt_interval(value, interval, scale=1.0, unit=""):
    """'0.43 (0.41-0.45)', '0.38% (0.33-0.42%)'; the figure alone without an interval."""
    if value is None:
        return "-"
    if not interval:
        return "%.3g%s" % (value * scale, unit)
    return "%.3g%s (%.3g-%.3g%s)" % (value * scale, unit, interval[0] * scale, interval[1] * scale, unit)


def worst_figures(rows, measure, key):
    """A pick's worst rows on one view set ('selection', or 'held_out'; format 1 rows carry the
    window's figures on the row itself) as text: (the measure, the wrong-surface rate), each with its
    interval; None where a row was not measured there."""
    sets = [r.get(key) if key in r else (r if key == "selection" else None) for r in rows]
    if any(f is None for f in sets):
        return None
    worst = max(sets, key=lambda f: f[measure])
    wrong = max(sets, key=lambda f: f["wrong_surface_rate"])
    return (fmt_interval(worst[measure], worst.get(measure + "_ci")),
            fmt_interval(wrong["wrong_surface_rate"], wrong.get("wrong_surface_ci"), 100, "%"))


def pick_cells(pick, measure):
    """A recommendation's pick as cells: setting, time, its rows' worst figures on the held-out set and
    on the window, samples, preprocessing."""
    rows = pick["rows"]
    precompute = [r for r in rows if r.get("precompute_seconds") is not None]
    pre = "-"
    if precompute:
        worst = max(precompute, key=lambda r: r["precompute_seconds"])
        pre = "%.3g s once (%.3g ms a frame)" % (worst["precompute_seconds"], worst.get("precompute_ms_per_frame") or 0)
    ns = pick["ns_per_ray"]
    held_out = worst_figures(rows, measure, "held_out") or ("not measured", "not measured")
    return [pick["label"], fmt_spread((ns["median"], ns["min"], ns["max"]), 2), held_out[0], held_out[1],
            "; ".join(worst_figures(rows, measure, "selection")),
            "%.1f" % statistics.mean(r["samples_per_ray"] for r in rows), pre]


def answer_notes(answer):
    """What else an answer says: the faster settings that held on the window only, the near miss,
    and whether held-out views checked it."""
    notes = []
    failed = answer.get("failed_held_out") or []
    if failed:
        notes.append("not %s: met the target on the window, not on the held-out views"
                     % ", ".join(p["label"] for p in failed))
    near = answer.get("near_miss")
    if near:
        notes.append("near miss %s: %s %.0f%% over its bound" % (near["setting"]["label"], near["measure"],
                                                                 100 * (near["margin"] - 1)))
    if answer.get("held_out_checked") is False:
        notes.append("not checked on held-out views")
    return "; ".join(notes) or "-"


def runner_up_text(answer):
    runner, ratio = answer.get("runner_up"), answer.get("runner_up_time_ratio")
    if not (runner and ratio):
        return "-"
    if "per_round" in ratio:  # format 2: the ratio of the median times that rank them, the rounds' spread
        rounds = ratio["per_round"]
        return "%s: %.2fx the time (per round %.2f-%.2f)%s" % (
            runner["label"], ratio["ratio"], rounds["min"], rounds["max"],
            "" if ratio["distinguishable"] else " (not distinguishable)")
    overlap = ratio["min"] <= 1.0 <= ratio["max"]
    return "%s: %s the time%s" % (runner["label"], fmt_ratio((ratio["median"], ratio["min"], ratio["max"])),
                                  " (not distinguishable)" if overlap else "")


def answer_cells(answer, measure):
    """The cells after backend and heightfield, and whether the first (the setting) is a choice."""
    if answer.get("choice"):
        return pick_cells(answer["choice"], measure) + [runner_up_text(answer), answer_notes(answer)], True
    closest = answer.get("closest")
    what = "none of %d meets the target" % answer.get("settings", 0)
    if closest:
        return [what + "; nearest: " + closest["label"]] + pick_cells(closest, measure)[1:] + ["-", answer_notes(answer)], False
    return [what] + ["-"] * 8 + [answer_notes(answer)], False


def recommendation_rows(recommendation):
    """[{"cells", "every" (the one setting for every heightfield), "chosen" (the setting is a
    choice, not the nearest miss), "id" (the row a reader opens: the pick's first, or None)}]."""
    measure = recommendation["target"]["measure"]
    out = []
    for b in recommendation["backends"]:
        for answer in [b["all_heightfields"]] + b["per_heightfield"]:
            every = answer is b["all_heightfields"]
            cells, chosen = answer_cells(answer, measure)
            pick = answer.get("choice") or answer.get("closest")
            out.append({"cells": [b["name"], "every heightfield" if every else answer["heightfield"]] + cells,
                        "every": every, "chosen": chosen, "id": pick["rows"][0]["id"] if pick else None})
    return out


def recommendation_intro(recommendation, run):
    """The sentence above the table, before its links."""
    target = recommendation["target"]
    return ("The fastest configuration by measured time per ray (median (min-max) of the repetitions) at each backend, "
            "among those with %s, on all heightfields as one setting (a shader runs one setting for every material) "
            "and on each. Chosen over the window %s and checked on its held-out set %s: a setting meets the target only "
            "where its held-out figures do too (95%% intervals beside them). Errors are the worst of the setting's "
            "heightfields; preprocessing (cone map, min-depth pyramid) is built once per depth map and amortised over "
            "%d frames; it is not in the time per ray. \"Not distinguishable\": the next fastest's time ratio spans 1 "
            "over the repetitions, so the two are equally fast as measured; a near miss is the fastest setting that "
            "misses a bound by less than 20%%." % (target["description"], run.window or "?",
                                                    run.held_out_window or "(none measured)", target["frames"]))


def varies(groups):
    """Whether the wrong-surface rate differs between groups beyond their intervals."""
    intervals = [g["wrong_surface_ci"] for g in groups if g.get("rays")]
    return len(intervals) > 1 and max(lo for lo, _ in intervals) > min(hi for _, hi in intervals)


def breakdown_lines(run, recommendation):
    """Where a choice's wrong-surface rate varies over the window beyond its intervals, by azimuth
    sector of V or band of view angles, at the first backend: its range and the worst group."""
    lines = []
    for b in recommendation["backends"][:1]:
        for a in b["per_heightfield"]:
            if not a.get("choice"):
                continue
            errors = (run.by_id.get(a["choice"]["rows"][0]["id"]) or {}).get("errors") or {}
            for key, what in (("by_azimuth", "azimuth of V"), ("by_view_angle", "view angle")):
                groups = errors.get(key) or []
                if not varies(groups):
                    continue
                worst = max(groups, key=lambda g: g["wrong_surface_rate"])
                lines.append("%s, %s (%s): wrong surface %s to %s by %s; the worst %g to %g degrees (p99 %.3g)" % (
                    a["heightfield"], a["choice"]["label"], b["name"],
                    fmt(min(g["wrong_surface_rate"] for g in groups), 2, 100, "%"),
                    fmt(worst["wrong_surface_rate"], 2, 100, "%"), what, worst["from"], worst["to"], worst["uv_error_p99"]))
    return lines


# ---------------------------------------------------------------------------------------------
# Warnings and alerts

def noisy_rows(run):
    """(relative spread, row) of the timed rows spread beyond SPREAD_LIMIT, worst first."""
    noisy = sorted(((relative_spread(spread(rays_rounds(r))), r) for r in run.timed), key=lambda x: -x[0])
    return [(s, r) for s, r in noisy if s > SPREAD_LIMIT]


def warnings(run, faults):
    """[(headline, text)]: a busy machine (first), disturbed timings, roofline and ceiling faults."""
    out = []
    load = run.load
    if load.get("busy"):
        out.append(("Warning: the machine was busy during this run",
                    "(%s). Load averages before %s, after %s; other processes used %s of the CPU time while timing. "
                    "Speeds and ratios may be disturbed; errors and samples per ray are deterministic and unaffected." % (
                        "; ".join(load.get("busy_reasons") or ["no reason given"]), load_averages(load.get("before")),
                        load_averages(load.get("after")), fmt(load.get("other_cpu_share"), 1, 100, "%"))))
    noisy = noisy_rows(run)
    if noisy:
        out.append(("Warning: %d of %d timed rows spread by more than %d%%" % (len(noisy), len(run.timed),
                                                                            100 * SPREAD_LIMIT),
                    "((max-min)/median of rays/s); the worst: %s." % "; ".join(
                        "%s (%.0f%%)" % (run.describe(r), 100 * s) for s, r in noisy[:5])))
    if faults:
        out.append(("Warning: %s above 100%%" % counted(len(faults), "roofline or ceiling fraction"),
                    ": timing disturbed, see the measurement faults under %s-%s in tables.md (Every backend)." % (
                        HEADLINE_TECHNIQUE.upper(), HEADLINE_LAYERS)))
    return out


def alerts_summary(alerts):
    """The alerts' sentence: how many in how many series, or why there are none."""
    if alerts is None:
        return ("No alerts.json: this run was not recorded into the history (a quick run without --record, or --out), "
                "so it was not compared with earlier runs.")
    found, tested = alerts.get("alerts") or [], alerts.get("series_tested", 0)
    rule = "Rule: %s. Machine: %s." % (alerts.get("rule", "?"), alerts.get("machine", "?"))
    if not found and tested == 0:  # the machine's first recorded run, or too few before it
        return "No series tested: this machine has too few earlier recorded runs to test against yet. " + rule
    if not found:
        return "No change beyond noise in %d series. %s" % (tested, rule)
    return "%s in %d series of this machine's history. %s" % (counted(len(found), "alert"), tested, rule)


# ---------------------------------------------------------------------------------------------
# The filters compared (docs/conventions.md#filters)

FILTER_DOCS = ("conventions.md", "filters")


def filters_title(run, pairs):
    return "%s against %s filtering" % (run.filter.capitalize(), pairs[0][1]["filter"])


def filters_intro(run, pairs):
    return ("The technique x layers matrix at %s read both ways: %s (this run's figures) and %s (accuracy only), each "
            "against the same exact level-0 surface. Bilinear is the search's own error; trilinear is what a player sees "
            "from a mipmapped depth map (the mip chain at each ray's level of detail). p99 in texels."
            % (run.best_isa, run.filter, pairs[0][1]["filter"]))


def filter_table(run, pairs):
    """Per configuration of the matrix measured under the other filter too (there are two): its errors
    and cost under both, as text cells ([(title, numeric)], rows)."""
    other = pairs[0][1]["filter"]
    columns = [("heightfield", False), ("technique", False), ("layers", False)] + [
        ("%s %s" % (title, f), True) for title in ("p99", "wrong surface", "samples/ray") for f in (run.filter, other)]
    rows = []
    for own, theirs in pairs:
        e, o = own.get("errors") or {}, theirs.get("errors") or {}
        rows.append([own["heightfield"]["label"], own["technique"], own["layers"],
                     fmt_error(e.get("uv_error_p99")), fmt_error(o.get("uv_error_p99")),
                     fmt(e.get("wrong_surface_rate"), 2, 100, "%"), fmt(o.get("wrong_surface_rate"), 2, 100, "%"),
                     fmt(own.get("samples_per_ray"), 2), fmt(theirs.get("samples_per_ray"), 2)])
    return columns, rows
