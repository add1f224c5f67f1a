"""The selection table and the success-vs-demonstrations curve of docs/baselines.md, from cells.

    python3 -m tavis_baseline.selection docs/baselines/cells/2026-12-02-selection [--out sel.md]

Cells are folders named `<dataset>_<recipe>_<demonstrations>` (wta_l1_2000, cpc_flow_200,
wta_rn18l1_2000: recipe = vision prefix + head) holding `tavis eval`'s summary.json and
episodes.jsonl, and the checkpoint's training.json (steps, wall time, validation L1) copied beside
them; `expert_<task>_<split>` is the expert on the same scenes. Every row is one training seed,
GR1T2, head camera, id: success with its 95 % Wilson interval, how far the failures got (the
stage funnel), how the episodes ended, and what the run cost on the card.
"""

import json
import re
import sys

from .table import DATASET_TASKS, Cell, rate, scan_cells, tables_command

CELL_NAME = re.compile(r"^(?P<dataset>[a-z]+)_(?P<recipe>[a-z0-9]+)_(?P<demos>\d+)(?P<variant>_[a-z0-9]+)?$")
VISIONS = {"rn18": "ResNet-18 + spatial softmax"}  # recipe prefix -> encoder; none: the CNN
HEADS = {"l1": "L1 (deterministic)", "flow": "flow matching", "act": "ACT CVAE"}


def recipe_parts(recipe):
    """(vision, head) of a recipe name such as `l1`, `flow` or `rn18l1`."""
    for prefix, vision in VISIONS.items():
        if recipe.startswith(prefix):
            return vision, HEADS.get(recipe[len(prefix):], recipe[len(prefix):])
    return "CNN", HEADS.get(recipe, recipe)


def load(root):
    """{(dataset, recipe, demos, variant): (Cell, training dict or None)} and {(task, split): expert Cell}."""
    matches, experts = scan_cells(root, CELL_NAME)
    runs = {}
    for match, folder in matches:
        training = folder / "training.json"
        info = json.loads(training.read_text()) if training.is_file() else None
        runs[(match["dataset"], match["recipe"], int(match["demos"]), match["variant"] or "")] = (Cell(folder), info)
    return runs, experts


def funnel(cell):
    stages = cell.summary.get("stages") or []
    return ", ".join(f"{s['stage'].replace('target_', '')} {s['reached']}" for s in stages) or "-"


def execution(cell):
    """How the server executed each chunk (its metadata frame, as `tavis eval` recorded it)."""
    metadata = cell.summary.get("server_metadata") or [{}]
    text = metadata[0].get("chunk_execution", "-") if metadata else "-"
    return text.split(":")[0]


def cost(info):
    if not info:
        return "-", "-", "-"
    steps = f"{info.get('steps_done', 0):,}"
    minutes = f"{info.get('wall_s', 0) / 60:.1f}"
    validation = info.get("validation_l1")
    return steps, minutes, "-" if validation is None else f"{validation:.4f}"


def selection_table(dataset, runs, experts):
    task = DATASET_TASKS.get(dataset, dataset)
    lines = [f"| {task}: vision | head | demos | served | steps | train min | val L1 | success, 96 id episodes "
             "| stages reached | ends |",
             "|---|---|---:|---|---:|---:|---:|---|---|---|"]
    keys = sorted((k for k in runs if k[0] == dataset), key=lambda k: (recipe_parts(k[1]), k[2], k[3]))
    for key in keys:
        cell, info = runs[key]
        vision, head = recipe_parts(key[1])
        steps, minutes, validation = cost(info)
        ends = ", ".join(f"{name} {n}" for name, n in sorted(cell.summary.get("ends", {}).items()))
        lines.append(f"| {vision} | {head} | {key[2]:,} | {execution(cell)} | {steps} | {minutes} | {validation} | {rate(cell)} "
                     f"| {funnel(cell)} | {ends} |")
    expert = experts.get((task, "id"))
    if expert is not None:
        lines.append(f"| expert | | | | | | | {rate(expert)} | {funnel(expert)} | |")
    return "\n".join(lines)


def demos_curve(dataset, runs):
    """Success against the number of demonstrations, one line per recipe seen at two sizes or more."""
    task = DATASET_TASKS.get(dataset, dataset)
    recipes = sorted({k[1] for k in runs if k[0] == dataset and not k[3]})
    lines = []
    for recipe in recipes:
        sizes = sorted(k[2] for k in runs if k[0] == dataset and k[1] == recipe and not k[3])
        if len(sizes) < 2:
            continue
        vision, head = recipe_parts(recipe)
        cells = [runs[(dataset, recipe, n, "")][0] for n in sizes]
        points = "; ".join(f"{n:,}: {100 * c.successes / c.n:.1f} %" for n, c in zip(sizes, cells))
        lines.append(f"- {task}, {vision}, {head}: {points}")
    return "\n".join(lines)


def render(root):
    runs, experts = load(root)
    if not runs:
        raise ValueError(f"{root}: no cell named <dataset>_<recipe>_<demonstrations> with a summary.json")
    parts = []
    for dataset in sorted({k[0] for k in runs}):
        parts.append(selection_table(dataset, runs, experts))
        curve = demos_curve(dataset, runs)
        if curve:
            parts.append("Success against demonstrations (the same recipe, the same time on the card):\n" + curve)
    return "\n\n".join(parts) + "\n"


def main(argv=None):
    return tables_command("tavis_baseline.selection", __doc__.splitlines()[0],
                          "folder of selection cells (<dataset>_<recipe>_<demonstrations>)", render, argv)


if __name__ == "__main__":
    sys.exit(main())
