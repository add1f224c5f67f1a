#!/usr/bin/python3
"""Contact sheet of every perturbation level (docs/perturbations.md): one row per level (the base
scene first), the head, fixed and right-wrist views of one episode after the scripted expert's
first second and a half, each rendered by `tavis render --perturb AXIS:LEVEL`. A runtime level's
row is taken later (--runtime-steps), once the target has been moved under the hand, beside the
base scene at that tick; a language level's row shows the episode's prompt, the only thing it
changes.

    tools/perturbation_contact_sheet.py --tavis build/tavis --out docs/images/perturbations.png

Needs Debian's python3-opencv (.ci/install-deps --tests) to read, label and write the PNGs.
"""
import argparse
import pathlib
import subprocess
import sys
import tempfile

import cv2
import numpy as np

CAMERAS = ["head", "fixed", "right_wrist"]
LABEL_WIDTH = 240
MARGIN = 4


AXES = ["camera", "sensor", "lighting", "appearance", "distractors", "language", "runtime"]


def levels(config_dir: pathlib.Path):
    """(axis, level) for every level of every axis file, in file order; the axes in the docs' order.
    Only the entries of a file's `levels:` list are levels (the distractors file lists its objects
    by name too)."""
    found = []
    for axis in AXES:
        in_levels = False
        for line in (config_dir / "perturbations" / f"{axis}.yaml").read_text().splitlines():
            stripped = line.strip()
            if not line.startswith((" ", "-", "#")) and stripped:
                in_levels = stripped == "levels:"
            elif in_levels and stripped.startswith("- name:"):
                found.append((axis, stripped.split(":", 1)[1].strip()))
    return found


def render(tavis, args, choice, steps, work):
    """The row's views and what `tavis render` said of the episode (its prompt, a move's tick)."""
    out = work / ((choice.replace(":", "_") if choice else "base") + f"_{steps}")
    command = [tavis, "render", "--task", args.task, "--robot", args.robot, "--seed", str(args.seed),
               "--steps", str(steps), "--width", str(args.width), "--height", str(args.height), "--out", str(out)]
    if choice:
        command += ["--perturb", choice]
    said = subprocess.run(command, check=True, stdout=subprocess.PIPE, text=True).stdout
    notes = [line.strip() for line in said.splitlines() if line.strip().startswith(("prompt:", "target "))]
    views = []
    for camera in CAMERAS:
        matches = sorted(out.glob(f"tick*_{camera}.png"))
        if len(matches) != 1:
            sys.exit(f"expected one tick*_{camera}.png in {out}, found {len(matches)}")
        views.append(cv2.imread(str(matches[0]), cv2.IMREAD_COLOR))
    return views, notes


def wrapped(text, width):
    """`text` in lines of at most `width` characters, broken between words."""
    lines, line = [], ""
    for word in text.split():
        if line and len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}" if line else word
    return lines + ([line] if line else [])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tavis", default="build/tavis")
    parser.add_argument("--config-dir", default="configs")
    parser.add_argument("--out", required=True)
    parser.add_argument("--task", default="clutter-pick-cube")
    parser.add_argument("--robot", default="gr1t2")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--steps", type=int, default=90)
    parser.add_argument("--runtime-steps", type=int, default=175,
                        help="control ticks before a runtime level's views (and the base beside them)")
    parser.add_argument("--width", type=int, default=160)
    parser.add_argument("--height", type=int, default=120)
    args = parser.parse_args()

    rows = [("base", "", args.steps)]
    for axis, level in levels(pathlib.Path(args.config_dir)):
        if axis == "runtime" and not any(row[1] == "" and row[2] == args.runtime_steps for row in rows):
            rows.append((f"base, tick {args.runtime_steps}", "", args.runtime_steps))
        steps = args.runtime_steps if axis == "runtime" else args.steps
        rows.append((f"{axis}:{level}", f"{axis}:{level}", steps))
    row_height = args.height + MARGIN
    sheet_width = LABEL_WIDTH + len(CAMERAS) * (args.width + MARGIN)
    header = 20
    sheet = np.full((header + len(rows) * row_height, sheet_width, 3), 32, np.uint8)
    font = cv2.FONT_HERSHEY_SIMPLEX
    for column, camera in enumerate(CAMERAS):
        cv2.putText(sheet, camera, (LABEL_WIDTH + column * (args.width + MARGIN) + 4, 15), font, 0.45, (230, 230, 230), 1,
                    cv2.LINE_AA)
    with tempfile.TemporaryDirectory() as work_dir:
        for row, (label, choice, steps) in enumerate(rows):
            top = header + row * row_height
            views, notes = render(args.tavis, args, choice, steps, pathlib.Path(work_dir))
            scale = 0.42  # smaller for a label too long for its column
            while cv2.getTextSize(label, font, scale, 1)[0][0] > LABEL_WIDTH - 8:
                scale -= 0.02
            cv2.putText(sheet, label, (4, top + 16), font, scale, (230, 230, 230), 1, cv2.LINE_AA)
            # What the views cannot show: a language level's prompt, when a runtime level moved the target.
            shown = [note for note in notes if (choice.startswith("language:") and note.startswith("prompt:")) or
                     (choice.startswith("runtime:") and note.startswith("target "))]
            lines = [part for note in shown for part in wrapped(note, 30)]
            for number, line in enumerate(lines[:7]):
                cv2.putText(sheet, line, (4, top + 34 + 13 * number), font, 0.32, (200, 200, 200), 1, cv2.LINE_AA)
            for column, view in enumerate(views):
                left = LABEL_WIDTH + column * (args.width + MARGIN)
                sheet[top:top + args.height, left:left + args.width] = view
    pathlib.Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    cv2.imwrite(args.out, sheet, [cv2.IMWRITE_PNG_COMPRESSION, 9])
    print(f"{args.out}: {len(rows)} rows x {len(CAMERAS)} cameras, {pathlib.Path(args.out).stat().st_size} bytes")


if __name__ == "__main__":
    main()
