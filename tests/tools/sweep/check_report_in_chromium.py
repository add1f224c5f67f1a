#!/usr/bin/python3
"""Opens a sweep's report.html in headless Chromium (Debian's `chromium`), a reader we did not
write, and checks what a person would see: the page renders without errors and fetches nothing,
its screenshot is not blank and shows the plots' colours, and every table of the page, read as a
person reads it (each value under its column's heading, th text by column index, colspan
honoured), holds the numbers of summary.json, which this script formats itself.

With --table MD LABEL it also reads `tavis table`'s Markdown MD (made from the sweep's cells of
policy label LABEL) the same way: every row has as many cells as its table has headings, and
each value under a heading equals the sweep's summary.json.

usage: check_report_in_chromium.py SWEEP_DIR WORK_DIR [--table MD LABEL]   (exit 0 when every check passes)
"""
import json
import os
import subprocess
import sys
from html.parser import HTMLParser

import av  # PyAV: decodes the screenshot PNG through FFmpeg, another reader we did not write
import numpy as np

CHROMIUM = "/usr/bin/chromium"
# The camera protocols in the order the funnel puts them side by side.
CAMERAS = ["head", "fixed", "head-only", "wrists-only", "fixed-only"]


def chromium(work, *args):
    command = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
               "--user-data-dir=" + os.path.join(work, "profile"), "--enable-logging=stderr", "--v=0",
               "--host-resolver-rules=MAP * ~NOTFOUND", *args]
    return subprocess.run(command, capture_output=True, text=True, timeout=120, check=True)


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


class Page(HTMLParser):
    """Every <table> as the title a reader sees above it (its <h3>) and rows of (tag, text, colspan)
    cells; the success plots' points, svgs and any external reference."""

    def __init__(self):
        super().__init__()
        self.tables = []
        self.circles = 0
        self.svgs = 0
        self.external = []
        self._cell = None
        self._heading = None
        self._title = ""

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        for key in ("src", "href"):
            if key in attrs:
                self.external.append(attrs[key])
        if tag == "circle" and attrs.get("class") == "success-point":
            self.circles += 1
        if tag == "svg":
            self.svgs += 1
        if tag == "h3":
            self._heading = ""
        if tag == "table":
            self.tables.append({"id": " ".join(self._title.split()), "rows": []})
        if tag == "tr" and self.tables:
            self.tables[-1]["rows"].append([])
        if tag in ("th", "td") and self.tables:
            self._cell = [tag, "", int(attrs.get("colspan") or 1)]
            self.tables[-1]["rows"][-1].append(self._cell)

    def handle_data(self, data):
        if self._cell is not None:
            self._cell[1] += data
        if self._heading is not None:
            self._heading += data

    def handle_endtag(self, tag):
        if tag in ("th", "td"):
            self._cell = None
        if tag == "h3":
            self._title, self._heading = self._heading, None


def expand(cells):
    """A row's texts by column index: a cell spanning n columns stands under each of them."""
    texts = []
    for _, text, span in cells:
        texts.extend([" ".join(text.split())] * span)
    return texts


def as_shown(table):
    """A page table as a person reads it: the heading row's texts, and per row its values by heading."""
    rows = table["rows"]
    if not rows or any(tag != "th" for tag, _, _ in rows[0]):
        fail("table %s has no heading row" % table["id"])
    headings = expand(rows[0])
    shown = []
    for number, row in enumerate(rows[1:], 1):
        if any(tag != "td" for tag, _, _ in row):
            fail("table %s row %d mixes headings into its values" % (table["id"], number))
        values = expand(row)
        if len(values) != len(headings):
            fail("table %s row %d has %d values under %d headings %s: %s"
                 % (table["id"], number, len(values), len(headings), headings, values))
        shown.append(values)
    return headings, shown


# summary.json's numbers, printed as the tables print them.
def pct(fraction):
    return "%.1f" % (100.0 * fraction)


def points(difference):
    return "-" if difference is None else "%+.1f" % (100.0 * difference)


def seconds(value):
    return "-" if value is None else "%.2f" % value


def pvalue(p):
    return "%.3g" % p


def rate_text(rate):
    if "success_rate" not in rate:
        return "-"
    return "%s [%s, %s]" % (pct(rate["success_rate"]), pct(rate["ci_low"]), pct(rate["ci_high"]))


def share(count, episodes):
    return "-" if count is None or episodes <= 0 else pct(count / episodes)


def success_tables(summary):
    several = len(summary["labels"]) > 1
    tables = {}
    for suite in summary["success"]:
        columns, differences = suite["columns"], suite["id_minus_ood"]
        headings = ["task"] + ["%s %s %s" % (c["robot"], c["split"], c["camera"]) for c in columns]
        headings += ["%s %s id - %s" % (d["robot"], d["camera"], d["ood_split"]) for d in differences]
        rows = []
        for t in range(len(columns[0]["tasks"])):
            rows.append([columns[0]["tasks"][t]["task"]] + [rate_text(c["tasks"][t]) for c in columns]
                        + [points(d["tasks"][t]) for d in differences])
        rows.append([suite["title"] + " mean (task average)"] + [pct(c["task_average"]) for c in columns]
                    + [points(d["task_average"]) for d in differences])
        rows.append([suite["title"] + " mean (pooled over episodes)"] + [rate_text(c["pooled"]) for c in columns]
                    + [points(d["pooled"]) for d in differences])
        name = "success_" + suite["suite"] + ("_" + suite["label"] if several else "")
        tables[name] = (headings, rows)
    return tables


def funnel_tables(rows):
    cameras = [c for c in CAMERAS if any(r["camera"] == c for r in rows)]
    cameras += [r["camera"] for r in rows if r["camera"] not in cameras]
    headings = ["policy", "task", "robot", "split", "stage"]
    for camera in cameras:
        headings += [camera + " %", camera + " alone %"]
    groups = {}
    for row in rows:
        groups.setdefault((row["label"], row["task"], row["robot"], row["split"]), {})[row["camera"]] = row
    funnel = []
    for key, by_camera in groups.items():
        stages = next(([s["stage"] for s in r["stages"]] for r in by_camera.values() if r["stages"]), [])
        for stage in stages:
            values = list(key) + [stage]
            for camera in cameras:
                row = by_camera.get(camera)
                step = next((s for s in row["stages"] if s["stage"] == stage), None) if row else None
                for count in ("reached", "reached_alone"):
                    if step is None:
                        values.append("-")
                    elif not step.get("applies", True):
                        values.append("n/a")
                    else:
                        values.append(share(step.get(count), row["episodes"]))
            funnel.append(values)
    episodes = [[r["label"], r["task"], r["robot"], r["split"], r["camera"], str(r["episodes"]),
                 share(r["successes"], r["episodes"]), str(r["simulator_faults"])] for r in rows]
    return {"stage_funnel": (headings, funnel),
            "stage_funnel_episodes": (["policy", "task", "robot", "split", "camera", "episodes", "success %",
                                       "simulator faults"], episodes)}


EVENTS = ["wrong_object_touched", "wrong_object_lifted", "target_dropped", "object_knocked_over",
          "object_out_of_workspace", "gripper_table_contact", "both_arms_moved", "opposite_arm_used",
          "reach_before_cue", "reach_before_go", "cue_never_fixated", "target_never_fixated", "time_out_still",
          "time_out_moving"]


def event_tables(rows):
    """The failure events (each event's heading over its count, n/a where it cannot fire) and the
    motion quality medians, formatted here from summary.json's "failure_events"."""
    def fixed(value, decimals):
        return "-" if value is None else "%.*f" % (decimals, value)
    events = [[r["label"], r["task"], r["robot"], r["split"], r["camera"], str(r["episodes"])]
              + ["n/a" if r["events"][e] is None else str(r["events"][e]) for e in EVENTS] for r in rows]
    motion = [[r["label"], r["task"], r["robot"], r["split"], r["camera"]]
              + [fixed(r["motion"][hand][key], decimals) for hand in ("left", "right")
                 for key, decimals in (("path_m", 3), ("jerk_rms", 1), ("sparc", 2))] for r in rows]
    return {"failure_events": (["policy", "task", "robot", "split", "camera", "episodes"] + EVENTS, events),
            "motion_quality": (["policy", "task", "robot", "split", "camera", "left path m", "left jerk m/s^3",
                                "left SPARC", "right path m", "right jerk m/s^3", "right SPARC"], motion)}


GAZE_HEADINGS = ["policy", "task", "robot", "split", "camera", "successful", "with GALT", "verified", "verified %",
                 "verified median s", "gaze on target %", "cue before reach %"]
ANCHOR_HEADINGS = ["policy", "task", "robot", "split", "camera", "anchor", "fixation", "event", "n", "missing",
                   "median s", "q1 s", "q3 s", "IQR s"]


def gaze_tables(rows):
    """The gaze table (verified GALT, gaze on target, look before reach) and the anchor table (each
    task's anchors: n, missing, median and quartiles), formatted here from summary.json's "gaze"."""
    def share(fraction):
        return "-" if fraction is None else pct(fraction)
    gaze, anchors = [], []
    for r in rows:
        g = r["gaze"]
        setting = [r["label"], r["task"], r["robot"], r["split"], r["camera"]]
        gaze.append(setting + [str(g["n_episodes"]), str(g["n_with_galt"]), str(g["n_verified"]),
                               share(g["verified_fraction"]), seconds(g["galt_verified_median_s"]),
                               share(g["gaze_on_target_ratio_mean"]), share(g["cue_before_reach_fraction"])])
        for a in g["anchors"]:
            anchors.append(setting + [a["anchor"], a["fixation"], a["event"], str(a["n"]), str(a["n_missing"])]
                           + [seconds(a[key]) for key in ("median_s", "q1_s", "q3_s", "iqr_s")])
    return {"gaze": (GAZE_HEADINGS, gaze), "gaze_anchors": (ANCHOR_HEADINGS, anchors)}


def expected_tables(summary):
    tables = success_tables(summary)
    tables["id_minus_ood"] = (
        ["policy", "task", "robot", "camera", "ood split", "id %", "ood %", "id - ood"],
        [[r["label"], r["task"], r["robot"], r["camera"], r["ood_split"], pct(r["id_rate"]), pct(r["ood_rate"]),
          points(r["difference"])] for r in summary["id_minus_ood"]])
    tables["head_vs_fixed"] = (
        ["policy", "task", "robot", "split", "pairs", "head %", "fixed %", "head - fixed", "head only", "fixed only",
         "McNemar p"],
        [[r["label"], r["task"], r["robot"], r["split"], str(r["pairs"]), pct(r["head_rate"]), pct(r["fixed_rate"]),
          points(r["difference"]), str(r["head_only"]), str(r["fixed_only"]), pvalue(r["mcnemar_p"])]
         for r in summary["paired"]])
    tables["successful_length"] = (
        ["policy", "task", "robot", "split", "camera", "successful", "mean s", "std s", "median s"],
        [[r["label"], r["task"], r["robot"], r["split"], r["camera"], str(r["successful_length_s"]["n"]),
          seconds(r["successful_length_s"]["mean"]), seconds(r["successful_length_s"]["std"]),
          seconds(r["successful_length_s"]["median"])] for r in summary["successful_length"]])
    tables["galt"] = (
        ["policy", "robot", "task", "split", "episodes", "detected", "mean s", "median s", "std s"],
        [[r["label"], r["robot"], r["task"], r["split"], str(r["n_episodes"]),
          "%d (%s %%)" % (r["n_valid"], pct(r["detection_rate"])), seconds(r["mean_s"]), seconds(r["median_s"]),
          seconds(r["std_s"])] for r in summary["galt"]])
    tables.update(funnel_tables(summary["stages"]))
    if "failure_events" in summary:
        tables.update(event_tables(summary["failure_events"]))
    if "gaze" in summary:
        tables.update(gaze_tables(summary["gaze"]))
    if summary["paired_camera_sets"]:
        tables["paired_camera_sets"] = (
            ["policy", "task", "robot", "split", "camera set", "pairs", "head %", "set %", "both", "head only",
             "set only", "neither", "McNemar p"],
            [[r["label"], r["task"], r["robot"], r["split"], r["camera"], str(r["pairs"]), pct(r["head_rate"]),
              pct(r["set_rate"]), str(r["both"]), str(r["head_only"]), str(r["set_only"]), str(r["neither"]),
              pvalue(r["mcnemar_p"])] for r in summary["paired_camera_sets"]])
    if "paired_perturbations" in summary:
        tables["paired_perturbations"] = (
            ["policy", "perturbation", "task", "robot", "split", "camera", "pairs", "base %", "perturbed %", "both",
             "base only", "perturbed only", "neither", "McNemar p"],
            [[r["label"], r["perturbation"], r["task"], r["robot"], r["split"], r["camera"], str(r["pairs"]),
              pct(r["base_rate"]), pct(r["perturbed_rate"]), str(r["both"]), str(r["base_only"]),
              str(r["perturbed_only"]), str(r["neither"]), pvalue(r["mcnemar_p"])]
             for r in summary["paired_perturbations"]])
    if "sequential" in summary:
        def side(r, which):
            return r[which + "_label"] + " " + r[which + "_camera"]

        def decision(r):
            if r["outcome"] == "undecided":
                return "undecided"
            return side(r, "first" if r["outcome"] == "first_better" else "second") + " better"
        tables["sequential_pairs"] = (
            ["kind", "first", "second", "task", "robot", "split", "seed", "stopped at", "cap", "decision",
             "decided at", "first only", "second only", "e-value", "episodes saved"],
            [[r["kind"], side(r, "first"), side(r, "second"), r["task"], r["robot"], r["split"], str(r["seed"]),
              str(r["stopped_at"]), str(r["cap"]), decision(r),
              "-" if r["decided_at"] is None else str(r["decided_at"]), str(r["first_only"]), str(r["second_only"]),
              pvalue(r["e_value"]), str(r["episodes_saved"])] for r in summary["sequential"]["pairs"]])
    if summary["seed_groups"]:
        rows = []
        for group in summary["seed_groups"]:
            for row, task in [(r, r["task"]) for r in group["rows"]] + \
                             [(r, "suite mean (task average)") for r in group["suite_means"]]:
                rows.append([group["seed_group"], row["suite"], task, row["robot"], row["split"], row["camera"],
                             str(row["n"]), pct(row["mean"]), pct(row["std"]), pct(row["min"]), pct(row["max"])])
        tables["seed_groups"] = (["seed group", "suite", "task", "robot", "split", "camera", "checkpoints", "mean %",
                                  "std", "min %", "max %"], rows)
    headline, rows = summary["headline"], []

    def value(number):
        return "-" if number is None else pct(number)
    if headline["q1_ablation"] is not None:
        rows += [["Q1 ablation (Fig. 3d)", arm, value(n)] for arm, n in headline["q1_ablation"].items()]
    if headline["q2_single_vs_multi"] is not None:
        rows += [["Q2 single vs multi-task (Fig. 3b)", r["suite"] + " " + which, value(r[which])]
                 for r in headline["q2_single_vs_multi"] for which in ("single", "multi")]
    if headline["q3_splits"] is not None:
        rows += [["Q3 generalisation (Fig. 3c)", r["suite"] + " " + split, value(r[split])]
                 for r in headline["q3_splits"] for split in ("id", "ood-spatial", "ood-init-pose")]
    tables["headline"] = (["question", "what", "value %"], rows)
    tables["cells"] = (
        ["cell", "policy", "episodes", "successful", "success %", "ci low %", "ci high %",
         "successful length mean s", "GALT mean s"],
        [[c["id"], c["label"], str(c["n_episodes"]), str(c["n_successful"]), pct(c["success_rate"]), pct(c["ci_low"]),
          pct(c["ci_high"]), seconds(c["successful_length_s"]["mean"]),
          "-" if c["galt"] is None else seconds(c["galt"]["mean_s"])] for c in summary["cells"]])
    return tables


def compare(name, headings, shown, expected, keyed):
    """Each value the reader sees under a heading against summary.json's. keyed: the shown rows are
    a subset, found by their values under the expected rows' first `keyed` headings."""
    want_headings, want_rows = expected
    if headings != want_headings:
        fail("table %s headings %s, summary.json's table has %s" % (name, headings, want_headings))
    if not keyed and len(shown) != len(want_rows):
        fail("table %s shows %d rows, summary.json has %d" % (name, len(shown), len(want_rows)))
    by_key = {tuple(row[:keyed]): row for row in want_rows}
    for number, values in enumerate(shown, 1):
        want = by_key.get(tuple(values[:keyed])) if keyed else want_rows[number - 1]
        if want is None:
            fail("table %s row %d %s: summary.json has no such row" % (name, number, values[:keyed]))
        for heading, value, wanted in zip(headings, values, want):
            if value != wanted:
                fail("table %s row %d (%s): under '%s' the reader sees '%s', summary.json gives '%s'"
                     % (name, number, values[0], heading, value, wanted))
    return len(shown)


# The title above each table, as the report prints it.
TITLES = {
    "id_minus_ood": "id - ood: success-rate drop from the id split (percentage points)",
    "head_vs_fixed": "Head vs fixed camera on matched episodes",
    "successful_length": "Length of successful episodes (s, 20 Hz steps / 20)",
    "galt": "GALT per robot and task (head camera, successful episodes)",
    "stage_funnel": "Stage funnel, the cameras side by side: episodes (%) that reached each stage and every earlier "
                    "stage that applies, and that reached it alone",
    "stage_funnel_episodes": "Stage funnel: episodes, success rate and simulator faults per camera",
    "paired_camera_sets": "Camera sets vs head on matched episodes",
    "failure_events": "Failure events: episodes (of the row's) in which each event fired",
    "motion_quality": "Motion quality: medians per arm of the tool centre point's path, RMS jerk and SPARC",
    "gaze": "Gaze: verified GALT and gaze on target (successful episodes)",
    "gaze_anchors": "Gaze anchors: lead time from the head's arrival to an action event (s, successful episodes)",
    "paired_perturbations": "Perturbations vs the base scene on matched episodes",
    "sequential_pairs": "Sequential paired test: where each pair stopped",
    "seed_groups": "Seed groups: success rate (%) across checkpoints (training seeds of one recipe)",
    "headline": "Headline numbers (suite means averaged over robots, %)",
    "cells": "Cells",
}


def table_titles(summary):
    titles = dict(TITLES)
    several = len(summary["labels"]) > 1
    for suite in summary["success"]:
        name = "success_" + suite["suite"] + ("_" + suite["label"] if several else "")
        titles[name] = suite["title"] + ", " + suite["label"] + ": success rate (%) [95% Wilson interval]"
    return titles


def check_page_tables(page, summary):
    """Every table of the page, found by the title above it, in page order."""
    expected = expected_tables(summary)
    by_title = {title: name for name, title in table_titles(summary).items() if name in expected}
    values, seen = 0, []
    for table in page.tables:
        name = by_title.get(table["id"])
        if name is None:
            fail("the page has a table titled '%s' that summary.json has no table for (known: %s)"
                 % (table["id"], list(by_title)))
        headings, shown = as_shown(table)
        values += compare(name, headings, shown, expected[name], 0) * len(headings)
        seen.append(name)
    missing = [name for name in expected if name not in seen]
    if missing:
        fail("the page lacks the tables %s" % missing)
    return len(page.tables), values


def markdown_tables(text):
    """The pipe tables of a Markdown file: [(title, headings, rows)], the title the bold line above."""
    tables, title, lines = [], "", text.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i].strip()
        if line.startswith("**"):
            title = line
        if line.startswith("|") and i + 1 < len(lines) and set(lines[i + 1].strip()) <= set("|:-"):
            split = lambda row: [cell.strip() for cell in row.strip().strip("|").split("|")]
            headings, rows, i = split(line), [], i + 2
            while i < len(lines) and lines[i].strip().startswith("|"):
                rows.append(split(lines[i]))
                i += 1
            tables.append((title, headings, rows))
            continue
        i += 1
    return tables


def check_markdown(path, label, summary):
    """`tavis table`'s Markdown for the cells of `label`: every value under its heading."""
    expected = expected_tables(summary)
    suites = [s for s in summary["success"] if s["label"] == label]
    funnel = funnel_tables([r for r in summary["stages"] if r["label"] == label])
    funnel.update(event_tables([r for r in summary.get("failure_events", []) if r["label"] == label]))
    funnel.update(gaze_tables([r for r in summary.get("gaze", []) if r["label"] == label]))
    tables = markdown_tables(open(path).read())
    names = ["stage_funnel", "stage_funnel_episodes"] + (["failure_events", "motion_quality"]
                                                         if "failure_events" in summary else [])
    if any(r["label"] == label for r in summary.get("gaze", [])):
        names += ["gaze", "gaze_anchors"]
    if len(tables) != 1 + len(names):
        fail("%s holds %d tables, not the success table and %s" % (path, len(tables), ", ".join(names)))
    values = 0
    for number, (title, headings, rows) in enumerate(tables):
        for row_number, row in enumerate(rows, 1):
            if len(row) != len(headings):
                fail("%s table %d row %d has %d cells under %d headings: %s" % (path, number + 1, row_number,
                                                                                len(row), len(headings), row))
        if number == 0:
            suite = next(s for s in suites if title.startswith("**" + s["title"] + "**"))
            name = "success_" + suite["suite"] + ("_" + label if len(summary["labels"]) > 1 else "")
            want_headings, want_rows = expected[name]
            # `tavis table` has no id - ood columns.
            width = 1 + len(suite["columns"])
            want = (want_headings[:width], [r[:width] for r in want_rows])
            values += compare(path + " success", headings, rows, want, 1) * len(headings)
        else:
            name = names[number - 1]
            want_headings, want_rows = funnel[name]
            # A row per setting; the anchor table has a row per setting and anchor.
            keyed = 6 if name == "gaze_anchors" else 5
            values += compare(path + " " + name, headings, rows, (want_headings, want_rows), keyed) * len(headings)
    return values


def main():
    sweep, work = sys.argv[1], sys.argv[2]
    url = "file://" + os.path.abspath(os.path.join(sweep, "report.html"))
    summary = json.load(open(os.path.join(sweep, "summary.json")))

    dumped = chromium(work, "--dump-dom", url)
    for line in dumped.stderr.splitlines():
        if "CONSOLE" in line or "Uncaught" in line or "Failed to load resource" in line or "net::ERR" in line:
            fail("the page logged an error: " + line)
    page = Page()
    page.feed(dumped.stdout)
    if page.external:
        fail("the report refers to other files or the network: %s" % page.external[:3])
    tables, values = check_page_tables(page, summary)
    points_expected = sum(1 for suite in summary["success"] for column in suite["columns"]
                          for row in column["tasks"] if "success_rate" in row)
    if page.circles != points_expected:
        fail("the success plots show %d points, summary.json has %d pooled cells" % (page.circles, points_expected))
    gaze_values = sum(len(shown) * len(headings) for name, (headings, shown) in expected_tables(summary).items()
                      if name in ("gaze", "gaze_anchors"))
    markdown = ""
    if len(sys.argv) == 6 and sys.argv[3] == "--table":
        markdown = ", tavis table's %d values under their headings" % check_markdown(sys.argv[4], sys.argv[5], summary)

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
    print("report ok: %d cells, %d tables with %d values under their headings equal summary.json (%d of them the "
          "gaze and anchor tables')%s, %d plot points, %d svg plots, screenshot %dx%d with %.1f%% ink, %d colours"
          % (len(summary["cells"]), tables, values, gaze_values, markdown, points_expected, page.svgs, image.shape[1],
             image.shape[0], 100 * not_white, colours))


if __name__ == "__main__":
    main()
