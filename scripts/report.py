#!/usr/bin/python3
"""Writes RUN_DIR/report.md and RUN_DIR/plots/*.png from a suite run directory.

Usage: scripts/report.py RUN_DIR [--history results/history.csv]

Inputs (written by `heightmarch suite`): bench*.json (Google Benchmark), sweep.csv,
gallery.json, claims.md/claims.json, machine.json. Sections whose inputs are missing say so.
With --history, one row per benchmark of this run is appended to the history CSV, and the
report plots rays/s over the recorded runs.
"""
import argparse
import csv
import glob
import json
import math
import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TECHNIQUES = ["parallax", "parallax-limited", "steep", "steep-limited", "relief", "pom", "shadow"]
ISAS = ["scalar", "sse4.2", "avx2", "avx512"]
LAYER_ORDER = ["1", "4", "8", "10", "16", "32", "64", "8-32"]
HISTORY_COLUMNS = ["date", "commit", "cpu", "isa", "threads", "benchmark", "rays_per_second_median"]


def atomic_write(path, text, mode="w"):
    directory = os.path.dirname(os.path.abspath(path))
    fd, temporary = tempfile.mkstemp(dir=directory, prefix=".tmp-")
    with os.fdopen(fd, mode) as f:
        f.write(text)
    os.replace(temporary, path)


def parse_name(name):
    """'BM_Trace/heightfield:bricks/technique:pom/...' -> ('BM_Trace', {'heightfield': 'bricks', ...})."""
    parts = name.split("/")
    fields = {}
    for part in parts[1:]:
        if ":" in part:
            key, value = part.split(":", 1)
            fields[key] = value
    return parts[0], fields


def load_benchmarks(run_dir):
    """Entries keyed by name without Google Benchmark's suffixes; the median aggregate wins."""
    entries, context = {}, {}
    for path in sorted(glob.glob(os.path.join(run_dir, "bench*.json"))):
        with open(path) as f:
            data = json.load(f)
        context = context or data.get("context", {})
        for b in data.get("benchmarks", []):
            if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
                continue
            kind, fields = parse_name(b.get("run_name", b["name"]))
            key = (kind,) + tuple(sorted((k, v) for k, v in fields.items() if k not in ("min_time", "repeats")))
            if key in entries and b.get("run_type") != "aggregate":
                continue
            entry = dict(b)
            entry["kind"], entry["fields"] = kind, fields
            entries[key] = entry
    return list(entries.values()), context


def select(entries, kind, **fields):
    return [e for e in entries if e["kind"] == kind and all(e["fields"].get(k) == v for k, v in fields.items())]


def one(entries, kind, **fields):
    found = select(entries, kind, **fields)
    return found[0] if found else None


def failed(e):
    return e is not None and e.get("error_occurred")


def mrays(e):
    if e is None:
        return "-"
    if failed(e):
        return "failed"
    return "%.1f" % (e.get("rays_per_second", 0) / 1e6)


def layer_key(layers):
    return LAYER_ORDER.index(layers) if layers in LAYER_ORDER else len(LAYER_ORDER)


def fmt(value, digits=3):
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "-"
    return ("%." + str(digits) + "f") % value


def max_threads(entries):
    threads = [int(e["fields"]["threads"]) for e in entries if "threads" in e["fields"]]
    return str(max(threads)) if threads else "1"


def best_isa(entries, machine):
    if machine.get("best_isa"):
        return machine["best_isa"]
    present = {e["fields"].get("isa") for e in entries if e["kind"] == "BM_Trace"}
    for isa in reversed(ISAS):
        if isa in present:
            return isa
    return "scalar"


def heightfields_of(entries):
    seen = []
    for e in entries:
        hf = e["fields"].get("heightfield")
        if e["kind"] == "BM_Trace" and hf and hf not in seen:
            seen.append(hf)
    return seen


def section_machine(machine, context):
    lines = ["## Machine", ""]
    rows = [("CPU", machine.get("cpu") or context.get("heightmarch_cpu", "?")),
            ("cores", machine.get("cores", context.get("num_cpus", "?"))),
            ("best ISA", machine.get("best_isa") or context.get("heightmarch_best_isa", "?")),
            ("threads", machine.get("threads", "?")),
            ("compiler", machine.get("compiler") or context.get("heightmarch_compiler", "?")),
            ("commit", machine.get("commit") or context.get("heightmarch_commit", "?")),
            ("date", machine.get("date") or context.get("date", "?")),
            ("benchmark view", context.get("heightmarch_view", "?")),
            ("depth maps", context.get("heightmarch_depth_map", "?")),
            ("run", "quick (smoke test)" if machine.get("quick") else "full")]
    lines += ["| | |", "|---|---|"] + ["| %s | %s |" % r for r in rows]
    return lines


def section_accuracy_speed(entries, isa, threads):
    lines = ["## Techniques x layers, per heightfield",
             "",
             "CPU packet kernels at %s, %s threads, the default view. uv errors in texels against the exact "
             "intersection; wrong surface = uv error above 1 texel." % (isa, threads)]
    for hf in heightfields_of(entries):
        rows = select(entries, "BM_Trace", heightfield=hf, isa=isa, threads=threads)
        if not rows:
            continue
        rows.sort(key=lambda e: (TECHNIQUES.index(e["fields"]["technique"]) if e["fields"]["technique"] in TECHNIQUES else 99,
                                 layer_key(e["fields"]["layers"])))
        lines += ["", "### %s" % hf, "",
                  "| technique | layers | Mrays/s | samples/ray | mean | p95 | max | wrong surface |",
                  "|---|---|---:|---:|---:|---:|---:|---:|"]
        for e in rows:
            f = e["fields"]
            if failed(e):
                lines.append("| %s | %s | failed: %s | | | | | |" % (f["technique"], f["layers"], e.get("error_message", "")))
                continue
            lines.append("| %s | %s | %s | %s | %s | %s | %s | %s%% |" % (
                f["technique"], f["layers"], mrays(e), fmt(e.get("samples_per_ray"), 2), fmt(e.get("uv_error_mean")),
                fmt(e.get("uv_error_p95")), fmt(e.get("uv_error_max"), 2), fmt(100 * e.get("wrong_surface_rate", 0), 2)))
    return lines


def section_isa_vs_glsl(entries, isa, threads):
    lines = ["## CPU per ISA against GLSL (OSMesa llvmpipe)", ""]
    glsl = select(entries, "BM_GLSL")
    if not glsl:
        lines.append("GLSL not run.")
    else:
        lines += ["Rays/s (M) at the most threads, the same rays and parameters on both sides; ratio = CPU (%s) / GLSL." % isa, "",
                  "| heightfield | technique | layers | CPU %s | GLSL | CPU/GLSL |" % isa, "|---|---|---|---:|---:|---:|"]
        for g in sorted(glsl, key=lambda e: (e["fields"]["heightfield"], TECHNIQUES.index(e["fields"]["technique"]) if e["fields"]["technique"] in TECHNIQUES else 99, layer_key(e["fields"]["layers"]))):
            f = g["fields"]
            if f["threads"] != threads:
                continue
            c = one(entries, "BM_Trace", heightfield=f["heightfield"], technique=f["technique"], layers=f["layers"], isa=isa, threads=threads)
            ratio = "-"
            if c and not failed(c) and not failed(g) and g.get("rays_per_second"):
                ratio = "%.1fx" % (c["rays_per_second"] / g["rays_per_second"])
            lines.append("| %s | %s | %s | %s | %s | %s |" % (f["heightfield"], f["technique"], f["layers"], mrays(c), mrays(g), ratio))
    lines += ["", "### POM, 32 layers, every backend", "",
              "Roofline = the same ISA's bilinear sampler alone at the same positions; fraction = POM's samples/s over it.", "",
              "| heightfield | backend | threads | Mrays/s | Msamples/s | roofline fraction | vs naive port |",
              "|---|---|---:|---:|---:|---:|---:|"]
    for hf in heightfields_of(entries):
        for t in sorted({e["fields"]["threads"] for e in select(entries, "BM_Trace", heightfield=hf, technique="pom", layers="32")}, key=int):
            naive = one(entries, "BM_NaivePort", heightfield=hf, layers="32", threads=t)
            rows = [("naive port", naive, None)]
            rows += [(i, one(entries, "BM_Trace", heightfield=hf, technique="pom", layers="32", isa=i, threads=t),
                      one(entries, "BM_SamplerRoofline", heightfield=hf, isa=i, threads=t)) for i in ISAS]
            rows.append(("glsl", one(entries, "BM_GLSL", heightfield=hf, technique="pom", layers="32", threads=t), None))
            for name, e, roof in rows:
                if e is None:
                    continue
                fraction = "-"
                if roof and not failed(roof) and not failed(e) and roof.get("samples_per_second"):
                    fraction = "%.0f%%" % (100 * e["samples_per_second"] / roof["samples_per_second"])
                vs_naive = "-"
                if naive and not failed(naive) and not failed(e) and naive.get("rays_per_second"):
                    vs_naive = "%.1fx" % (e["rays_per_second"] / naive["rays_per_second"])
                lines.append("| %s | %s | %s | %s | %s | %s | %s |" % (
                    hf, name, t, mrays(e), "failed" if failed(e) else fmt(e.get("samples_per_second", 0) / 1e6, 0), fraction, vs_naive))
    return lines


def section_threads(entries):
    lines = ["## Thread scaling", "", "| heightfield | backend | 1 thread | N threads | N | speed-up |", "|---|---|---:|---:|---:|---:|"]
    found = False
    for hf in heightfields_of(entries):
        for kind, isa in [("BM_Trace", i) for i in ISAS] + [("BM_GLSL", "glsl"), ("BM_NaivePort", "scalar-naive")]:
            rows = select(entries, kind, heightfield=hf, layers="32", isa=isa)
            rows = [e for e in rows if e["fields"].get("technique") == "pom" and not failed(e)]
            by_threads = {int(e["fields"]["threads"]): e for e in rows}
            if 1 in by_threads and len(by_threads) > 1:
                n = max(by_threads)
                found = True
                lines.append("| %s | %s POM-32 | %s | %s | %d | %.2fx |" % (hf, isa, mrays(by_threads[1]), mrays(by_threads[n]), n,
                                                                          by_threads[n]["rays_per_second"] / by_threads[1]["rays_per_second"]))
    if not found:
        lines.append("| (only one thread count measured) | | | | | |")
    return lines


def plot_error_vs_layers(entries, isa, threads, path):
    hfs = heightfields_of(entries)
    if not hfs:
        return False
    fig, axes = plt.subplots(1, len(hfs), figsize=(4.2 * len(hfs), 4), squeeze=False)
    for ax, hf in zip(axes[0], hfs):
        for technique in ["steep", "steep-limited", "relief", "pom"]:  # shadow shares POM's hit
            rows = [e for e in select(entries, "BM_Trace", heightfield=hf, technique=technique, isa=isa, threads=threads)
                    if not failed(e) and e["fields"]["layers"].isdigit()]
            rows.sort(key=lambda e: int(e["fields"]["layers"]))
            if rows:
                ax.plot([int(e["fields"]["layers"]) for e in rows], [max(e["uv_error_mean"], 1e-4) for e in rows], marker="o", label=technique)
        for technique, style in [("parallax", "--"), ("parallax-limited", ":")]:
            e = one(entries, "BM_Trace", heightfield=hf, technique=technique, isa=isa, threads=threads)
            if e and not failed(e):
                ax.axhline(max(e["uv_error_mean"], 1e-4), linestyle=style, color="gray", label=technique)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_title(hf)
        ax.set_xlabel("layers")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("mean uv error (texels)")
    axes[0][-1].legend(fontsize=7)
    fig.suptitle("Error against layer count (default view)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return True


def plot_error_vs_angle(run_dir, path):
    sweep = os.path.join(run_dir, "sweep.csv")
    if not os.path.exists(sweep):
        return False
    with open(sweep) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return False
    hfs = list(dict.fromkeys(r["heightfield"] for r in rows))
    fig, axes = plt.subplots(1, len(hfs), figsize=(4.5 * len(hfs), 4), squeeze=False)
    for ax, hf in zip(axes[0], hfs):
        configs = list(dict.fromkeys((r["technique"], r["layers"]) for r in rows if r["heightfield"] == hf))
        for technique, layers in configs:
            if layers not in ("1", "32"):
                continue
            pts = [(float(r["theta"]), max(float(r["uv_error_mean"]), 1e-4)) for r in rows
                   if r["heightfield"] == hf and r["technique"] == technique and r["layers"] == layers]
            label = technique if layers == "1" else "%s %s" % (technique, layers)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker=".", label=label)
        ax.set_yscale("log")
        ax.set_title(hf)
        ax.set_xlabel("view angle from the normal (degrees)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("mean uv error (texels)")
    axes[0][-1].legend(fontsize=7)
    fig.suptitle("Error against view angle\n(sweep views; layered techniques at 32 layers)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return True


def cheapest(points, limit):
    ok = [p for p in points if p["p95"] < limit]
    return max(ok, key=lambda p: p["speed"]) if ok else None


def plot_error_vs_speed(entries, isa, threads, path):
    hfs = heightfields_of(entries)
    if not hfs:
        return False, []
    notes = []
    fig, axes = plt.subplots(1, len(hfs), figsize=(5 * len(hfs), 4.5), squeeze=False)
    for ax, hf in zip(axes[0], hfs):
        points = []
        for e in select(entries, "BM_Trace", heightfield=hf, isa=isa, threads=threads):
            if failed(e) or e["fields"]["technique"] == "shadow":
                continue
            points.append({"label": "%s %s" % (e["fields"]["technique"], e["fields"]["layers"]) if e["fields"]["layers"] != "1" else e["fields"]["technique"],
                           "technique": e["fields"]["technique"], "speed": e["rays_per_second"] / 1e6,
                           "p95": max(e["uv_error_p95"], 1e-4)})
        for technique in TECHNIQUES:
            pts = [p for p in points if p["technique"] == technique]
            if pts:
                ax.scatter([p["speed"] for p in pts], [p["p95"] for p in pts], label=technique, s=18)
        for p in points:
            ax.annotate(p["label"].split(" ")[-1] if " " in p["label"] else "", (p["speed"], p["p95"]), fontsize=5, alpha=0.7)
        for limit, color in [(1.0, "tab:orange"), (0.25, "tab:red")]:
            ax.axhline(limit, color=color, linestyle=":", linewidth=1)
            best = cheapest(points, limit)
            if best:
                ax.scatter([best["speed"]], [best["p95"]], s=160, facecolors="none", edgecolors=color, linewidths=2)
                notes.append("%s: cheapest configuration with p95 < %g texel: **%s** (%.1f Mrays/s, p95 %.3f)" % (hf, limit, best["label"], best["speed"], best["p95"]))
            else:
                notes.append("%s: no configuration reaches p95 < %g texel" % (hf, limit))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(hf)
        ax.set_xlabel("Mrays/s (%s, %s threads)" % (isa, threads))
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("p95 uv error (texels)")
    axes[0][-1].legend(fontsize=7)
    fig.suptitle("Error against speed\ncircles: cheapest with p95 < 1 texel (orange) and < 0.25 texel (red)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return True, notes


def plot_isa_speedup(entries, path):
    hfs = heightfields_of(entries)
    bars = []
    for hf in hfs:
        threads = sorted({e["fields"]["threads"] for e in select(entries, "BM_Trace", heightfield=hf, technique="pom", layers="32")}, key=int)
        for t in threads:
            naive = one(entries, "BM_NaivePort", heightfield=hf, layers="32", threads=t)
            for isa in ISAS:
                e = one(entries, "BM_Trace", heightfield=hf, technique="pom", layers="32", isa=isa, threads=t)
                if e and not failed(e) and naive and not failed(naive):
                    bars.append(("%s\n%st" % (hf, t), isa, e["rays_per_second"] / naive["rays_per_second"]))
    if not bars:
        return False
    groups = list(dict.fromkeys(b[0] for b in bars))
    fig, ax = plt.subplots(figsize=(max(6, 1.6 * len(groups)), 4))
    width = 0.8 / len(ISAS)
    for k, isa in enumerate(ISAS):
        xs = [groups.index(b[0]) + (k - 1.5) * width for b in bars if b[1] == isa]
        ys = [b[2] for b in bars if b[1] == isa]
        ax.bar(xs, ys, width, label=isa)
        for x, y in zip(xs, ys):
            ax.text(x, y, "%.1f" % y, ha="center", va="bottom", fontsize=6)
    ax.axhline(1.0, color="gray", linewidth=1)
    ax.set_xticks(range(len(groups)))
    ax.set_xticklabels(groups, fontsize=8)
    ax.set_ylabel("rays/s relative to the naive scalar port")
    ax.set_title("POM-32 speed-up per ISA")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return True


def update_history(history_path, entries, machine):
    rows = []
    for e in entries:
        if e["kind"] not in ("BM_Trace", "BM_GLSL") or failed(e):
            continue
        rows.append({"date": machine.get("date", ""), "commit": machine.get("commit", ""), "cpu": machine.get("cpu", ""),
                     "isa": e["fields"].get("isa", ""), "threads": e["fields"].get("threads", ""),
                     "benchmark": e.get("run_name", e["name"]), "rays_per_second_median": "%.6g" % e.get("rays_per_second", 0)})
    existing = []
    if os.path.exists(history_path):
        with open(history_path) as f:
            existing = list(csv.DictReader(f))
    existing = [r for r in existing if not (r["commit"] == machine.get("commit") and r["date"] == machine.get("date"))]
    all_rows = existing + rows
    lines = [",".join(HISTORY_COLUMNS)]
    for r in all_rows:
        lines.append(",".join('"%s"' % r[c].replace('"', "'") if "," in r[c] else r[c] for c in HISTORY_COLUMNS))
    atomic_write(history_path, "\n".join(lines) + "\n")
    return all_rows


def plot_history(rows, path):
    runs = list(dict.fromkeys((r["date"], r["commit"]) for r in rows))
    if len(runs) < 2:
        return False
    key = [b for b in dict.fromkeys(r["benchmark"] for r in rows) if "technique:pom/layers:32/" in b][:6]
    fig, ax = plt.subplots(figsize=(8, 4))
    for bench in key:
        pts = [(runs.index((r["date"], r["commit"])), float(r["rays_per_second_median"]) / 1e6) for r in rows if r["benchmark"] == bench]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=bench.replace("BM_", "").replace("/technique:pom/layers:32", ""))
    ax.set_xticks(range(len(runs)))
    ax.set_xticklabels(["%s\n%s" % (d[:10], c) for d, c in runs], fontsize=6)
    ax.set_ylabel("Mrays/s")
    ax.set_title("POM-32 over recorded runs")
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return True


def section_gallery(run_dir):
    path = os.path.join(run_dir, "gallery.json")
    if not os.path.exists(path):
        return ["## Gallery", "", "Not produced in this run."]
    with open(path) as f:
        gallery = json.load(f)
    lines = ["## Gallery", "", "%s, %s. Left: shaded render at the technique's uv; right: uv error "
             "(log scale 0.01 to 10 texels, legend below each map)." % (gallery.get("heightfield", ""), gallery.get("view", "")), "",
             "| technique | render | error | mean | p95 | wrong surface |", "|---|---|---|---:|---:|---:|"]
    for e in gallery.get("entries", []):
        name = e["technique"] + ("" if e.get("layers") in (None, "-", "1") else " " + e["layers"])
        lines.append("| %s | ![](%s) | ![](%s) | %s | %s | %s%% |" % (
            name, e["render"], e["error"], fmt(e.get("uv_error_mean")), fmt(e.get("uv_error_p95")), fmt(100 * e.get("wrong_surface_rate", 0), 2)))
    return lines


def section_claims(run_dir):
    lines = ["## The tutorials' claims", ""]
    path = os.path.join(run_dir, "claims.json")
    if not os.path.exists(path):
        return lines + ["Not measured in this run."]
    with open(path) as f:
        claims = json.load(f)
    lines += ["Rules, figures and every check: [claims.md](claims.md).", "", "| claim | verdict |", "|---|---|"]
    for c in claims:
        lines.append("| %s: %s | **%s** |" % (c["id"], c["claim"], c["verdict"]))
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--history", help="history CSV to append this run's rows to, and to plot")
    args = parser.parse_args()
    run_dir = args.run_dir
    machine = {}
    if os.path.exists(os.path.join(run_dir, "machine.json")):
        with open(os.path.join(run_dir, "machine.json")) as f:
            machine = json.load(f)
    entries, context = load_benchmarks(run_dir)
    isa, threads = best_isa(entries, machine), max_threads(entries)
    os.makedirs(os.path.join(run_dir, "plots"), exist_ok=True)
    md = ["# heightmarch report", "",
          "Parallax-mapping techniques on the CPU (packet kernels per ISA) and as GLSL (OSMesa llvmpipe), measured "
          "against the exact ray/heightfield intersection. Reproduce with `scripts/main` (see README)."]
    md += [""] + section_machine(machine, context)
    md += [""] + section_claims(run_dir)
    if entries:
        md += [""] + section_accuracy_speed(entries, isa, threads)
        md += [""] + section_isa_vs_glsl(entries, isa, threads)
        md += [""] + section_threads(entries)
    else:
        md += ["", "No benchmark results in this run."]
    md += ["", "## Plots", ""]
    if plot_error_vs_layers(entries, isa, threads, os.path.join(run_dir, "plots", "error_vs_layers.png")):
        md += ["![error against layers](plots/error_vs_layers.png)", ""]
    if plot_error_vs_angle(run_dir, os.path.join(run_dir, "plots", "error_vs_angle.png")):
        md += ["![error against view angle](plots/error_vs_angle.png)", ""]
    shown, notes = plot_error_vs_speed(entries, isa, threads, os.path.join(run_dir, "plots", "error_vs_speed.png"))
    if shown:
        md += ["![error against speed](plots/error_vs_speed.png)", ""] + ["- " + n for n in notes] + [""]
    if plot_isa_speedup(entries, os.path.join(run_dir, "plots", "isa_speedup.png")):
        md += ["![speed-up per ISA](plots/isa_speedup.png)", ""]
    if args.history:
        rows = update_history(args.history, entries, machine)
        if plot_history(rows, os.path.join(run_dir, "plots", "history.png")):
            md += ["![history](plots/history.png)", ""]
    md += section_gallery(run_dir)
    atomic_write(os.path.join(run_dir, "report.md"), "\n".join(md) + "\n")
    print("report: %s" % os.path.join(run_dir, "report.md"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
