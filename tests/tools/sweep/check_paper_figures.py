#!/usr/bin/python3
"""Reads a sweep's paper products back and compares them with summary.json: every figure's SVG
(figures/*.svg, parsed as XML: the data-* numbers of its bars, dots, bins and medians), its PNG
(decoded by PyAV: the SVG's size, not blank), the same SVGs inside report.html, the gaze figures'
(figures/gaze_*.svg) numbers against summary.json's gaze_figures, Table 1's LaTeX
per label, and the headline table.

usage: check_paper_figures.py SWEEP_DIR   (prints "figures ok: ..." and exits 0 when all agree)
"""
import json
import os
import sys
import xml.etree.ElementTree as ET

import av
import numpy as np

SVG = "{http://www.w3.org/2000/svg}"
EXPECTED = {"fig3a": "fig3a_head_vs_fixed", "fig3b": "fig3b_single_vs_multi", "fig3c": "fig3c_splits",
            "fig3d": "fig3d_ablation", "fig4": "fig4_galt"}


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def close(a, b, what):
    if abs(float(a) - float(b)) > 1e-5:
        fail("%s: SVG %s, summary.json %s" % (what, a, b))


def marks(root, attribute):
    return [e.attrib for e in root.iter() if e.tag in (SVG + "rect", SVG + "circle", SVG + "line") and "data-" + attribute in e.attrib]


def check_bars(root, bars, fields, name):
    drawn = marks(root, "value")
    expected = [(bar, field) for bar in bars for field in fields if bar[field] is not None]
    if len(drawn) != len(expected):
        fail("%s draws %d bars, summary.json has %d" % (name, len(drawn), len(expected)))
    for mark, (bar, field) in zip(drawn, expected):
        if mark["data-suite"] != bar["suite"] or mark["data-robot"] != bar["robot"]:
            fail("%s: bar of %s %s where summary.json has %s %s" % (name, mark["data-suite"], mark["data-robot"], bar["suite"], bar["robot"]))
        close(mark["data-value"], bar[field]["mean"], "%s %s %s %s" % (name, bar["suite"], bar["robot"], field))
        close(mark["data-std"], bar[field]["std"], "%s %s %s %s spread" % (name, bar["suite"], bar["robot"], field))
    return len(drawn)


def check_figure(key, data, root):
    if key == "fig3a":
        dots = marks(root, "value")
        expected = [(p, camera) for p in data["points"] for camera in ("head", "fixed")]
        if len(dots) != len(expected):
            fail("fig3a draws %d dots, summary.json has %d" % (len(dots), len(expected)))
        # Drawn a panel per robot: match each dot by its task, robot and camera.
        by_key = {(d["data-task"], d["data-robot"], d["data-camera"]): d for d in dots}
        for point, camera in expected:
            dot = by_key.get((point["task"], point["robot"], camera))
            if dot is None:
                fail("fig3a: no dot for %s %s %s" % (point["task"], point["robot"], camera))
            close(dot["data-value"], point[camera]["mean"], "fig3a %s %s %s" % (point["task"], point["robot"], camera))
        return len(dots)
    if key == "fig3b":
        return check_bars(root, data["bars"], ("single", "multi"), key)
    if key == "fig3c":
        return check_bars(root, data["bars"], ("id", "ood-spatial", "ood-init-pose"), key)
    if key == "fig3d":
        bars = marks(root, "arm")
        for arm in data["arms"]:
            means = [b for b in bars if b["data-robot"] == "mean" and b["data-arm"] == arm["arm"]]
            if len(means) != (arm["mean_over_robots"] is not None):
                fail("fig3d: %s's mean drawn %d times" % (arm["arm"], len(means)))
            if means:
                close(means[0]["data-value"], arm["mean_over_robots"], "fig3d %s mean" % arm["arm"])
            for entry in arm["per_robot"]:
                found = [b for b in bars if b["data-arm"] == arm["arm"] and b["data-robot"] == entry["robot"]]
                if len(found) != 1:
                    fail("fig3d: %s %s drawn %d times" % (arm["arm"], entry["robot"], len(found)))
                close(found[0]["data-value"], entry["rate"]["mean"], "fig3d %s %s" % (arm["arm"], entry["robot"]))
        return len(bars)
    if key == "fig4":
        bins = marks(root, "count")
        medians = marks(root, "median")
        checked = 0
        for row in data["tasks"]:
            for series in ("policy", "reference"):
                if row[series] is None:
                    continue
                # The panels are drawn in task order; each series' bins in bin order.
                start = checked
                counts = [int(b["data-count"]) for b in bins[start:start + data["bins"]["count"]]]
                if [b["data-series"] for b in bins[start:start + data["bins"]["count"]]] != [series] * data["bins"]["count"]:
                    fail("fig4 %s: the %s bins are not where expected" % (row["task"], series))
                if counts != row[series]["counts"]:
                    fail("fig4 %s %s: SVG counts %s, summary.json %s" % (row["task"], series, counts, row[series]["counts"]))
                checked += data["bins"]["count"]
                if row[series]["median"] is not None:
                    found = [m for m in medians if m["data-task"] == row["task"] and m["data-series"] == series]
                    if len(found) != 1:
                        fail("fig4 %s %s: %d median markers" % (row["task"], series, len(found)))
                    close(found[0]["data-median"], row[series]["median"], "fig4 %s %s median" % (row["task"], series))
        return checked
    fail("unknown figure " + key)


GAZE = {"galt_verified": "gaze_galt_verified", "anchors": "gaze_anchors", "gaze_on_target": "gaze_on_target"}


def check_gaze_figure(key, data, root):
    """A gaze figure's data-* numbers against summary.json's gaze_figures (gaze_figures.h)."""
    if key == "galt_verified":
        bins = marks(root, "count")
        medians = marks(root, "median")
        count, checked = data["bins"]["count"], 0
        for row in data["tasks"]:
            for series in ("verified", "unverified"):
                drawn = bins[checked:checked + count]
                if [b["data-series"] for b in drawn] != [series] * count:
                    fail("gaze_galt_verified %s: the %s bins are not where expected" % (row["task"], series))
                if [int(b["data-count"]) for b in drawn] != row[series]["counts"]:
                    fail("gaze_galt_verified %s %s: SVG counts %s, summary.json %s"
                         % (row["task"], series, [b["data-count"] for b in drawn], row[series]["counts"]))
                checked += count
                median = row[series]["median"]
                found = [m for m in medians if m["data-task"] == row["task"] and m["data-series"] == series]
                if median is not None and data["bins"]["low"] <= median <= data["bins"]["high"]:
                    if len(found) != 1:
                        fail("gaze_galt_verified %s %s: %d median markers" % (row["task"], series, len(found)))
                    close(found[0]["data-median"], median, "gaze_galt_verified %s %s median" % (row["task"], series))
        return checked
    if key == "anchors":
        boxes = marks(root, "anchor")
        if len(boxes) != len(data["rows"]):
            fail("gaze_anchors draws %d boxes, summary.json has %d rows" % (len(boxes), len(data["rows"])))
        for box, row in zip(boxes, data["rows"]):
            what = "gaze_anchors %s %s %s" % (row["task"], row["robot"], row["anchor"])
            if (box["data-task"], box["data-robot"], box["data-anchor"]) != (row["task"], row["robot"], row["anchor"]):
                fail("%s: the box drawn is %s %s %s" % (what, box["data-task"], box["data-robot"], box["data-anchor"]))
            for key_ in ("median", "q1", "q3"):
                close(box["data-" + key_], row[key_ + "_s"], what + " " + key_)
            if int(box["data-n"]) != row["n"]:
                fail("%s: n %s, summary.json %d" % (what, box["data-n"], row["n"]))
        return 4 * len(boxes)
    if key == "gaze_on_target":
        bars = marks(root, "value")
        expected = [(g, b) for g in data["groups"] for b in g["bars"]]
        if len(bars) != len(expected):
            fail("gaze_on_target draws %d bars, summary.json has %d" % (len(bars), len(expected)))
        by_key = {(b["data-task"], b["data-robot"], b["data-series"]): b for b in bars}
        for group, bar in expected:
            drawn = by_key.get((group["task"], group["robot"], bar["series"]))
            if drawn is None:
                fail("gaze_on_target: no bar for %s %s %s" % (group["task"], group["robot"], bar["series"]))
            close(drawn["data-value"], bar["value"], "gaze_on_target %s %s %s" % (group["task"], group["robot"],
                                                                                  bar["series"]))
        return len(bars)
    fail("unknown gaze figure " + key)


def check_png(path, svg_root):
    with av.open(path) as container:
        image = next(container.decode(video=0)).to_ndarray(format="rgb24").astype(int)
    if (image.shape[1], image.shape[0]) != (int(svg_root.attrib["width"]), int(svg_root.attrib["height"])):
        fail("%s is %dx%d, its SVG %sx%s" % (path, image.shape[1], image.shape[0], svg_root.attrib["width"], svg_root.attrib["height"]))
    ink = np.any(image < 200, axis=2).mean()
    colours = len(np.unique(image.reshape(-1, 3), axis=0))
    if ink < 0.005 or colours < 8:
        fail("%s looks blank: %.4f ink, %d colours" % (path, ink, colours))


def main():
    sweep = sys.argv[1]
    summary = json.load(open(os.path.join(sweep, "summary.json")))
    report = open(os.path.join(sweep, "report.html")).read()
    figures = summary["figures"]
    drawn = 0
    numbers = 0
    for key, name in EXPECTED.items():
        path = os.path.join(sweep, "figures", name + ".svg")
        if figures[key] is None:
            if os.path.exists(path):
                fail("%s drawn but summary.json has no data for it" % name)
            continue
        svg_text = open(path).read()
        root = ET.fromstring(svg_text)
        numbers += check_figure(key, figures[key], root)
        if svg_text.strip() not in report:
            fail("report.html does not hold %s.svg" % name)
        check_png(os.path.join(sweep, "figures", name + ".png"), root)
        drawn += 1
    gaze_figures = summary.get("gaze_figures") or {}
    for key, name in GAZE.items():
        path = os.path.join(sweep, "figures", name + ".svg")
        if gaze_figures.get(key) is None:
            if os.path.exists(path):
                fail("%s drawn but summary.json has no data for it" % name)
            continue
        svg_text = open(path).read()
        root = ET.fromstring(svg_text)
        numbers += check_gaze_figure(key, gaze_figures[key], root)
        if svg_text.strip() not in report:
            fail("report.html does not hold %s.svg" % name)
        check_png(os.path.join(sweep, "figures", name + ".png"), root)
        drawn += 1
    for label in summary["labels"]:
        latex = open(os.path.join(sweep, "tables", "table1_%s.tex" % label["label"])).read()
        for suite in summary["success"]:
            if suite["label"] != label["label"]:
                continue
            for column in suite["columns"]:
                for row in column["tasks"]:
                    if "success_rate" in row and ("%.1f" % (100 * row["success_rate"])) not in latex:
                        fail("table1_%s.tex lacks %s's %.1f" % (label["label"], row["task"], 100 * row["success_rate"]))
                if ("%.1f" % (100 * column["task_average"])) not in latex:
                    fail("table1_%s.tex lacks the suite mean %.1f" % (label["label"], 100 * column["task_average"]))
    headline = open(os.path.join(sweep, "tables", "headline.md")).read()
    values = []
    for key in ("q1_ablation",):
        if summary["headline"][key] is not None:
            values += [v for v in summary["headline"][key].values() if v is not None]
    for key in ("q2_single_vs_multi", "q3_splits"):
        for row in summary["headline"][key] or []:
            values += [v for k, v in row.items() if k not in ("suite", "robots") and v is not None]
    for value in values:
        if ("| %.1f |" % (100 * value)) not in headline:
            fail("headline.md lacks %.1f" % (100 * value))
    print("figures ok: %d figures, %d drawn numbers equal summary.json, %d headline numbers, %d Table 1 files"
          % (drawn, numbers, len(values), len(summary["labels"])))


if __name__ == "__main__":
    main()
