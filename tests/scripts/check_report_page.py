#!/usr/bin/python3
"""Opens a run's report.html in headless Chromium and checks it as a reader meets it.

Usage: check_report_page.py RUN_DIR SCREENSHOT.png

Drives Debian's chromium over the DevTools protocol (python3-websocket): fails on any console
error, uncaught exception or failed load (a missing image included); checks that the technique
filter offers the techniques the run measured and no other, that the frontier
draws exactly the configurations its filters select, one point each (the ids drawn against the
rows of measurements.json the filters name); hovers a point and checks the label names that
point's configuration; clicks it and checks its figures are shown; saves a screenshot of the
page's first screen. Prints the time the page took to be drawn.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

import websocket

from heightmarch_tools.measurements import backend_label, depth_map, load_run, view_name

CHROMIUM = os.environ.get("HEIGHTMARCH_CHROMIUM", "/usr/bin/chromium")
# As root on a closed network: no sandbox, no GPU, and nothing that phones home (its connections
# would be refused and reported as errors).
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--remote-debugging-port=0", "--window-size=1400,1000"]
TIMEOUT = 90  # seconds for any one wait


class Failure(Exception):
    pass


class Browser:
    def __init__(self):
        self.profile = tempfile.mkdtemp(prefix="heightmarch-chromium-")
        self.process = subprocess.Popen([CHROMIUM] + FLAGS + ["--user-data-dir=" + self.profile, "about:blank"],
                                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        port_file = os.path.join(self.profile, "DevToolsActivePort")
        deadline = time.time() + TIMEOUT
        while not os.path.exists(port_file) or not open(port_file).read().strip():
            if time.time() > deadline or self.process.poll() is not None:
                raise Failure("chromium did not start (%s)" % CHROMIUM)
            time.sleep(0.1)
        port = open(port_file).read().split()[0]
        pages = json.load(urllib.request.urlopen("http://127.0.0.1:%s/json/list" % port, timeout=TIMEOUT))
        page = next(p for p in pages if p.get("type") == "page")
        self.socket = websocket.create_connection(page["webSocketDebuggerUrl"], timeout=TIMEOUT)
        self.next_id = 0
        self.events = []

    def call(self, method, **params):
        self.next_id += 1
        self.socket.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        deadline = time.time() + TIMEOUT
        while time.time() < deadline:
            message = json.loads(self.socket.recv())
            if message.get("id") == self.next_id:
                if "error" in message:
                    raise Failure("%s: %s" % (method, message["error"]))
                return message.get("result", {})
            self.events.append(message)
        raise Failure("%s: no answer" % method)

    def evaluate(self, expression):
        result = self.call("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in result:
            raise Failure("%s: %s" % (expression[:60], result["exceptionDetails"]))
        return result["result"].get("value")

    def wait_for(self, expression, what):
        deadline = time.time() + TIMEOUT
        while time.time() < deadline:
            value = self.evaluate(expression)
            if value:
                return value
            time.sleep(0.05)
        raise Failure("timed out waiting for %s" % what)

    def errors(self):
        """Console errors, uncaught exceptions and failed loads seen so far."""
        out = []
        for e in self.events:
            method, params = e.get("method"), e.get("params", {})
            if method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
                out.append("console: " + " ".join(str(a.get("value", a.get("description", ""))) for a in params.get("args", [])))
            elif method == "Runtime.exceptionThrown":
                details = params.get("exceptionDetails", {})
                out.append("exception: " + str(details.get("exception", {}).get("description") or details.get("text")))
            elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
                entry = params["entry"]
                out.append("log: %s %s" % (entry.get("text"), entry.get("url", "")))
        return out

    def open_report(self, run_dir):
        """Opens RUN_DIR/report.html at 1400x1000 and waits until its script has drawn it; the ms it took."""
        for domain in ("Runtime", "Log", "Page"):
            self.call(domain + ".enable")
        self.call("Emulation.setDeviceMetricsOverride", width=1400, height=1000, deviceScaleFactor=1, mobile=False)
        self.call("Page.navigate", url="file://" + os.path.abspath(os.path.join(run_dir, "report.html")))
        return int(self.wait_for("document.body && document.body.dataset.ready", "the page to be drawn"))

    def check_no_errors(self):
        errors = self.errors()
        if errors:
            raise Failure("%d console error(s), the first: %s" % (len(errors), errors[0]))

    def close(self):
        try:
            self.socket.close()
        finally:
            self.process.terminate()
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.process.kill()
            shutil.rmtree(self.profile, ignore_errors=True)


def expected_ids(run, state):
    """The rows the page's filters select, from measurements.json (its own reading of the filters)."""
    sizes = {}
    for r in run.rows:
        sizes.setdefault(r["heightfield"]["label"], set()).add(depth_map(r))
    out = set()
    for r in run.rows:
        if r.get("technique") not in run.style or not r.get("errors") or r.get("failure"):
            continue
        hf = r["heightfield"]["label"] + (" (%s)" % depth_map(r) if len(sizes[r["heightfield"]["label"]]) > 1 else "")
        cost = r.get("speed") if state["cost"] == "ns_per_ray" else r.get("samples_per_ray")
        if (hf in state["heightfield"] and r["technique"] in state["technique"] and backend_label(r) == state["backend"]
                and (state["threads"] == "all" or str(r["threads"]) == state["threads"])
                and view_name(r["view"]) == state["view"] and cost is not None
                and r["errors"].get(state["measure"]) is not None):
            out.add(r["id"])
    return out


STATE = """(() => {
  const checked = name => [...document.querySelectorAll(`#filter-${name} input:checked`)].map(i => i.value);
  const value = name => document.getElementById(`filter-${name}`).value;
  return {heightfield: checked("heightfield"), technique: checked("technique"), backend: value("backend"),
          threads: value("threads"), view: value("view"), measure: value("measure"), cost: value("cost")};
})()"""

# Per chart, the row ids of its configuration traces (uid cfg-*), and the number of points drawn.
DRAWN = """(() => [...document.querySelectorAll('.frontier-chart')].map(div => {
  const traces = [...div.querySelectorAll('.scatterlayer .trace')];
  const ids = [], drawn = [];
  div.data.forEach((t, i) => {
    if (!String(t.uid).startsWith('cfg-')) return;
    ids.push(...t.customdata);
    drawn.push(traces[i].querySelectorAll('path.point').length);
  });
  return {ids, drawn: drawn.reduce((a, b) => a + b, 0)};
}))()"""

# The centre of the first configuration point of the first chart, and its row id.
FIRST_POINT = """(() => {
  const div = document.querySelector('.frontier-chart');
  const index = div.data.findIndex(t => String(t.uid).startsWith('cfg-'));
  const point = div.querySelectorAll('.scatterlayer .trace')[index].querySelector('path.point');
  point.scrollIntoView({block: 'center'});
  const box = point.getBoundingClientRect();
  return {x: box.left + box.width / 2, y: box.top + box.height / 2, id: div.data[index].customdata[0]};
})()"""


def check(run_dir, screenshot):
    run = load_run(run_dir)
    browser = Browser()
    try:
        ready_ms = browser.open_report(run_dir)
        state = browser.evaluate(STATE)
        measured = {r["technique"] for r in run.rows if r.get("technique") in run.style}
        if set(state["technique"]) != measured:
            raise Failure("the technique filter offers %s, the run measured %s" % (sorted(state["technique"]), sorted(measured)))
        charts = browser.evaluate(DRAWN)
        drawn_ids = [i for c in charts for i in c["ids"]]
        want = expected_ids(run, state)
        if not want:
            raise Failure("the default filters select no configuration: %s" % state)
        if len(drawn_ids) != len(set(drawn_ids)) or set(drawn_ids) != want:
            raise Failure("the frontier draws %d points for %d configurations (missing %s, extra %s)" % (
                len(drawn_ids), len(want), sorted(want - set(drawn_ids))[:5], sorted(set(drawn_ids) - want)[:5]))
        if sum(c["drawn"] for c in charts) != len(want):
            raise Failure("the charts' SVG holds %d points for %d configurations" % (sum(c["drawn"] for c in charts), len(want)))
        print("ok: the frontier draws one point per configuration: %d configurations in %d charts (%s, %s threads, %s)" % (
            len(want), len(charts), state["backend"], state["threads"], state["view"]))

        point = browser.evaluate(FIRST_POINT)
        browser.call("Input.dispatchMouseEvent", type="mouseMoved", x=point["x"], y=point["y"])
        text = browser.wait_for("(document.querySelector('.hoverlayer .hovertext') || {}).textContent",
                                "a hover label on row %d" % point["id"])
        # Points of equal figures lie on each other (parallax and parallax-limited on a flat run): the
        # label names the one Plotly takes, which must be a drawn configuration under the mouse's point.
        hovered = re.search(r"\(row (\d+)\)", text)
        if not hovered or int(hovered.group(1)) not in set(drawn_ids):
            raise Failure("hovering row %d shows %r, no drawn configuration" % (point["id"], text))
        row = run.by_id[int(hovered.group(1))]
        for part in ("(row %d)" % row["id"], run.label(row), "%s, %d thread" % (backend_label(row), row["threads"])):
            if part not in text:
                raise Failure("hovering row %d shows %r, without %r" % (row["id"], text, part))
        print("ok: hovering a point shows its configuration: %s" % text[:120])

        browser.call("Input.dispatchMouseEvent", type="mousePressed", x=point["x"], y=point["y"], button="left", clickCount=1)
        browser.call("Input.dispatchMouseEvent", type="mouseReleased", x=point["x"], y=point["y"], button="left", clickCount=1)
        detail = browser.wait_for("(document.querySelector('#detail h3') || {}).textContent", "the clicked point's detail")
        if run.label(row) not in detail:
            raise Failure("clicking row %d shows %r" % (row["id"], detail))
        print("ok: clicking it shows its figures: %s" % detail)

        browser.evaluate("document.getElementById('frontier').scrollIntoView()")
        time.sleep(0.3)  # images decoding after the scroll
        shot = browser.call("Page.captureScreenshot", format="png")
        with open(screenshot, "wb") as f:
            import base64
            f.write(base64.b64decode(shot["data"]))
        browser.check_no_errors()
        size = os.path.getsize(os.path.join(run_dir, "report.html"))
        print("ok: no console error; drawn %d ms after it started loading (%.1f MB, %d rows); screenshot %s" % (
            ready_ms, size / 1e6, len(run.rows), screenshot))
    finally:
        browser.close()


def main(check, doc):
    """Runs check(*arguments) as a command: its usage (doc's third line) without the right number
    of arguments, FAIL and exit 1 on a Failure."""
    arguments = sys.argv[1:]
    if len(arguments) != check.__code__.co_argcount:
        print(doc.strip().splitlines()[2], file=sys.stderr)
        sys.exit(2)
    try:
        check(*arguments)
    except Failure as e:
        print("FAIL: report.html: %s" % e)
        sys.exit(1)


if __name__ == "__main__":
    main(check, __doc__)
