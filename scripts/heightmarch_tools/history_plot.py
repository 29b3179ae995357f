"""The history plot: the headline configuration (POM-32, 1 thread, the run's first heightfield and
default view) over the recorded runs, one panel per machine, a line per backend."""
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FuncFormatter  # noqa: E402

from . import history  # noqa: E402
from .escape import terminal  # noqa: E402
from .measurements import HEADLINE_LAYERS, HEADLINE_TECHNIQUE, backend_colours  # noqa: E402
from .report_plots import save  # noqa: E402  (and its text.parse_math off)

MARKERS = "osD^vP*Xh<>"
MAX_WIDTH_INCHES = 16.0


def style(name, bases, colours):
    """Colour, marker and line of a backend: the report's colour of it (an ISA's auto-vectorised port
    the light shade of its ISA's), its base's marker, dashed and hollow when autovec."""
    base = name[:-len("-autovec")] if name.endswith("-autovec") else name
    autovec = base != name
    return {"color": colours[name], "marker": MARKERS[bases.index(base) % len(MARKERS)],
            "linestyle": "--" if autovec else "-", "markerfacecolor": "none" if autovec else colours[name]}


def plain_log_label(value, _):
    """A log axis labelled 1, 2, 5 per decade in plain numbers (0.5, 20, 100), as the report's plots are."""
    if value <= 0:
        return ""
    return "%g" % value if round(value / 10 ** math.floor(math.log10(value) + 1e-9)) in (1, 2, 5) else ""


def draw(data, rows, path):
    """Draws path; False when no recorded run holds the headline configuration."""
    headline = [r for r in data["rows"] if r.get("speed") and r.get("technique") == HEADLINE_TECHNIQUE
                and r.get("layers") == HEADLINE_LAYERS and r["threads"] == 1 and r["view"]["kind"] == "default"]
    if not headline:
        return False
    want = history.series_fields(headline[0])
    picked = [r for r in rows if r["technique"] == HEADLINE_TECHNIQUE and r["layers"] == HEADLINE_LAYERS
              and r["threads"] == "1" and all(r[k] == want[k] for k in ("heightfield", "view", "depth_map", "filter"))]
    machines = list(dict.fromkeys(r["machine"] for r in sorted(picked, key=lambda r: r["date"])))
    if not machines:
        return False
    runs = {m: sorted({(r["date"], r["commit"]) for r in picked if r["machine"] == m}) for m in machines}
    bases = list(dict.fromkeys(list(data["backends"]) + [r["backend"].replace("-autovec", "") for r in picked]))
    colours = backend_colours(bases + sorted({r["backend"] for r in picked} - set(bases)))
    total = sum(len(v) for v in runs.values())
    width = min(MAX_WIDTH_INCHES, max(7.0, 0.8 * total + 2.2 * len(machines)))
    fig, axes = plt.subplots(1, len(machines), figsize=(width, 4.8), sharey=True, squeeze=False,
                             gridspec_kw={"width_ratios": [max(len(runs[m]), 2) for m in machines]})
    for ax, machine in zip(axes[0], machines):
        mine = [r for r in picked if r["machine"] == machine]
        for name in sorted({r["backend"] for r in mine}, key=lambda b: (bases.index(b.replace("-autovec", "")), b)):
            pts = sorted((runs[machine].index((r["date"], r["commit"])), [float(r[c]) / 1e6 for c in (
                "rays_per_second_median", "rays_per_second_min", "rays_per_second_max")]) for r in mine if r["backend"] == name)
            ax.errorbar([x for x, _ in pts], [v[0] for _, v in pts],
                        yerr=[[v[0] - v[1] for _, v in pts], [v[2] - v[0] for _, v in pts]],
                        markersize=4, capsize=3, label=name, **style(name, bases, colours))
        ax.set_xticks(range(len(runs[machine])))
        ax.set_xticklabels(["%s\n%s" % (terminal(d[5:16].replace("T", " ")), terminal(c[:7])) for d, c in runs[machine]],
                           fontsize=6)
        ax.set_xlim(-0.5, max(len(runs[machine]), 2) - 0.5)
        ax.set_title(machine if history.is_known(machine) else "unknown machine:\n" + machine[len(history.UNKNOWN_PREFIX):],
                     fontsize=7)
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(FuncFormatter(plain_log_label))
        ax.yaxis.set_minor_formatter(FuncFormatter(plain_log_label))
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("Mrays/s, median (bars: min-max)")
    handles = {}
    for ax in axes[0]:
        for h, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, h)
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=min(len(handles), 6), fontsize=7, frameon=False)
    fig.suptitle("%s, %s layers, %s view, %s %s, 1 thread, over the recorded runs: one panel per machine "
                 "(a machine change starts a panel)" % (HEADLINE_TECHNIQUE.upper(), HEADLINE_LAYERS, terminal(want["view"]),
                                                       terminal(want["heightfield"]), want["depth_map"]), fontsize=9)
    legend_rows = (len(handles) + 5) // 6
    fig.tight_layout(rect=(0, 0.04 + 0.05 * legend_rows, 1, 0.94))
    save(fig, path)
    return True
