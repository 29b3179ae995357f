"""The record across runs: results/history.csv, one row per timed row of every recorded run, and
its plot (the headline configuration at 1 thread over the recorded runs).

scripts/report.py calls record() for a run recorded with --history.
"""
import csv
import io
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from benchmark_results import Unusable, atomic_write, read_json, spread  # noqa: E402

COLUMNS = ["date", "commit", "cpu", "backend", "threads", "heightfield", "technique", "layers",
           "view", "depth_map", "rays_per_second_median", "rays_per_second_min", "rays_per_second_max"]
# The configuration that every backend runs and that the plot follows.
HEADLINE_TECHNIQUE, HEADLINE_LAYERS = "pom", "32"
MARKERS = "osD^vP*Xh"
MAX_PLOT_PIXELS = 1600  # widest plot, so a page shows it whole


def view_name(view):
    name = "%s %dx%d" % (view["kind"], view["width"], view["height"])
    if view.get("theta") is not None:
        name += " theta %g phi %g" % (view["theta"], view.get("phi") or 0)
    return name


def depth_map(row):
    return "%dx%d" % (row["heightfield"]["width"], row["heightfield"]["height"])


def backend(row):
    """The backend as history tells rows apart: 'avx2', or 'avx2-autovec' for the auto-vectorised port."""
    return row["backend"] + ("-autovec" if row["kind"] == "autovec" else "")


def rows_of_run(data):
    """One history row per timed row of a run's measurements.json."""
    p = data["provenance"]
    out = []
    for r in data["rows"]:
        if not r.get("speed"):
            continue
        s = spread(r["speed"]["rays_per_second"]["rounds"])
        out.append({"date": p.get("date", ""), "commit": p.get("commit", ""), "cpu": p.get("cpu", ""),
                    "backend": backend(r), "threads": str(r["threads"]), "heightfield": r["heightfield"]["label"],
                    # rows without a technique (roofline, exact) are named by their kind
                    "technique": r.get("technique") or r["kind"], "layers": r.get("layers") or "",
                    "view": view_name(r["view"]), "depth_map": depth_map(r),
                    "rays_per_second_median": "%.6g" % s[0], "rays_per_second_min": "%.6g" % s[1],
                    "rays_per_second_max": "%.6g" % s[2]})
    return out


def read(path):
    """The history's rows ([] where the file does not exist yet)."""
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        if reader.fieldnames != COLUMNS:
            raise Unusable("%s: columns are not %s" % (path, ",".join(COLUMNS)))
        return list(reader)


def append(path, data):
    """Appends a run's rows (replacing an earlier record of the same date and commit); all rows."""
    date, commit = data["provenance"].get("date", ""), data["provenance"].get("commit", "")
    rows = [r for r in read(path) if (r["date"], r["commit"]) != (date, commit)] + rows_of_run(data)
    out = io.StringIO()
    writer = csv.DictWriter(out, COLUMNS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    atomic_write(path, out.getvalue())
    return rows


def plot(data, rows, path):
    """The headline configuration at 1 thread over the recorded runs, one line per backend."""
    headline = [r for r in data["rows"] if r.get("speed") and r.get("technique") == HEADLINE_TECHNIQUE
                and r.get("layers") == HEADLINE_LAYERS and r["threads"] == 1 and r["view"]["kind"] == "default"]
    hf = headline[0]["heightfield"]["label"] if headline else (data["rows"] or [{"heightfield": {"label": ""}}])[0]["heightfield"]["label"]
    view = view_name(headline[0]["view"]) if headline else "default"
    picked = [r for r in rows if r["technique"] == HEADLINE_TECHNIQUE and r["layers"] == HEADLINE_LAYERS
              and r["threads"] == "1" and r["heightfield"] == hf and r["view"].startswith(view)
              and (not headline or r["depth_map"] == depth_map(headline[0]))]
    if not picked:
        return False
    runs = sorted({(r["date"], r["commit"]) for r in picked})
    by_backend = {}
    for r in picked:
        by_backend.setdefault(r["backend"], []).append(r)
    names = list(dict.fromkeys(list(data["backends"]) + list(by_backend)))
    cmap = plt.get_cmap("tab10")
    colors = {b: cmap(i % 10) for i, b in enumerate(names)}
    fig, ax = plt.subplots(figsize=(max(7.0, 0.9 * len(runs) + 3), 4.2))
    for name in [b for b in colors if b in by_backend]:
        pts = sorted((runs.index((r["date"], r["commit"])), [float(r[c]) / 1e6 for c in COLUMNS[-3:]])
                     for r in by_backend[name])
        ax.errorbar([x for x, _ in pts], [v[0] for _, v in pts], yerr=[[v[0] - v[1] for _, v in pts], [v[2] - v[0] for _, v in pts]],
                    marker=MARKERS[list(colors).index(name) % len(MARKERS)], markersize=4, capsize=3,
                    color=colors[name], label=name)
    ax.set_xticks(range(len(runs)))
    ax.set_xticklabels(["%s\n%s" % (d[:16].replace("T", " "), c) for d, c in runs], fontsize=7)
    ax.set_yscale("log")
    ax.set_ylabel("Mrays/s, median (bars: min-max)")
    ax.grid(True, which="both", alpha=0.3)
    fig.suptitle("%s, %s layers, %s view, %s, 1 thread, over the recorded runs" % (
        HEADLINE_TECHNIQUE.upper(), HEADLINE_LAYERS, view, hf), fontsize=10)
    fig.legend(*ax.get_legend_handles_labels(), loc="lower center", ncol=min(len(by_backend), 6), fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.1, 1, 0.95))
    fig.savefig(path, dpi=min(130, MAX_PLOT_PIXELS / fig.get_figwidth()))
    plt.close(fig)
    return True


def record(run_dir, history_path):
    """Appends the run in run_dir to the history and draws run_dir/plots/history.png; whether the
    plot was drawn (the headline configuration may be missing from the run)."""
    data = read_json(os.path.join(run_dir, "measurements.json"))
    rows = append(history_path, data)
    os.makedirs(os.path.join(run_dir, "plots"), exist_ok=True)
    return plot(data, rows, os.path.join(run_dir, "plots", "history.png"))
