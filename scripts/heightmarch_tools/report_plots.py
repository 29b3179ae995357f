"""The report's plots (RUN_DIR/plots/*.png), drawn with matplotlib from a run's rows: error against
time per ray at the recommendation's backend, error against layers, error against view angle and
the speed-up per ISA. Errors are drawn on a symlog axis, so an exact 0 is drawn at 0. The history
plot is history_plot.py's. report.py calls them.
"""
import io
import math
import statistics

import matplotlib

matplotlib.use("Agg")
# Text is text: a '$' in a map's name is no mathtext (which would fail to parse, or typeset it).
# Names enter a plot through terminal() (no control character), the rule for plot text.
matplotlib.rcParams["text.parse_math"] = False
import matplotlib.pyplot as plt  # noqa: E402
from PIL import Image  # noqa: E402  (matplotlib's own dependency)
from matplotlib.ticker import FixedLocator, FuncFormatter, NullLocator  # noqa: E402

from .measurements import (HEADLINE_LAYERS, HEADLINE_TECHNIQUE, backend_colours, counted, depth_map,  # noqa: E402
                          groups, ns_per_ray_rounds, speedup)
from .escape import terminal  # noqa: E402
from .spreads import spread  # noqa: E402
from .writers import atomic_write  # noqa: E402

MAX_PLOT_PIXELS = 1600  # widest plot, so a page shows it whole
# Errors below this many texels are drawn on the linear part of a symlog axis: zero shows as 0.
ZERO_BAND = 1e-3


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
    per_row = max(1, int(fig.get_figwidth() / 1.6))  # legend entries are about 1.6 inches wide
    legend_rows = (len(handles) + per_row - 1) // per_row or 1
    ncol = (len(handles) + legend_rows - 1) // legend_rows or 1
    bottom = 0.02 + 0.035 * legend_rows * 4.0 / fig.get_figheight()
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=ncol, fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, bottom, 1, 0.95))
    save(fig, path)


def save(fig, path):
    """The figure as a PNG at most MAX_PLOT_PIXELS wide, of 256 colours (a third of the full-colour
    file: a committed run's budget, docs/measurements.md), written whole (writers.atomic_write: never
    through a link planted at path, never half a file on a full disk), and closed."""
    png = io.BytesIO()
    fig.savefig(png, format="png", dpi=min(130, MAX_PLOT_PIXELS / fig.get_figwidth()))
    plt.close(fig)
    png.seek(0)
    palette = io.BytesIO()
    Image.open(png).convert("RGB").quantize(256, method=Image.Quantize.MEDIANCUT).save(palette, "PNG", optimize=True)
    atomic_write(path, palette.getvalue())


def plain(v, _=None):
    """A tick label: plain numbers at 1, 2 and 5 per decade (0.1, 2, 50), empty elsewhere."""
    if v == 0:
        return "0"
    return "%g" % v if v > 0 and round(v / 10 ** math.floor(math.log10(v) + 1e-9)) in (1, 2, 5) else ""


def log_axis(ax, axis="x", ticks=None):
    """A log axis labelled with plain numbers; with ticks, labelled at those values alone (layer counts)."""
    (ax.set_xscale if axis == "x" else ax.set_yscale)("log")
    a = ax.xaxis if axis == "x" else ax.yaxis
    a.set_major_formatter(FuncFormatter(plain))
    a.set_minor_formatter(FuncFormatter(plain))
    if ticks:
        a.set_major_locator(FixedLocator(ticks))
        a.set_major_formatter(FuncFormatter(lambda v, _: "%g" % v))
        a.set_minor_formatter(FuncFormatter(lambda v, _: ""))


def error_axis(ax, values, label):
    """The error axis: log above ZERO_BAND, linear below it (symlog), so an exact 0 is drawn at 0 and
    labelled 0, never as a made-up 1e-4; the linear band is shaded and named."""
    top = max([v for v in values if v is not None] + [1.0])
    ax.set_yscale("symlog", linthresh=ZERO_BAND, linscale=0.6)
    decades = [0.0] + [10.0 ** k for k in range(int(math.log10(ZERO_BAND)), int(math.ceil(math.log10(top))) + 1)]
    ax.yaxis.set_major_locator(FixedLocator(decades))
    ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: plain(v) or "%g" % v))
    ax.yaxis.set_minor_locator(NullLocator())
    ax.set_ylim(-ZERO_BAND * 0.15, top * 1.6)
    ax.axhspan(-ZERO_BAND * 0.15, ZERO_BAND, color="0.93", zorder=0)
    if label:
        ax.set_ylabel(label + "\n(shaded: below %g texel, linear to 0)" % ZERO_BAND, fontsize=8)


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
            errors = [(r["min_layers"], r["errors"]["uv_error_mean"]) for r in group
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
        log_axis(ax, "x", sorted({x for name, errors in series.items() for x, _ in errors
                                  if run.style[name.split(" = ")[0]]["layered"]}))
        error_axis(ax, [y for errors in series.values() for _, y in errors], "mean uv error (texels)")
        ax.set_title("%s (%s)" % (terminal(hf), depth_map(rows[0])), fontsize=9)
        ax.set_xlabel("layers")
        ax.grid(True, which="both", alpha=0.3)
    finish(fig, path, "Error against layer count (default view; dashed: techniques without a layer count, "
                      "one sample or maxmip's pyramid walk)", axes)
    return True


def plot_error_vs_angle(run, path):
    """A panel per heightfield and layer spec, a line per technique in the registry's colours."""
    rows = [r for r in run.with_purpose("sweep") if r["view"]["kind"] == "sweep" and r.get("errors") and r.get("technique")]
    if not rows:
        return False
    heightfields = list(groups(sorted(rows, key=run.order), lambda r: r["heightfield"]["label"]))
    specs = list(dict.fromkeys(r["layers"] for r in sorted(rows, key=run.order)
                               if run.style[r["technique"]]["layered"])) or ["1"]
    phis = sorted({r["view"].get("phi") or 0 for r in rows})
    fig, grid = plt.subplots(len(heightfields), len(specs), figsize=(max(3.4 * len(specs), 7.0), 2.6 * len(heightfields) + 1.2),
                             squeeze=False)
    axes = [ax for line in grid for ax in line]
    for i, hf in enumerate(heightfields):
        for j, spec in enumerate(specs):
            ax = grid[i][j]
            panel = [r for r in rows if r["heightfield"]["label"] == hf
                     and (r["layers"] == spec or not run.style[r["technique"]]["layered"])]
            values = []
            for technique, t_rows in groups(sorted(panel, key=run.order), lambda r: r["technique"]).items():
                # mean over the azimuths measured at each angle
                by_theta = groups(t_rows, lambda r: r["view"]["theta"])
                thetas = sorted(by_theta)
                errors = [statistics.mean(r["errors"]["uv_error_mean"] for r in by_theta[t]) for t in thetas]
                values += errors
                ax.plot(thetas, errors, markersize=3, linewidth=1, label=technique,
                        linestyle="-" if run.style[technique]["layered"] else "--", **technique_kw(run, technique))
            error_axis(ax, values, "mean uv error (texels)" if j == 0 else "")
            ax.set_title("%s, %s layers" % (terminal(hf), terminal(spec)), fontsize=8)
            ax.set_xlabel("view angle from the normal (degrees)" if i == len(heightfields) - 1 else "", fontsize=8)
            ax.tick_params(labelsize=7)
            ax.grid(True, which="both", alpha=0.3)
    azimuth = "azimuth %g deg" % phis[0] if len(phis) == 1 else "mean over azimuths %s deg" % ", ".join("%g" % p for p in phis)
    finish(fig, path, "Error against view angle (sweep views, %s; dashed: techniques without a layer count, the same "
                      "in every column)" % azimuth, axes)
    return True


def plot_error_vs_speed(run, recommendation, path):
    """The frontier of the recommendation's backend: time per ray against its error measure, per
    heightfield; filled markers meet the wrong-surface bound, hollow ones do not; rings: the choice."""
    if not recommendation or not recommendation["backends"]:
        return False
    target, backend = recommendation["target"], recommendation["backends"][0]
    measure = target["measure"]
    chosen = {a["heightfield"]: a["choice"]["rows"][0]["id"] for a in backend["per_heightfield"] if a.get("choice")}
    everywhere = {r["id"] for r in (backend["all_heightfields"].get("choice") or {}).get("rows", [])}
    rows = [r for r in run.rows if r.get("speed") and r.get("errors") and r.get("technique") in run.style
            and r["kind"] in ("trace", "glsl") and r["backend"] == backend["backend"] and r["threads"] == backend["threads"]
            and r["view"]["kind"] == "default" and not r.get("failure")
            and r["heightfield"]["label"] in {a["heightfield"] for a in backend["per_heightfield"]}
            and (r.get("filter") or "bilinear") == backend.get("filter", "bilinear")
            and set(r["purposes"]) & {"matrix", "filters", "claims", "glsl"}]
    by_hf = groups(sorted(rows, key=run.order), lambda r: r["heightfield"]["label"])
    if not by_hf:
        return False
    fig, axes = panel_grid(len(by_hf), 4.6, 3.8)
    for ax, (hf, hf_rows) in zip(axes, by_hf.items()):
        for technique, group in groups(hf_rows, lambda r: r["technique"]).items():
            group = sorted(group, key=lambda r: (r["min_layers"] != r["max_layers"], r["max_layers"] or 0))
            times = [spread(ns_per_ray_rounds(r)) for r in group]
            ys = [r["errors"][measure] for r in group]
            style = technique_kw(run, technique)
            fixed = [(t[0], y) for r, t, y in zip(group, times, ys) if r["min_layers"] == r["max_layers"]]
            if len(fixed) > 1:  # a technique's fixed layer counts as one curve, fewest layers first
                ax.plot([x for x, _ in fixed], [y for _, y in fixed], color=style["color"], linewidth=0.7, alpha=0.6)
            for r, t, y in zip(group, times, ys):
                ok = r["errors"][target["wrong_measure"]] <= target["max_wrong_rate"]
                ax.errorbar([t[0]], [y], xerr=[[t[0] - t[1]], [t[2] - t[0]]], linestyle="none", markersize=5,
                            elinewidth=0.7, color=style["color"], marker=style["marker"],
                            markerfacecolor=style["color"] if ok else "white", label=technique)
                if r["id"] in (chosen.get(hf), ) or r["id"] in everywhere:
                    ax.plot([t[0]], [y], linestyle="none", marker="o", markersize=15, markerfacecolor="none",
                            markeredgecolor="black", markeredgewidth=1.3 if r["id"] == chosen.get(hf) else 0.8,
                            label="recommended here (ring) / for every heightfield (thin ring)")
                    ax.annotate(terminal(run.label(r)), (t[0], y), xytext=(9, 7), textcoords="offset points", fontsize=7,
                                fontweight="bold")
        ax.axhline(target["max_error"], color="black", linestyle="--", linewidth=0.8,
                   label="target: %s" % terminal(target["description"]))
        log_axis(ax, "x")
        error_axis(ax, [r["errors"][measure] for r in hf_rows], "%s %s error (%s)" % (
            measure.rsplit("_", 1)[-1], "uv" if measure.startswith("uv_") else "search", target.get("unit", "texels")))
        ax.set_title("%s (%s)" % (terminal(hf), depth_map(hf_rows[0])), fontsize=9)
        ax.set_xlabel("ns per ray at %s, median (bars: min-max)" % terminal(backend["name"]), fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
        ax.plot([], [], linestyle="none", marker="o", markerfacecolor="white", color="gray",
                label="hollow: %s above %g%%" % ("wrong pixel" if target.get("unit") == "pixels" else "wrong surface",
                                                  100 * target["max_wrong_rate"]))
    finish(fig, path, "Error against time per ray at %s (the recommendation's backend; lines join a technique's fixed "
                      "layer counts)" % terminal(backend["name"]), axes)
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
    colours = backend_colours(run.backend_names())
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
            ax.bar(xs, ys, width, color=colours[isa], label=isa,
                   yerr=[[s[0] - s[1] for _, s in mine], [s[2] - s[0] for _, s in mine]], capsize=2, error_kw={"linewidth": 0.8})
            for x, (_, s) in zip(xs, mine):
                ax.text(x, s[2], "%.1f" % s[0], ha="center", va="bottom", fontsize=6)
        ax.axhline(1.0, color="gray", linewidth=1)
        ax.set_xticks(range(len(by_group)))
        ax.set_xticklabels([terminal(g) for g in by_group], fontsize=7)
        ax.set_ylabel("rays/s over %s" % ("the naive port" if ref == "naive" else ref))
    finish(fig, path, "%s-%s speed-up per ISA: median of per-round ratios (bars: min-max)" % (
        HEADLINE_TECHNIQUE.upper(), HEADLINE_LAYERS), axes)
    return True
