"""The cases of hostile_inputs.py, by issue 32's six classes (what each expects is in its line)."""
import json
import os
import shutil
import signal
import subprocess
import time

from hostile_inputs import PYTHON, ROOT, Case, Skip

# A terminal's title, a screen clear, a bidirectional override, a C1 CSI and a bell.
ESCAPES = "\x1b]0;PWN\x07\x1b[2J\u202e\u009b31m"
# An endless loop in a brought-in shader (llvmpipe cuts it only after 65,535 passes: tens of
# seconds at these sizes, far beyond the cases' waits).
ENDLESS = """vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) {
  vec2 t = texCoords;
  while (texture(depthMap, t).r < 2.0) t += vec2(1e-7);
  return t;
}
"""
# The values the report's own reader is given here (each run costs its Python's start-up): those
# issue 32 found it failing on, and a value recommend's reader and its differ on.
REPORT_READS = ("NaN", "1e400", "a string for seconds", "seconds 1e308", "id 1e20", "width as a string",
                "layers beyond an int", "deep nesting")


def cases(build, sandbox):
    tool = os.path.join(build, "heightmarch")
    out = []
    add = lambda *a, **k: out.append(Case(*a, **k))  # noqa: E731
    base = sandbox.path("base")
    # The base run: what the tool writes, so every variant below is one hostile change to it.
    subprocess.run([tool, "suite", "--quick", "--techniques", "pom", "--parts", "matrix", "--no-glsl", "--out", base],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    data = json.load(open(os.path.join(base, "measurements.json")))
    timed = next(i for i, r in enumerate(data["rows"]) if r.get("speed"))

    def run_dir(name, change=None, text=None, files=()):
        """runs/NAME: the base run's measurements.json changed by change(data) (in place), or
        replaced by text (bytes or str, or None: none); files: (name, bytes) beside it."""
        d = sandbox.path("runs", name)
        os.makedirs(d)
        if text is None and change is not None or text is None and not files:
            copy = json.loads(json.dumps(data))
            if change:
                change(copy)
            text = json.dumps(copy, indent=1)
        if text is not None:
            with open(os.path.join(d, "measurements.json"), "wb") as f:
                f.write(text.encode() if isinstance(text, str) else text)
        for name_, content in files:
            with open(os.path.join(d, name_), "wb") as f:
                f.write(content.encode() if isinstance(content, str) else content)
        return d

    def row_field(*path, value):
        """A change that sets the timed row's field at path to value."""
        def change(d):
            target = d["rows"][timed]
            for p in path[:-1]:
                target = target[p]
            target[path[-1]] = value
        return change

    def literal(token):
        """measurements.json with the timed row's first seconds written as token (NaN, 1e400, ...)."""
        copy = json.loads(json.dumps(data))
        copy["rows"][timed]["speed"]["seconds"][0] = "@@TOKEN@@"
        return json.dumps(copy).replace('"@@TOKEN@@"', token)

    report = lambda d, *more: [tool, "report", d] + list(more)  # noqa: E731
    recommend = lambda d, *more: [tool, "recommend", d] + list(more)  # noqa: E731
    rel = lambda d: os.path.relpath(d, sandbox.root)  # noqa: E731

    # ------------------------------------------------------------------------------------------
    # 1. Strings from files reach the outputs escaped (report.md, the page and the CSV of hostile
    #    names: test_hostile_names.sh; here what reaches the terminal and the CSV's header).
    def hostile_fields(d):
        d["rows"][timed]["heightfield"]["label"] = "map" + ESCAPES
        for r in d["rows"]:
            r["=HYPERLINK(\"http:x\")"] = "x"  # a field a reader may add, named like a formula
            r["errors"]["@SUM(A1)"] = None
    # named like an option, its report's files links to a file outside: a report is still written
    # into it, as files of its own
    d = run_dir("--history=" + sandbox.path("outside", "planted.csv"), hostile_fields)
    for f in ("report.md", "measurements.csv", "report.html"):
        os.symlink(os.path.join(sandbox.outside, "victim.txt"), os.path.join(d, f))

    def csv_header_clean(_, d=d):
        import csv
        with open(os.path.join(d, "measurements.csv"), newline="") as f:
            header = next(csv.reader(f))
        bad = [h for h in header if h[:1] in ("=", "+", "-", "@", "\t", "\r")]
        return "measurements.csv's header has formula cells %s" % bad if bad else None
    add("strings", "report of a run named like an option, a label with terminal escapes, fields named like "
        "formulas, its files links outside: its own files, nothing printed raw, no formula in the CSV's header",
        report(d), 0, writes=[rel(d)], check=csv_header_clean)
    add("strings", "recommend prints a label with terminal escapes as text", recommend(d), 0)
    add("strings", "recommend --json prints it as JSON escapes", recommend(d, "--json"), 0,
        check=lambda r: None if any(a["heightfield"] == "map" + ESCAPES for b in json.loads(r.out)["backends"]
                                    for a in b["per_heightfield"]) else "the label did not survive as JSON")
    d = run_dir("esc-refused", row_field("layers", value="8" + ESCAPES))
    add("strings", "report quotes a refused value with escapes as text", report(d), 2, writes=[rel(d)])
    add("strings", "recommend quotes a refused value with escapes as text", recommend(d), 2)
    add("strings", "report of a run directory named with escapes", report(sandbox.path("no" + ESCAPES)), 2)

    # ------------------------------------------------------------------------------------------
    # 2. A path from a file never decides where files go.
    for name, path in (("traversal", "gallery/../../outside/victim.txt"), ("absolute", sandbox.path("outside", "x.png"))):
        d = run_dir("image-" + name, row_field("images", value={"render": path, "error": path}))
        add("paths", "report refuses an image path that leaves the gallery (%s)" % name, report(d), 2, writes=[rel(d)])
    d = run_dir("plots-link")
    os.symlink(sandbox.outside, os.path.join(d, "plots"))
    add("paths", "report refuses a plots/ that links outside the run", report(d), 2, writes=[rel(d)])
    d = sandbox.path("gallery-link")
    os.makedirs(d)
    os.symlink(sandbox.outside, os.path.join(d, "gallery"))
    add("paths", "suite refuses a gallery/ that links outside its --out", [tool, "suite", "--quick", "--techniques", "pom",
        "--parts", "gallery", "--no-glsl", "--out", d], 2, writes=[rel(d)], timeout=30)
    d = run_dir("lock-link")
    os.makedirs(sandbox.path("hist-lock-link"))
    os.symlink(os.path.join(sandbox.outside, "victim.txt"), sandbox.path("hist-lock-link", "history.csv.lock"))
    add("paths", "report --history refuses a lock file that is a link", report(d, "--history",
        sandbox.path("hist-lock-link", "history.csv")), 1, writes=[rel(d)])

    # ------------------------------------------------------------------------------------------
    # 3. Readers check kind, size and every value: one line, exit 2, never a figure, never a hang.
    def special(name, make):
        d = sandbox.path("runs", name)
        os.makedirs(d)
        make(os.path.join(d, "measurements.json"))
        return d
    kinds = {"FIFO": lambda p: os.mkfifo(p), "link to /dev/zero": lambda p: os.symlink("/dev/zero", p),
             "directory": os.mkdir, "empty file": lambda p: open(p, "w").close(),
             "sparse 1 GiB file": lambda p: os.truncate(open(p, "w").name, 1 << 30)}
    for i, (kind, make) in enumerate(kinds.items()):
        d = special("kind-%d" % i, make)
        env = {"HEIGHTMARCH_MEMORY_LIMIT": "200M"}
        if kind in ("FIFO", "link to /dev/zero", "sparse 1 GiB file"):
            add("readers", "report: measurements.json as a %s" % kind, report(d), 2, env=env, timeout=10, writes=[rel(d)])
        add("readers", "recommend: measurements.json as a %s" % kind, recommend(d), 2, env=env, timeout=10)
    values = [("NaN", literal("NaN")), ("1e400", literal("1e400")), ("-Infinity", literal("-Infinity")),
              ("invalid UTF-8", b'{"format": "\xff\xfe"}'), ("a string for seconds", literal('"fast"')),
              ("seconds 1e308", literal("1e308")), ("no seconds", None), ("rays -1", None), ("id 1e20", None),
              ("id 2^64-1", None), ("uv error -5", None), ("width as a string", None), ("threads 0", None),
              ("format_version 2^32+2", None), ("layers beyond an int", None), ("deep nesting", None),
              ("a truncated file", json.dumps(data)[:-40]), ("an unknown technique", None)]
    changes = {"no seconds": row_field("speed", "seconds", value=[]), "rays -1": row_field("rays", value=-1),
               "id 1e20": row_field("id", value=1e20), "id 2^64-1": row_field("id", value=2 ** 64 - 1),
               "uv error -5": row_field("errors", "uv_error_p99", value=-5),
               "width as a string": row_field("heightfield", "width", value="256"),
               "threads 0": row_field("threads", value=0),
               "format_version 2^32+2": lambda d: d.update(format_version=2 ** 32 + 2),
               "layers beyond an int": row_field("layers", value="99999999999999999999"),
               "an unknown technique": row_field("technique", value="pom2")}
    deep = json.dumps(dict(data, rows=[dict(data["rows"][timed], id="@@DEEP@@")]))
    deep = deep.replace('"@@DEEP@@"', "[" * 100000 + "]" * 100000)
    for i, (what, text) in enumerate(values):
        if what == "deep nesting":
            text = deep
        d = run_dir("value-%d" % i, changes.get(what), text)
        if what in REPORT_READS:  # the others are the report's unit tests' (tests/python)
            add("readers", "report: %s" % what, report(d), 2, writes=[rel(d)])
        add("readers", "recommend: %s" % what, recommend(d), 2)
    for i, (name, make) in enumerate((("claims.json", lambda p: os.mkfifo(p)),
                                      ("recommendation.json", lambda p: os.symlink("/dev/zero", p)),
                                      ("alerts.json", lambda p: open(p, "w").write('{"format_version": 1, "alerts": NaN}')))):
        d = run_dir("beside-%d" % i)
        make(os.path.join(d, name))
        add("readers", "report: %s beside it hostile" % name, report(d), 2, writes=[rel(d)], timeout=10)
    # compare reads Google Benchmark files the same way (the regress engineer's area)
    bench = os.path.join(base, "bench.json")
    compare = os.path.join(ROOT, "scripts", "compare")
    fifo = sandbox.path("bench.fifo")
    os.mkfifo(fifo)
    nan = sandbox.path("bench-nan.json")
    with open(nan, "w") as f:
        f.write(open(bench).read().replace('"real_time": ', '"real_time": NaN, "x": ', 1))
    for what, other in (("a FIFO", fifo), ("/dev/zero", "/dev/zero"), ("a NaN time", nan)):
        add("readers", "compare: NEW is %s" % what, [compare, bench, other], 2, timeout=10, owner="regress",
            env={"PYTHONPATH": os.path.join(ROOT, "scripts")})

    # ------------------------------------------------------------------------------------------
    # 4. The history holds: no row lost, invented or kept from a run that did not complete.
    from heightmarch_tools import history as history_module
    header = ",".join(history_module.COLUMNS) + "\n"

    def history_file(name, text):
        d = sandbox.path("histories", name)
        os.makedirs(d)
        with open(os.path.join(d, "history.csv"), "wb") as f:
            f.write(text.encode() if isinstance(text, str) else text)
        return os.path.join(d, "history.csv")

    good = run_dir("recorded")
    subprocess.run(report(good, "--history", sandbox.path("recorded-history.csv")), check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    rows = open(sandbox.path("recorded-history.csv")).read().split("\n", 1)[1]
    unchanged = lambda path: lambda r: (None if open(path, "rb").read() == before_text[path]  # noqa: E731
                                        else "the history changed")
    before_text = {}

    def hostile_history(name, content, expect, what, check_unchanged=True, **k):
        path = history_file(name, content)
        before_text[path] = open(path, "rb").read()
        d = run_dir("for-" + name)
        add("history", what, report(d, "--history", path), expect, writes=[rel(d), rel(path) + ".lock"]
            + ([] if check_unchanged else [rel(os.path.dirname(path))]), check=unchanged(path) if check_unchanged else None, **k)
        return path
    conflict = header + "<<<<<<< HEAD\n" + rows + "=======\n" + rows + ">>>>>>> other\n"
    hostile_history("conflict", conflict, 2, "a merge conflict's markers: refused with the line, history kept",
                    text="line 2")
    first = rows.splitlines()[0].split(",")
    word = ",".join(first[:-4] + ["fast"] + first[-3:]) + "\n"
    hostile_history("word", header + word, 2, "a word in a numeric column: refused, history kept")
    hostile_history("nan", header + ",".join(first[:-4] + ["nan"] + first[-3:]) + "\n", 2,
                    "nan in a numeric column: refused, history kept")
    hostile_history("nul", header + rows.replace(",", ",\0", 1), 2, "a NUL byte: refused, history kept")
    hostile_history("huge-cell", header + rows.replace(",", "," + "x" * 300000, 1), 2,
                    "a 300 kB cell: refused, history kept")
    hostile_history("crlf", (header + rows).replace("\n", "\r\n"), 0, "a history with CRLF line ends still reads",
                    check_unchanged=False)
    path = history_file("repair", conflict)
    add("history", "repair-history drops the markers, naming each", [os.path.join(ROOT, "scripts", "repair-history"),
        path], 0, writes=[rel(os.path.dirname(path))], env={"PYTHONPATH": os.path.join(ROOT, "scripts")},
        check=lambda r, path=path: None if r.out.count(b"drops") == 3 and open(path).read() == header + rows + rows
        else "did not drop exactly the three marker lines")
    d = run_dir("history-dir")
    add("history", "--history DIR: one line", report(d, "--history", sandbox.path("histories")), 2, writes=[rel(d)])
    d = run_dir("history-fifo")
    os.makedirs(sandbox.path("fifo-history"))
    os.mkfifo(sandbox.path("fifo-history", "history.csv"))
    add("history", "--history a FIFO: one line, no hang", report(d, "--history", sandbox.path("fifo-history", "history.csv")),
        2, writes=[rel(d), "fifo-history/history.csv.lock"], timeout=10)
    d = run_dir("incomplete-run", files=[("INCOMPLETE", "")])
    shutil.copy(os.path.join(base, "measurements.json"), d)
    path = history_file("incomplete", header + rows)
    before_text[path] = open(path, "rb").read()
    add("history", "an INCOMPLETE run is not recorded", report(d, "--history", path), 2,
        writes=[rel(d), rel(path) + ".lock"], check=unchanged(path))
    # alerts.csv beside the history is read last: a bad one must stop the recording before any row
    path = history_file("bad-alerts", header + rows)
    before_text[path] = open(path, "rb").read()
    with open(os.path.join(os.path.dirname(path), "alerts.csv"), "w") as f:
        f.write("<<<<<<< HEAD\n")
    d = run_dir("for-bad-alerts")
    add("history", "a malformed alerts.csv: refused before the history gets a row", report(d, "--history", path), 2,
        writes=[rel(d), rel(path) + ".lock"], check=unchanged(path))

    # Recordings at once: four runs of four dates into one history keep all their rows.
    together = sandbox.path("together", "history.csv")
    os.makedirs(os.path.dirname(together))
    runs = []
    for i in range(4):
        runs.append(run_dir("together-%d" % i, lambda d, i=i: d["provenance"].update(date="2031-01-0%dT00:00:00Z" % (i + 1))))
    script = " & ".join("%s report %s --history %s > /dev/null" % (tool, r, together) for r in runs) + " & wait"

    def all_kept(_):
        dates = [line.split(",")[0] for line in open(together).read().splitlines()[1:]]
        counts = [dates.count("2031-01-0%dT00:00:00Z" % (i + 1)) for i in range(4)]
        return None if counts == [len(rows.splitlines())] * 4 else "rows per recording: %s" % counts
    add("history", "four recordings at once keep every row", ["bash", "-c", script], 0, timeout=60,
        writes=["runs", "together"], check=all_kept)

    # Ctrl-C and SIGTERM while a recording loads, draws or writes: it ends with one line and 128+N,
    # or completes; either way the history holds the whole run or nothing of it.
    for i, (delay, signum) in enumerate(((0.15, signal.SIGINT), (0.6, signal.SIGINT), (1.2, signal.SIGTERM),
                                         (2.0, signal.SIGINT))):
        path = history_file("signal-%d" % i, header + rows.replace("2", "1", 1))
        d = run_dir("signal-%d" % i)

        def whole_or_nothing(r, path=path, before=open(path).read()):
            now = open(path).read()
            if r.rc == 0:
                return None if now.count("\n") == before.count("\n") + len(rows.splitlines()) else "a partial recording"
            return None if now == before else "interrupted, yet the history changed"
        add("history", "%s %.2f s into a recording" % (signal.Signals(signum).name, delay),
            report(d, "--history", path), (0, 128 + signum, -signum), signals=[(delay, signum)], writes=[rel(d),
            rel(os.path.dirname(path))], check=whole_or_nothing)

    # A full disk under the report and under the history (tmpfs, as root).
    def tmpfs(name, size):
        def mount():
            d = sandbox.path(name)
            os.makedirs(d, exist_ok=True)
            if os.geteuid() != 0 or subprocess.run(["mount", "-t", "tmpfs", "-o", "size=%s" % size, "tmpfs", d],
                                                   stderr=subprocess.DEVNULL).returncode:
                raise Skip("no tmpfs can be mounted here (needs root)")
            sandbox.mounts.append(d)
            return d
        return mount

    def full_run():
        d = tmpfs("full-run", "64k")()
        shutil.copy(os.path.join(base, "measurements.json"), d)
    add("history", "report on a full disk: one line, no temporary", report(sandbox.path("full-run")), 1,
        setup=full_run, writes=["full-run"])

    def full_history():
        d = tmpfs("full-history", "8k")()
        shutil.copy(sandbox.path("recorded-history.csv"), os.path.join(d, "history.csv"))
        with open(os.path.join(d, "filler"), "wb") as f:
            try:
                f.write(b"x" * (1 << 20))
            except OSError:
                pass
        before_text[os.path.join(d, "history.csv")] = open(os.path.join(d, "history.csv"), "rb").read()
    d = run_dir("for-full-history", lambda x: x["provenance"].update(date="2032-01-01T00:00:00Z"))
    add("history", "recording on a full disk: one line, history kept", report(d, "--history",
        sandbox.path("full-history", "history.csv")), 1, setup=full_history, writes=[rel(d), "full-history/history.csv.lock"],
        check=unchanged(sandbox.path("full-history", "history.csv")))

    # ------------------------------------------------------------------------------------------
    # 5. The GL worker dies with its client and every wait on it is bounded.
    glsl = [tool, "glsl", "--res", "32", "--size", "32x32", "--threads", "1", "--repetitions", "1", "--layers", "8"]
    bin_dir = sandbox.path("bin")
    os.makedirs(bin_dir)

    def fake_worker(name, body):
        path = os.path.join(bin_dir, name)
        with open(path, "w") as f:
            f.write(body)
        os.chmod(path, 0o755)
        return {"HEIGHTMARCH_GLSL_WORKER": path}
    header_bytes = "import struct, sys, time\nsys.stdout.buffer.write(struct.pack('<IIQ', 0x4c474d48, 1, 1 << 62))\n" \
                   "sys.stdout.flush()\ntime.sleep(100)\n"
    for name, body in (("exits", "#!/bin/sh\nexit 0\n"), ("yes", "#!/bin/sh\nexec yes\n"),
                       ("zeros", "#!/bin/sh\nexec cat /dev/zero\n"),
                       ("huge-message", "#!%s\n%s" % (PYTHON, header_bytes)),
                       ("hangs-up", "#!/bin/sh\nexec 1>&- 0<&-\nexec sleep 100\n")):
        add("worker", "a worker that %s: one line, nothing left running" % name.replace("-", " "), glsl, 1,
            env=fake_worker(name, body), timeout=15)
    add("worker", "a worker that is not there: one line", glsl, 1,
        env={"HEIGHTMARCH_GLSL_WORKER": sandbox.path("bin", "none")}, timeout=15)
    for what, more in (("--gl bogus", ["--gl", "bogus"]), ("--gl-device 99", ["--gl", "egl", "--gl-device", "99"]),
                       ("--gl-device with escapes", ["--gl-device", ESCAPES]),
                       ("--gl osmesa with a device", ["--gl", "osmesa", "--gl-device", "software"])):
        add("worker", "%s: one line" % what, glsl + more, 2, timeout=15)
    shader = sandbox.path("endless.glsl")
    with open(shader, "w") as f:
        f.write(ENDLESS)
    endless = [tool, "glsl", "--shader", shader, "--res", "64", "--size", "256x256", "--threads", "1",
               "--repetitions", "1"]

    def drawing(p):
        """Waits (20 s at most) until p's worker runs, then 1.5 s for it to compile and draw."""
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline and p.poll() is None:
            for entry in os.listdir("/proc"):
                try:
                    with open("/proc/%s/stat" % entry) as f:
                        fields = f.read().split()
                except OSError:
                    continue
                if fields[1].startswith("(heightmarch-gls") and int(fields[3]) == p.pid:
                    time.sleep(1.5)
                    return
            time.sleep(0.05)
    for path, signum in (("egl", signal.SIGKILL), ("osmesa", signal.SIGTERM), ("egl", signal.SIGINT)):
        more = ["--gl", "egl", "--gl-device", "software"] if path == "egl" else ["--gl", "osmesa"]
        add("worker", "%s to the client mid-draw (%s): its worker ends with it" % (signal.Signals(signum).name, path),
            endless + more, (-signum, 128 + signum), signals=[(drawing, signum)], timeout=30)
    add("worker", "SIGTERM to the client while its worker starts: nothing left", glsl + ["--gl", "osmesa"],
        (-15, 143), signals=[(0.3, signal.SIGTERM)], timeout=15)

    # ------------------------------------------------------------------------------------------
    # 6. Signals to the suite, INCOMPLETE runs, and the scripts' arguments.
    suite = [tool, "suite", "--quick", "--techniques", "pom", "--parts", "matrix", "--no-glsl", "--record"]

    def interrupted(cwd):
        def check(_):
            runs = os.listdir(os.path.join(cwd, "results")) if os.path.isdir(os.path.join(cwd, "results")) else []
            if [r for r in runs if r != "latest" and not os.path.exists(os.path.join(cwd, "results", r, "INCOMPLETE"))]:
                return "a run not INCOMPLETE: %s" % runs
            return "recorded into the history" if os.path.exists(os.path.join(cwd, "results", "history.csv")) else None
        return check
    for i, (delay, signum) in enumerate(((0.5, signal.SIGINT), (1.5, signal.SIGHUP), (2.5, signal.SIGTERM))):
        cwd = sandbox.path("suite-%d" % i)
        os.makedirs(cwd)
        add("signals", "%s %.1f s into a recorded suite: exits by it, INCOMPLETE, no history row" % (
            signal.Signals(signum).name, delay), suite, (-signum, 128 + signum), cwd=cwd, signals=[(delay, signum)],
            writes=["suite-%d" % i], timeout=30, check=interrupted(cwd))
    d = run_dir("incomplete-out", files=[("INCOMPLETE", "")])
    add("signals", "suite --out an INCOMPLETE run: refused at once", suite + ["--out", d], 2, timeout=10,
        writes=[rel(d) + "/.lock"])
    d = run_dir("locked")
    holder = subprocess.Popen(["flock", os.path.join(d, ".lock"), "sleep", "600"], start_new_session=True)
    sandbox.holders.append(holder)
    add("signals", "report of a run another process is writing (its .lock held): refused at once", report(d), 2,
        timeout=10, writes=[rel(d)])
    scripts = os.path.join(ROOT, "scripts")
    for what, argv in (("regress REV with escapes", [os.path.join(scripts, "regress"), "HEAD" + ESCAPES]),
                       ("regress REV shaped like an option", [os.path.join(scripts, "regress"), "--output=x"]),
                       ("bisect with $(...) revisions", [os.path.join(scripts, "bisect"), "$(touch pwned)", "HEAD"]),
                       ("compare with no file", [compare, sandbox.path("none.json"), bench])):
        add("signals", "%s: one line" % what, argv, 2, timeout=20, owner="regress", cwd=sandbox.root,
            env={"PYTHONPATH": scripts})
    add("signals", "Ctrl-C of compare: one line", [compare, bench, bench], (0, 130), timeout=20, owner="regress",
        signals=[(0.3, signal.SIGINT)], env={"PYTHONPATH": scripts})
    return out
