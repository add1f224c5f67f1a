#!/usr/bin/python3
"""Opens a sweep's report.html in headless Chromium (Debian's `chromium`), a reader we did not
write, and checks what a person would see: the page renders without errors and fetches nothing,
its screenshot is not blank and shows the plots' colours, and the numbers in the rendered DOM
equal those in summary.json.

usage: check_report_in_chromium.py SWEEP_DIR WORK_DIR   (exit 0 when every check passes)
"""
import json
import os
import subprocess
import sys
from html.parser import HTMLParser

import av  # PyAV: decodes the screenshot PNG through FFmpeg, another reader we did not write
import numpy as np

CHROMIUM = "/usr/bin/chromium"


def chromium(work, *args):
    command = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
               "--user-data-dir=" + os.path.join(work, "profile"), "--enable-logging=stderr", "--v=0",
               "--host-resolver-rules=MAP * ~NOTFOUND", *args]
    return subprocess.run(command, capture_output=True, text=True, timeout=120, check=True)


class CellNumbers(HTMLParser):
    """The text of every <td data-cell data-field>, the success plots' points and any external reference."""

    def __init__(self):
        super().__init__()
        self.fields = {}
        self.circles = 0
        self.svgs = 0
        self.external = []
        self._open = None

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        for key in ("src", "href"):
            if key in attrs:
                self.external.append(attrs[key])
        if tag == "circle" and attrs.get("class") == "success-point":
            self.circles += 1
        if tag == "svg":
            self.svgs += 1
        if tag == "td" and "data-cell" in attrs:
            self._open = (attrs["data-cell"], attrs["data-field"])
            self.fields[self._open] = ""

    def handle_data(self, data):
        if self._open:
            self.fields[self._open] += data

    def handle_endtag(self, tag):
        if tag == "td":
            self._open = None


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def main():
    sweep, work = sys.argv[1], sys.argv[2]
    url = "file://" + os.path.abspath(os.path.join(sweep, "report.html"))
    summary = json.load(open(os.path.join(sweep, "summary.json")))

    dumped = chromium(work, "--dump-dom", url)
    for line in dumped.stderr.splitlines():
        if "CONSOLE" in line or "Uncaught" in line or "Failed to load resource" in line or "net::ERR" in line:
            fail("the page logged an error: " + line)
    page = CellNumbers()
    page.feed(dumped.stdout)
    if page.external:
        fail("the report refers to other files or the network: %s" % page.external[:3])

    cells = summary["cells"]
    if len({cell for cell, _ in page.fields}) != len(cells):
        fail("the DOM shows %d cells, summary.json has %d" % (len({c for c, _ in page.fields}), len(cells)))
    checked = 0
    for cell in cells:
        def shown(field):
            key = (cell["id"], field)
            if key not in page.fields:
                fail("no %s for cell %s in the DOM" % (field, cell["id"]))
            return page.fields[key].strip()

        for field in ("n_episodes", "n_successful"):
            if int(shown(field)) != cell[field]:
                fail("%s %s: DOM %s, summary.json %s" % (cell["id"], field, shown(field), cell[field]))
        for field in ("success_rate", "ci_low", "ci_high"):
            if abs(float(shown(field)) - 100.0 * cell[field]) > 0.05 + 1e-9:
                fail("%s %s: DOM %s %%, summary.json %r" % (cell["id"], field, shown(field), cell[field]))
        expected = cell["galt"]["mean_s"] if cell["galt"] else None
        if (expected is None) != (shown("galt_mean_s") == "-") or (expected is not None and abs(float(shown("galt_mean_s")) - expected) > 0.005 + 1e-9):
            fail("%s GALT mean: DOM %s, summary.json %r" % (cell["id"], shown("galt_mean_s"), expected))
        checked += 1
    points = sum(1 for suite in summary["success"] for column in suite["columns"] for row in column["tasks"] if "success_rate" in row)
    if page.circles != points:
        fail("the success plots show %d points, summary.json has %d pooled cells" % (page.circles, points))

    shot = os.path.join(work, "report.png")
    chromium(work, "--screenshot=" + shot, "--window-size=1200,1400", url)
    with av.open(shot) as container:
        image = next(container.decode(video=0)).to_ndarray(format="rgb24").astype(int)
    not_white = np.any(image < 245, axis=2).mean()
    colours = len(np.unique(image.reshape(-1, 3), axis=0))
    # The id split's blue (#1f77b4) of the success plot, and the histograms' fills.
    blue = (np.abs(image - np.array([0x1f, 0x77, 0xb4])).sum(axis=2) < 30).sum()
    if not_white < 0.01 or colours < 16 or blue < 20:
        fail("the screenshot looks blank: %.3f of it not white, %d colours, %d blue pixels" % (not_white, colours, blue))
    print("report ok: %d cells' numbers equal summary.json, %d plot points, %d svg plots, screenshot %dx%d with %.1f%% ink, %d colours"
          % (checked, points, page.svgs, image.shape[1], image.shape[0], 100 * not_white, colours))


if __name__ == "__main__":
    main()
