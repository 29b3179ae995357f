"""What report.md (report.py) and report.html (report_page.py) both say, as plain text made once:
the figures' text (a median with its spread, a ratio, an error), the recommendation's table with
its human column names and the "(not distinguishable)" caveat, the warnings (the busy machine
first), the alerts' summary. Each format renders it with its own escaping rule (escape.markdown,
escape.html or the page's textContent), so the two cannot drift apart.
"""
import math
import statistics

from .measurements import (HEADLINE_LAYERS, HEADLINE_TECHNIQUE, counted, rays_rounds, samples_rounds, walks_per_isa,
                           wrong_ci_name)
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

# An answer whose filter's bias alone misses the target (recommendation.hpp's filter_dominated).
FILTER_DOMINATED = "filter-dominated: more layers do not change what a player sees here"
FILTER_DOMINATED_SHORT = "filter-dominated"

def target_words(target):
    """('pixel', 'wrong pixel') or ('texel', 'wrong surface'): how a target's unit and wrong rate read."""
    return ("pixel", "wrong pixel") if target.get("unit") == "pixels" else ("texel", "wrong surface")


def recommendation_columns(target):
    """[(title, numeric)]: the table's columns, in words."""
    short = target["measure"].rsplit("_", 1)[-1]
    unit, wrong = target_words(target)
    return [("backend", False), ("heightfield", False), ("configuration", False), ("time per ray (ns)", True),
            ("held-out %s search error (%ss, 95%% interval)" % (short, unit), True), ("held-out %s" % wrong, True),
            ("window: %s search error; %s" % (short, wrong), True),
            ("filter bias: %s; %s" % (short, wrong), True), ("samples per ray", True), ("preprocessing", False),
            ("next fastest", False), ("notes", False)]


def fmt_interval(value, interval, scale=1.0, unit=""):
    """'0.43 (0.41-0.45)', '0.38% (0.33-0.42%)'; the figure alone without an interval."""
    if value is None:
        return "-"
    if not interval:
        return "%.3g%s" % (value * scale, unit)
    return "%.3g%s (%.3g-%.3g%s)" % (value * scale, unit, interval[0] * scale, interval[1] * scale, unit)


def worst_figures(rows, target, key):
    """A pick's worst rows on one view set ('selection', or 'held_out'; format 1 rows carry the
    window's figures on the row itself) as text: (the measure, the wrong rate), each with its
    interval; None where a row was not measured there."""
    measure, wrong = target["measure"], target["wrong_measure"]
    sets = [r.get(key) if key in r else (r if key == "selection" else None) for r in rows]
    if any(f is None for f in sets):
        return None
    worst = max(sets, key=lambda f: f[measure])
    worst_wrong = max(sets, key=lambda f: f[wrong])
    return (fmt_interval(worst[measure], worst.get(measure + "_ci")),
            fmt_interval(worst_wrong[wrong], worst_wrong.get(wrong_ci_name(wrong)), 100, "%"))


def bias_figures(rows, target):
    """The filter's bias of a pick's worst row on the window (format 3), or '-' (bilinear: none)."""
    measure, wrong = target.get("bias_measure"), target.get("bias_wrong_measure")
    sets = [r.get("selection") or {} for r in rows]
    if not measure or not all(measure in f for f in sets) or all(f[measure] == 0 and f[wrong] == 0 for f in sets):
        return "-"
    worst = max(sets, key=lambda f: f[measure])
    return "%s; %s" % (fmt_interval(worst[measure], None), fmt(max(f[wrong] for f in sets), 2, 100, "%"))


def pick_cells(pick, target):
    """A recommendation's pick as cells: setting, time, its rows' worst figures on the held-out set and
    on the window, the filter's bias, samples, preprocessing."""
    rows = pick["rows"]
    precompute = [r for r in rows if r.get("precompute_seconds") is not None]
    pre = "-"
    if precompute:
        worst = max(precompute, key=lambda r: r["precompute_seconds"])
        pre = "%.3g s once (%.3g ms a frame)" % (worst["precompute_seconds"], worst.get("precompute_ms_per_frame") or 0)
    ns = pick["ns_per_ray"]
    held_out = worst_figures(rows, target, "held_out") or ("not measured", "not measured")
    return [pick["label"], fmt_spread((ns["median"], ns["min"], ns["max"]), 2), held_out[0], held_out[1],
            "; ".join(worst_figures(rows, target, "selection")), bias_figures(rows, target),
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
    if answer.get("filter_dominated"):
        notes.append(FILTER_DOMINATED)
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


def answer_cells(answer, target):
    """The cells after backend and heightfield, and whether the first (the setting) is a choice."""
    if answer.get("choice"):
        return pick_cells(answer["choice"], target) + [runner_up_text(answer), answer_notes(answer)], True
    closest = answer.get("closest")
    what = "none of %d meets the target" % answer.get("settings", 0)
    if closest:
        return [what + "; nearest: " + closest["label"]] + pick_cells(closest, target)[1:] + ["-", answer_notes(answer)], False
    return [what] + ["-"] * 9 + [answer_notes(answer)], False


def recommendation_rows(recommendation):
    """[{"cells", "every" (the one setting for every heightfield), "chosen" (the setting is a
    choice, not the nearest miss), "id" (the row a reader opens: the pick's first, or None)}]."""
    target = recommendation["target"]
    out = []
    for b in recommendation["backends"]:
        for answer in [b["all_heightfields"]] + b["per_heightfield"]:
            every = answer is b["all_heightfields"]
            cells, chosen = answer_cells(answer, target)
            pick = answer.get("choice") or answer.get("closest")
            out.append({"cells": [b["name"], "every heightfield" if every else answer["heightfield"]] + cells,
                        "every": every, "chosen": chosen, "id": pick["rows"][0]["id"] if pick else None})
    return out


def recommendation_intro(recommendation, run):
    """The sentence above the table, before its links."""
    target = recommendation["target"]
    unit, wrong = target_words(target)
    return ("The fastest configuration by measured time per ray (median (min-max) of the repetitions) at each backend "
            "and filter, among those with %s: the search error, each ray's hit against the exact hit on the surface "
            "it reads (level 0 under bilinear, the blend of two mip levels at its level of detail under trilinear), in "
            "%ss; on all heightfields as one setting (a shader runs one setting for every material) and on each. "
            "Under trilinear the filter's bias (the surface read's exact hit from level 0's: what mipmapping costs, "
            "which no layer count changes) stands beside it; \"%s\" marks an answer whose bias alone misses the "
            "target. Chosen over the window %s and checked on its held-out set %s: a setting meets the target only "
            "where its held-out figures do too (95%% intervals beside them). Errors are the worst of the setting's "
            "heightfields; preprocessing (cone map, min-depth pyramid) is built once per depth map and amortised over "
            "%d frames; it is not in the time per ray. \"Not distinguishable\": the next fastest's time ratio spans 1 "
            "over the repetitions, so the two are equally fast as measured; a near miss is the fastest setting that "
            "misses a bound by less than 20%%." % (target["description"], unit, FILTER_DOMINATED_SHORT,
                                                    run.window or "?", run.held_out_window or "(none measured)",
                                                    target["frames"]))


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


def filters_intro(run, pairs, target=None):
    unit = filter_unit(pairs, target)
    return ("The technique x layers matrix at %s read both ways, %s (this run's own) and %s, each row at the %s "
            "percentile of %s: the search error (each ray's hit against the exact hit on the surface it reads: level 0 "
            "under bilinear, the blend of two mip levels at its level of detail under trilinear: what layers buy), the "
            "filter's bias (the surface read's exact hit from level 0's: what mipmapping costs, 0 under bilinear and "
            "for maxmip, which reads level 0), and the error against level 0 the player sees (the two as vectors "
            "added). %s"
            % (run.best_isa, run.filter, pairs[0][1]["filter"], (target or {}).get("measure", "_p99").rsplit("_", 1)[-1],
               unit, ("Filter-dominated: the bias alone misses the target (%s) and is at least the search error: more "
                      "layers do not change what a player sees there." % target["description"]) if target else ""))


def filter_unit(pairs, target):
    """The unit the table reads in: the target's, else pixels where the rows have them, else texels."""
    if target:
        return target.get("unit", "texels")
    e = pairs[0][0].get("errors") or {}
    return "pixels" if e.get("search_pixel_error_p99") is not None else "texels"


def filter_table(run, pairs, target=None):
    """Per configuration of the matrix measured under the other filter too (there are two): its search
    error, the filter's bias, the error against level 0 and the wrong rate under both, in the target's
    unit, whether the trilinear row is filter-dominated, and the cost, as text cells ([(title, numeric)], rows)."""
    other = pairs[0][1]["filter"]
    unit = filter_unit(pairs, target)
    p = (target or {}).get("measure", "_p99").rsplit("_", 1)[-1]
    names = {"texels": ("search_error", "filter_bias", "uv_error", "search_wrong_surface_rate", "wrong surface"),
             "pixels": ("search_pixel_error", "filter_pixel_bias", "pixel_error", "search_wrong_pixel_rate",
                        "wrong pixel")}[unit]
    search, bias, total, wrong, wrong_words = names
    columns = [("heightfield", False), ("technique", False), ("layers", False)] + [
        ("%s %s" % (title, f), True) for f in (run.filter, other)
        for title in ("search %s (%s)" % (p, unit), "filter bias %s" % p, "%s against level 0" % p,
                      "search %s" % wrong_words)] + [("samples/ray %s" % f, True) for f in (run.filter, other)]
    if target:
        columns.append(("filter-dominated", False))
    rows = []
    for own, theirs in pairs:
        cells = [own["heightfield"]["label"], own["technique"], own["layers"]]
        dominated = "-"
        for row in (own, theirs):
            e = row.get("errors") or {}
            # A run before the search error (format 2): level 0's is every filter's reference.
            s, b, t = e.get("%s_%s" % (search, p)), e.get("%s_%s" % (bias, p)), e.get("%s_%s" % (total, p))
            cells += [fmt_error(s), fmt_error(b), fmt_error(t), fmt(e.get(wrong), 2, 100, "%")]
            if target and row.get("filter") == "trilinear" and None not in (s, b):
                misses = b > target["max_error"] or (e.get(bias_wrong_name(bias)) or 0) > target["max_wrong_rate"]
                dominated = "yes" if misses and b >= s else "no"
        cells += [fmt(own.get("samples_per_ray"), 2), fmt(theirs.get("samples_per_ray"), 2)]
        rows.append(cells + ([dominated] if target else []))
    return columns, rows


def bias_wrong_name(bias):
    """The filter's wrong rate of its bias distribution (metrics.hpp): filter_bias -> filter_wrong_surface_rate."""
    return "filter_wrong_pixel_rate" if bias == "filter_pixel_bias" else "filter_wrong_surface_rate"
