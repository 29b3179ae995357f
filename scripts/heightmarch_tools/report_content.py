"""What report.md (report.py) and report.html (report_page.py) both say, as plain text made once:
the figures' text (a median with its spread, a ratio, an error), the recommendation's table with
its human column names and the "(not distinguishable)" caveat, the warnings (the busy machine
first), the alerts' summary. Each format renders it with its own escaping rule (escape.markdown,
escape.html or the page's textContent), so the two cannot drift apart.
"""
import math
import statistics

from .measurements import HEADLINE_LAYERS, HEADLINE_TECHNIQUE, counted, rays_rounds
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
# The recommendation's table

def recommendation_columns(measure):
    """[(title, numeric)]: the table's columns, in words."""
    return [("backend", False), ("heightfield", False), ("configuration", False), ("time per ray (ns)", True),
            ("%s uv error (texels)" % measure.replace("uv_error_", ""), True), ("wrong surface", True),
            ("samples per ray", True), ("preprocessing", False), ("next fastest", False)]


def pick_cells(pick, measure):
    """A recommendation's pick as cells: setting, time, its rows' worst error measures, preprocessing."""
    rows = pick["rows"]
    precompute = [r for r in rows if r.get("precompute_seconds") is not None]
    pre = "-"
    if precompute:
        worst = max(precompute, key=lambda r: r["precompute_seconds"])
        pre = "%.3g s once (%.3g ms a frame)" % (worst["precompute_seconds"], worst.get("precompute_ms_per_frame") or 0)
    ns = pick["ns_per_ray"]
    return [pick["label"], fmt_spread((ns["median"], ns["min"], ns["max"]), 2), fmt_error(max(r[measure] for r in rows)),
            fmt(max(r["wrong_surface_rate"] for r in rows), 2, 100, "%"),
            "%.1f" % statistics.mean(r["samples_per_ray"] for r in rows), pre]


def answer_cells(answer, measure):
    """The cells after backend and heightfield, and whether the first (the setting) is a choice."""
    if answer.get("choice"):
        cells = pick_cells(answer["choice"], measure)
        runner, ratio = answer.get("runner_up"), answer.get("runner_up_time_ratio")
        if runner and ratio:
            overlap = ratio["min"] <= 1.0 <= ratio["max"]
            cells.append("%s: %s the time%s" % (runner["label"], fmt_ratio((ratio["median"], ratio["min"], ratio["max"])),
                                               " (not distinguishable)" if overlap else ""))
        else:
            cells.append("-")
        return cells, True
    closest = answer.get("closest")
    what = "none of %d meets the target" % answer.get("settings", 0)
    if closest:
        return [what + "; nearest: " + closest["label"]] + pick_cells(closest, measure)[1:] + ["-"], False
    return [what, "-", "-", "-", "-", "-", "-"], False


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


def recommendation_intro(recommendation):
    """The sentence above the table, before its links."""
    target = recommendation["target"]
    return ("The fastest configuration by measured time per ray (median (min-max) of the repetitions) at each backend, "
            "among those with %s, on all heightfields as one setting (a shader runs one setting for every material) "
            "and on each. Errors are the worst of the setting's heightfields; preprocessing (cone map, min-depth "
            "pyramid) is built once per depth map and amortised over %d frames; it is not in the time per ray. "
            "\"Not distinguishable\": the next fastest's time ratio spans 1 over the repetitions, so the two are equally "
            "fast as measured." % (target["description"], target["frames"]))


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
