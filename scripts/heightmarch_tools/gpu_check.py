"""The GPU check (scripts/gpu_check): on a machine with a GPU, in one command of a few minutes,
the GLSL techniques through EGL on the GPU's own driver against the CPU, and their GPU time.

1. What it needs: a built tree (build/heightmarch, heightmarch-bench and the worker); where the
   default build/ is not built, scripts/setup installs the Debian packages and builds it, while a
   --build DIR given is taken as it is (one that is missing or not built is refused in one line,
   never built in its place); with --debs DIR the packages there
   are unpacked (dpkg-deb -x) into BUILD/gpu-root instead, for a machine that reaches no mirror,
   and the libraries and EGL vendor files found there are used. A GPU's EGL needs its driver's
   vendor library and vendor file (NVIDIA: libEGL_nvidia.so.0 and 10_nvidia.json in
   /usr/share/glvnd/egl_vendor.d) beside libglvnd's libEGL.so.1: the check names the vendor files
   it finds, and a worker library that does not load stops it in one line.
2. EGL's devices (`heightmarch glsl --list-devices`, devices.txt); the device is --gl-device, else
   the first that is not Mesa's software one.
3. Conformance: every technique at 4, 32 and 8-32 layers on the five builtins, on the device and
   on the CPU (`heightmarch glsl --compare --json`, 128 x 128 rays), per technique the share of
   rays with identical sample counts and the uv difference (p99, max, texels); the GPU's errors
   against the exact intersection beside the CPU's. A GPU's texture unit filters with fixed-point
   weights, so differences are reported, not failed (docs/techniques.md#the-gl-paths).
4. Timing: POM, relief and steep at 8, 32 and 8-32 layers, cone at 32 and maxmip, on the five
   builtins at 1920 x 1080 (heightmarch-bench, --benchmark_repetitions 5): the GPU's time by
   GL_TIME_ELAPSED queries (a software device's by the wall clock), medians of the repetitions.
5. The run directory (results/<date>-<commit>-gpu-<device>, or --out): devices.txt,
   conformance.json, bench.json and report.md.

--quick (the script's own test, on llvmpipe with --gl-device software): bricks alone, pom and
maxmip at 32 layers, 64 x 64 views, 2 repetitions (a --size or --repetitions given still holds).

Every option is checked before anything runs: the sizes and counts in range, --build, --debs and
--out as paths of the kind each must be.
"""
import argparse
import concurrent.futures
import glob
import json
import os
import subprocess
import time

from . import cli
from .errors import Unusable
from .escape import markdown, terminal
from .readers import parse_json, read_json
from .writers import atomic_write

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
BUILTINS = ["bricks", "toybox", "terrain", "waves", "spikes"]
CONFORMANCE_LAYERS = ["4", "32", "8-32"]
# The timed configurations: technique, layer specs (heightmarch-bench's filter).
TIMED = [("pom", ["8", "32", "8-32"]), ("relief", ["8", "32", "8-32"]), ("steep", ["8", "32", "8-32"]),
         ("cone", ["32"]), ("maxmip", [None])]
QUICK_TIMED = [("pom", ["32"]), ("maxmip", [None])]
UNIT_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}  # Google Benchmark's time units, in ms
STEP_TIMEOUT = 300  # seconds a command of the check may take (each bounds its own GL waits)
SETUP_TIMEOUT = 3600  # scripts/setup: package installs and a build of the tree
BINARIES = ("heightmarch", "heightmarch-bench", "heightmarch-glsl-worker")
MAX_SIDE = 16384  # heightmarch's largest view side (kMaxViewSide)
MAX_REPETITIONS = 1000
VENDOR_DIRS = ["/usr/share/glvnd/egl_vendor.d", "/etc/glvnd/egl_vendor.d"]


def run(args, env, timeout=STEP_TIMEOUT):
    """A command's stdout; Unusable naming it and its last line of output when it fails."""
    try:
        done = subprocess.run(args, env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise Unusable("%s ran past %d s" % (" ".join(args[:3]), timeout))
    if done.returncode != 0:
        last = (done.stderr.strip() or done.stdout.strip()).splitlines()[-1:] or ["no output"]
        raise Unusable("%s: exit %d: %s" % (" ".join(args[:3]), done.returncode, last[0]))
    return done.stdout


def unpack(debs, root, env):
    """The .deb files of debs unpacked into root, their libraries and EGL vendor files used."""
    packages = sorted(glob.glob(os.path.join(debs, "*.deb")))
    if not packages:
        raise Unusable("--debs %s: no .deb files there" % debs)
    for p in packages:
        run(["dpkg-deb", "-x", p, root], env)
    libraries = [d for d in glob.glob(os.path.join(root, "usr/lib/*-linux-gnu")) + glob.glob(os.path.join(root, "usr/lib"))]
    env["LD_LIBRARY_PATH"] = ":".join(libraries + [env.get("LD_LIBRARY_PATH", "")]).rstrip(":")
    vendors = [d for d in (os.path.join(root, v.lstrip("/")) for v in VENDOR_DIRS) if os.path.isdir(d)]
    if vendors:  # libglvnd reads its vendor files from here instead (and from nowhere else)
        env["__EGL_VENDOR_LIBRARY_DIRS"] = ":".join(vendors + VENDOR_DIRS)
    return len(packages)


def prepare(args, env):
    """The tree built, the worker's libraries loading; what was found, as report lines."""
    notes = []
    if args.debs:
        notes.append("unpacked %d packages of %s into %s" % (unpack(args.debs, os.path.join(args.build, "gpu-root"), env),
                                                            args.debs, os.path.join(args.build, "gpu-root")))
    binaries = [os.path.join(args.build, b) for b in BINARIES]
    if not all(os.access(b, os.X_OK) for b in binaries):  # only the default build/ (check_paths)
        run([os.path.join(ROOT, "scripts/setup"), "-DHEIGHTMARCH_BUILD_TESTS=OFF"], env, timeout=SETUP_TIMEOUT)
        notes.append("installed what was missing and built %s (scripts/setup)" % args.build)
    missing = [line.split()[0] for line in run(["ldd", binaries[2]], env).splitlines() if "not found" in line]
    if missing:
        raise Unusable("the GLSL worker needs %s, which do not load (install them, or unpack them with --debs)"
                       % ", ".join(missing))
    vendors = sorted(os.path.basename(f) for d in env.get("__EGL_VENDOR_LIBRARY_DIRS", ":".join(VENDOR_DIRS)).split(":")
                     for f in glob.glob(os.path.join(d, "*.json")))
    notes.append("EGL vendor files: %s" % (", ".join(vendors) or "none (EGL will list no device)"))
    return notes


def devices(args, env):
    """EGL's devices as (index, name, renderer, extensions), and the raw listing."""
    text = run([os.path.join(args.build, "heightmarch"), "glsl", "--list-devices"], env)
    listed = [line.split("\t") for line in text.splitlines() if line.count("\t") == 3]
    return listed, text


def pick_device(listed, asked):
    if asked:
        if not any(asked in (index, name) for index, name, _, _ in listed):
            raise Unusable("--gl-device %s: EGL lists %s" % (asked, ", ".join(n for _, n, _, _ in listed) or "no device"))
        return asked
    gpus = [name for _, name, _, _ in listed if name != "software"]
    if not gpus:
        raise Unusable("EGL lists no GPU (only %s): is the GPU driver's EGL vendor library installed? "
                       "--gl-device software runs the check on llvmpipe" % (", ".join(n for _, n, _, _ in listed) or "nothing"))
    return gpus[0]


def conformance(args, env, device, builtins, techniques, layer_specs, size):
    """One record per technique, layer spec and builtin: the device's hits against the CPU's.
    A few at once where the machine has the cores (each is a process with its own GL context)."""
    def one(case):
        hf, technique, layers = case
        out = parse_json(run([os.path.join(args.build, "heightmarch"), "glsl", "--gl", "egl", "--gl-device", device,
                              "--heightmap", "builtin:" + hf, "--res", "128", "--technique", technique,
                              "--layers", layers, "--size", size, "--threads", "1", "--repetitions", "1",
                              "--compare", "--json"], env), "heightmarch glsl --json")
        glsl, compared = out["glsl"], out["comparisons"][0]
        c = compared["conformance"] or {}
        return {"heightfield": hf, "technique": technique, "layers": glsl["layers"],
                "gl": glsl["gl"], "provenance": glsl["provenance"],
                "identical_sample_counts": c.get("identical_sample_counts"),
                "uv_difference_p99": c.get("uv_difference_p99"), "uv_difference_max": c.get("uv_difference_max"),
                "gpu_uv_error_p99": glsl["errors"]["uv_error_p99"],
                "cpu_uv_error_p99": compared["cpu"]["errors"]["uv_error_p99"], "cpu_backend": compared["cpu"]["backend"]}
    cases = [(hf, t, layers) for hf in builtins for t in techniques for layers in layer_specs]
    with concurrent.futures.ThreadPoolExecutor(max(1, min(4, (os.cpu_count() or 1) // 4))) as pool:
        return list(pool.map(one, cases))


def timing(args, env, device, builtins, timed, size, repetitions, out):
    """heightmarch-bench over the timed configurations on the device, into out/bench.json."""
    layer_specs = sorted({spec for _, specs in timed for spec in specs if spec})
    pattern = "|".join("^BM_GLSL/.*/technique:%s/%s" % (t, "(%s)/" % "|".join("layers:" + s for s in specs)
                                                         if specs != [None] else "") for t, specs in timed)
    run([os.path.join(args.build, "heightmarch-bench"), "--hm_gl", "egl", "--hm_gl_device", device, "--hm_size", size,
         "--hm_heightfields", ",".join(builtins), "--hm_layers", ",".join(layer_specs), "--hm_threads", "1",
         "--benchmark_filter=" + pattern, "--benchmark_repetitions=%d" % repetitions,
         "--benchmark_out=" + os.path.join(out, "bench.json")], env, timeout=3 * STEP_TIMEOUT)
    return read_json(os.path.join(out, "bench.json"), nonfinite=True)  # an aggregate's counters may be NaN


def fields(name):
    return dict(part.split(":", 1) for part in name.split("/")[1:] if ":" in part)


def report(device, listed, notes, records, bench, seconds, args, conformance_size):
    gl = records[0]["gl"] if records else {}
    p = records[0]["provenance"] if records else {}
    software = gl.get("software", True)
    md = ["# heightmarch GPU check: %s" % markdown(gl.get("label", "?")), "",
          "EGL device **%s**: %s, %s, driver %s. CPU %s (%s cores), commit %s, %s; %.0f s. Command: `scripts/gpu_check%s`."
          % (markdown(device), markdown(gl.get("renderer", "?")), markdown(gl.get("version", "?")),
             markdown(gl.get("driver", "?")), markdown(p.get("cpu", "?")), p.get("cores", "?"), p.get("commit", "?"),
             p.get("date", "?"), seconds, markdown(" " + " ".join(args.argv)) if args.argv else ""), ""]
    md += ["## What it found", ""] + ["- " + markdown(n) for n in notes] + [
        "", "| index | device | renderer | extensions |", "|---|---|---|---|"]
    md += ["| %s | %s | %s | %s |" % tuple(markdown(x) for x in d) for d in listed]
    md += ["", "## Conformance against the CPU", "",
           "Each technique on the device and on the CPU (%s, bit for bit the scalar reference) on the same rays, over "
           "%s at %s layers (%s rays each): the least share of rays with identical sample counts, the largest "
           "uv difference (p99 and max, texels) and the GPU's and the CPU's p99 uv error against the exact "
           "intersection (the largest of the heightfields). %s" % (
               records[0]["cpu_backend"] if records else "?", ", ".join(sorted({r["heightfield"] for r in records})),
               ", ".join(dict.fromkeys(r["layers"] for r in records)), conformance_size,
               "llvmpipe rounds its filter's last bit unlike the CPU on a few percent of samples (docs/techniques.md)."
               if software else "A GPU's texture unit filters with fixed-point weights (8 fractional bits on NVIDIA), "
               "the CPU in float: the differences are the GPU's, reported rather than failed "
               "(docs/techniques.md#the-gl-paths)."), "",
           "| technique | identical sample counts | uv difference p99 | uv difference max | device's p99 error "
           "| CPU's p99 error |",
           "|---|---|---|---|---|---|"]
    for technique in dict.fromkeys(r["technique"] for r in records):
        mine = [r for r in records if r["technique"] == technique]
        def worst(key, mine=mine):
            return max((r[key] for r in mine if r[key] is not None), default=None)
        same = min((r["identical_sample_counts"] for r in mine if r["identical_sample_counts"] is not None), default=None)
        cells = ["-" if same is None else "%.2f%%" % (100 * same)] + [
            "-" if worst(k) is None else "%.3g" % worst(k)
            for k in ("uv_difference_p99", "uv_difference_max", "gpu_uv_error_p99", "cpu_uv_error_p99")]
        md.append("| %s | %s |" % (technique, " | ".join(cells)))
    clock = "the wall clock to glFinish (a software device: its timer queries span the draw call alone)" \
        if software else "GL_TIME_ELAPSED queries"
    md += ["", "## GPU time", "",
           "heightmarch-bench on the device at %s, each configuration %s times: the median time of a draw by %s "
           "(`bench.json`, whose counters hold both clocks), and its rays/s." % (args.size, args.repetitions, clock), "",
           "| heightfield | technique | layers | ms (median) | wall ms | timer ms | Mrays/s |", "|---|---|---|---|---|---|---|"]
    for b in bench.get("benchmarks", []):
        if b.get("aggregate_name") != "median":
            continue
        f = fields(b["run_name"])
        def ms(key, b=b):
            return "%.3f" % (1e3 * b[key]) if key in b else "-"
        md.append("| %s | %s | %s | %.3f | %s | %s | %.1f |" % (
            markdown(f.get("heightfield", "?")), f.get("technique", "?"), f.get("layers", "?"),
            b["real_time"] * UNIT_MS[b.get("time_unit", "ns")],
            ms("gl_wall_seconds"), ms("gl_timer_seconds"), b.get("rays_per_second", 0) / 1e6))
    return "\n".join(md) + "\n"


def view_size(text):
    """--size: WxH, each side a whole number of pixels in [1, MAX_SIDE]."""
    w, x, h = text.partition("x")
    if not (x and w.isdigit() and h.isdigit() and w.isascii() and h.isascii()
            and 1 <= int(w) <= MAX_SIDE and 1 <= int(h) <= MAX_SIDE):
        raise argparse.ArgumentTypeError("%s is not WxH with sides in [1, %d]" % (text, MAX_SIDE))
    return text


def repetitions(text):
    """--repetitions: a whole count in [1, MAX_REPETITIONS] (Google Benchmark aborts on a negative one)."""
    if not (text.isascii() and text.isdigit() and 1 <= int(text) <= MAX_REPETITIONS):
        raise argparse.ArgumentTypeError("%s is not a whole number in 1..%d" % (text, MAX_REPETITIONS))
    return int(text)


def check_paths(args, default_build):
    """Every path given, checked before anything runs (nothing is built, unpacked or created for
    a mistyped one): --build a built tree (the default build/ alone may be built by scripts/setup),
    --debs a directory, --out a directory to create or an empty one."""
    if args.build != default_build or args.debs:
        if not os.path.isdir(args.build):
            raise Unusable("--build %s: no such directory" % terminal(args.build))
        missing = [b for b in BINARIES if not os.access(os.path.join(args.build, b), os.X_OK)]
        if missing:
            raise Unusable("--build %s: holds no %s: build it first (scripts/setup, or cmake --build %s)" % (
                terminal(args.build), ", ".join(missing), terminal(args.build)))
    if args.debs and not os.path.isdir(args.debs):
        raise Unusable("--debs %s: no such directory" % terminal(args.debs))
    if args.out:
        if os.path.lexists(args.out) and not os.path.isdir(args.out):
            raise Unusable("--out %s: is not a directory" % terminal(args.out))
        if os.path.isdir(args.out) and os.listdir(args.out):
            raise Unusable("--out %s: holds files already; give another --out" % terminal(args.out))
        parent = os.path.dirname(os.path.abspath(args.out))
        if not os.path.isdir(parent):
            raise Unusable("--out %s: its parent %s is no directory" % (terminal(args.out), terminal(parent)))


def main(argv):
    parser = cli.Parser(prog="gpu_check", description="the GLSL techniques on a GPU through EGL: conformance and GPU time")
    default_build = os.path.join(ROOT, "build")
    parser.add_argument("--gl-device", help="the EGL device (default: the first that is not software)")
    parser.add_argument("--out", help="run directory (default: results/<date>-<commit>-gpu-<device>)")
    parser.add_argument("--build", default=default_build,
                        help="a built tree (default: build, which scripts/setup builds where it is not)")
    parser.add_argument("--debs", help="a folder of Debian packages to unpack instead of installing")
    parser.add_argument("--size", type=view_size, help="the timed view, WxH (default 1920x1080; quick: 64x64)")
    parser.add_argument("--repetitions", type=repetitions,
                        help="timed repetitions, 1..%d (default 5; quick: 2)" % MAX_REPETITIONS)
    parser.add_argument("--quick", action="store_true", help="bricks, pom and maxmip at 32 layers, 64 x 64: the test")
    args = parser.parse_args(argv)
    args.argv = argv
    args.size = args.size or ("64x64" if args.quick else "1920x1080")
    args.repetitions = args.repetitions or (2 if args.quick else 5)
    check_paths(args, default_build)
    start = time.monotonic()
    env = dict(os.environ)
    notes = prepare(args, env)
    listed, listing = devices(args, env)
    device = pick_device(listed, args.gl_device)
    if args.out:
        out = args.out
    else:
        stamp = time.strftime("%Y-%m-%d", time.gmtime())
        commit = run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], env).strip()
        out = os.path.join(ROOT, "results", "%s-%s-gpu-%s" % (stamp, commit, device))
    if os.path.exists(out) and os.listdir(out):
        raise Unusable("%s: holds files already; give another --out" % terminal(out))
    os.makedirs(out, exist_ok=True)
    atomic_write(os.path.join(out, "devices.txt"), listing)
    builtins = ["bricks"] if args.quick else BUILTINS
    # Every technique of the registry, as the suite's plan lists its GLSL rows.
    techniques = ["pom", "maxmip"] if args.quick else list(dict.fromkeys(
        line.split("\t")[2] for line in run([os.path.join(args.build, "heightmarch"), "suite", "--dry-run", "--quick",
                                             "--parts", "glsl", "--layers", "32"], env).splitlines() if "\tglsl\t" in line))
    conformance_size = "64x64" if args.quick else "128x128"
    records = conformance(args, env, device, builtins, techniques, ["32"] if args.quick else CONFORMANCE_LAYERS,
                          conformance_size)
    atomic_write(os.path.join(out, "conformance.json"), json.dumps(records, indent=1) + "\n")
    bench = timing(args, env, device, builtins, QUICK_TIMED if args.quick else TIMED, args.size, args.repetitions, out)
    atomic_write(os.path.join(out, "report.md"),
                 report(device, listed, notes, records, bench, time.monotonic() - start, args, conformance_size))
    print("gpu_check: %s" % os.path.join(out, "report.md"))
    return 0
