#!/usr/bin/python3
"""Opens the report.html of a run whose maps are named with markup in headless Chromium and checks
that no name runs as script and the page still draws.

Usage: check_page_injection.py RUN_DIR

The names (test_hostile_names.sh) carry `<img src=x onerror=window.__pwned=1;document.title='PWN'>`
and `<!--<script>`: the page must draw (its script ran to the end: body[data-ready]), every row of
the recommendation's table is clicked and must open its configuration below and bring it into
view, the first point of every frontier chart is clicked and hovered; then window.__pwned must be
unset, the title untouched, no console error (an <img src=x> that was made would fail to load),
and every name shown as text somewhere on the page.
"""
from check_report_page import Browser, Failure, main
from heightmarch_tools.readers import read_json, run_file

ROWS = "document.querySelectorAll('table.recommendation tr').length - 1"
CLICK_ROW = """(() => {
  const tr = document.querySelectorAll('table.recommendation tr')[%d];
  tr.click();
  const detail = document.getElementById('detail'), box = detail.getBoundingClientRect();
  return {shown: (detail.querySelector('h3') || {}).textContent || '', top: box.top, height: window.innerHeight};
})()"""
POINTS = """(() => [...document.querySelectorAll('.frontier-chart')].map(div => {
  const point = div.querySelector('.scatterlayer .trace path.point');
  point.scrollIntoView({block: 'center'});
  const box = point.getBoundingClientRect();
  return {x: box.left + box.width / 2, y: box.top + box.height / 2};
}))()"""


def check(run_dir):
    data = read_json(run_file(run_dir, "measurements.json"))
    labels = sorted({r["heightfield"]["label"] for r in data["rows"]})
    browser = Browser()
    try:
        browser.open_report(run_dir)  # drawn: its script ran to the end
        title = browser.evaluate("document.title")
        rows = browser.evaluate(ROWS)
        if rows < 1:
            raise Failure("the recommendation's table has no row")
        for i in range(1, rows + 1):
            opened = browser.evaluate(CLICK_ROW % i)
            if not opened["shown"] or not 0 <= opened["top"] < opened["height"]:
                raise Failure("clicking row %d of the recommendation opens %r at %d px, outside the %d px window" % (
                    i, opened["shown"], opened["top"], opened["height"]))
        points = browser.evaluate(POINTS)
        for p in points:
            browser.call("Input.dispatchMouseEvent", type="mouseMoved", x=p["x"], y=p["y"])
            browser.call("Input.dispatchMouseEvent", type="mousePressed", x=p["x"], y=p["y"], button="left", clickCount=1)
            browser.call("Input.dispatchMouseEvent", type="mouseReleased", x=p["x"], y=p["y"], button="left", clickCount=1)
        browser.evaluate("new Promise(done => setTimeout(done, 300))")  # a payload's image load, had one been made
        if browser.evaluate("window.__pwned") is not None or browser.evaluate("document.title") != title or "PWN" in title:
            raise Failure("a map's name ran as script (window.__pwned set or the title changed)")
        text = browser.evaluate("document.body.innerText")
        missing = [label for label in labels if label.replace("\n", " ") not in text.replace("\n", " ")
                   and label not in text]
        if missing:
            raise Failure("names not shown as text: %s" % missing)
        browser.check_no_errors()  # an <img src=x> made of a name would fail to load
        print("ok: report.html with maps named with markup: drawn, %d recommendation rows clicked (each opens its "
              "configuration in view), %d frontier points clicked, no script ran, every name shown as text" % (
                  rows, len(points)))
    finally:
        browser.close()


if __name__ == "__main__":
    main(check, __doc__)
