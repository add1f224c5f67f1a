"""The baseline table of docs/baselines.md from a folder of evaluation cells.

    python3 -m tavis_baseline.table WORK/eval [--out table.md]

Cells are folders named `<dataset>_<camera>_<seed>_<split>` (as tools/baseline/gpu_table_runs.sh
writes them: cp_head_0_id, wtahs_fixed_2_id, ...) holding `tavis eval`'s summary.json and
episodes.jsonl, and `expert_<task>_<split>` for the expert on the same scenes. For each task it
prints success per training seed with its 95 % Wilson interval, the mean and sample standard
deviation across seeds, the exact two-sided McNemar test of each seed's head cell against its
fixed twin (the same scenes, paired episode by episode), and the median GALT of the head
policies' successes beside the expert's. The head-still ablation (dataset `wtahs`) is compared
with the fixed policy trained on head-first demonstrations of the same task, seed by seed.
A cell that is missing or failed shows as `-`.
"""

import argparse
import json
import math
import re
import statistics
import sys
from pathlib import Path

DATASET_TASKS = {"cp": "conditional-pick", "wta": "wait-then-act", "cpc": "clutter-pick-cube"}
ABLATION = {"wtahs": "wta"}  # head-still demonstrations -> the head-first dataset of the same task
SPLITS = ("id", "ood-spatial", "ood-init-pose")
SEEDS = (0, 1, 2)
CELL_NAME = re.compile(r"^(?P<dataset>[a-z]+)_(?P<camera>head|fixed)_(?P<seed>\d+)_(?P<split>[a-z-]+)$")


def wilson(successes, n, z=1.96):
    """The 95 % Wilson score interval of a binomial proportion, as fractions (z = 1.96, as `tavis eval`
    and `tavis table` compute it)."""
    if n == 0:
        return 0.0, 1.0
    p = successes / n
    denominator = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denominator
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denominator
    return max(0.0, centre - half), min(1.0, centre + half)


def mcnemar_exact(only_a, only_b):
    """Exact two-sided McNemar p-value: the discordant pairs under Binomial(n, 1/2)."""
    n = only_a + only_b
    if n == 0:
        return 1.0
    k = min(only_a, only_b)
    tail = sum(math.comb(n, i) for i in range(k + 1)) / 2 ** n
    return min(1.0, 2 * tail)


class Cell:
    """One evaluation cell: its per-episode success and its summary."""

    def __init__(self, folder):
        self.folder = Path(folder)
        self.summary = json.loads((self.folder / "summary.json").read_text())
        self.success = {}
        with open(self.folder / "episodes.jsonl") as records:
            for line in records:
                record = json.loads(line)
                self.success[record["episode"]] = bool(record["success"])
        if len(self.success) != self.summary["n_episodes"]:
            raise ValueError(f"{self.folder}: episodes.jsonl holds {len(self.success)} episodes, "
                             f"summary.json says {self.summary['n_episodes']}")

    @property
    def n(self):
        return len(self.success)

    @property
    def successes(self):
        return sum(self.success.values())

    def galt_median(self):
        galt = self.summary.get("galt") or {}
        return galt.get("median_s") if galt.get("n_valid") else None


def scan_cells(root, pattern):
    """[(name match, folder)] of the folders of `root` whose name `pattern` matches, and
    {(task, split): expert Cell} of its `expert_<task>_<split>` folders; folders without a summary
    and records (a run that failed) are left out."""
    matches, experts = [], {}
    for folder in sorted(Path(root).iterdir()):
        if not (folder / "summary.json").is_file() or not (folder / "episodes.jsonl").is_file():
            continue
        if folder.name.startswith("expert_"):
            task, _, split = folder.name[len("expert_"):].rpartition("_")
            experts[(task, split)] = Cell(folder)
            continue
        match = pattern.match(folder.name)
        if match:
            matches.append((match, folder))
    return matches, experts


def load_cells(root):
    """{(dataset, camera, seed, split): Cell} and {(task, split): expert Cell}."""
    matches, experts = scan_cells(root, CELL_NAME)
    policies = {(m["dataset"], m["camera"], int(m["seed"]), m["split"]): Cell(folder) for m, folder in matches}
    return policies, experts


def rate(cell):
    if cell is None:
        return "-"
    low, high = wilson(cell.successes, cell.n)
    return f"{cell.successes}/{cell.n} = {100 * cell.successes / cell.n:.1f} % [{100 * low:.1f}, {100 * high:.1f}]"


def spread(cells):
    rates = [100 * c.successes / c.n for c in cells if c is not None]
    if not rates:
        return "-"
    if len(rates) == 1:
        return f"{rates[0]:.1f} % (one seed)"
    return f"{statistics.mean(rates):.1f} % ({statistics.stdev(rates):.1f})"


def paired(a, b):
    """`a-only : b-only, p = ...` over the episodes both cells hold."""
    if a is None or b is None:
        return "-"
    common = sorted(set(a.success) & set(b.success))
    only_a = sum(a.success[e] and not b.success[e] for e in common)
    only_b = sum(b.success[e] and not a.success[e] for e in common)
    return f"{only_a} : {only_b}, p = {mcnemar_exact(only_a, only_b):.2g}"


def galt_text(cells):
    values = [c.galt_median() for c in cells if c is not None]
    return " / ".join("-" if v is None else f"{v:.2f}" for v in values) or "-"


def task_table(dataset, policies, experts):
    task = DATASET_TASKS[dataset]
    lines = [f"| {task}, GR1T2 | " + " | ".join(f"seed {s}" for s in SEEDS) + " | mean (sd) across seeds |",
             "|---|" + "---|" * (len(SEEDS) + 1)]
    for split in SPLITS:
        if not any(key[0] == dataset and key[3] == split for key in policies):
            continue
        for camera in ("head", "fixed"):
            cells = [policies.get((dataset, camera, s, split)) for s in SEEDS]
            lines.append(f"| {split}, {camera} | " + " | ".join(rate(c) for c in cells) + f" | {spread(cells)} |")
        pairs = [paired(policies.get((dataset, "head", s, split)), policies.get((dataset, "fixed", s, split)))
                 for s in SEEDS]
        lines.append(f"| {split}, McNemar (head-only : fixed-only) | " + " | ".join(pairs) + " | |")
    lines.append("")
    lines.append(f"GALT of the head policies' successes (median, s, seeds {', '.join(map(str, SEEDS))}) against the "
                 "expert on the same scenes:")
    for split in SPLITS:
        heads = [policies.get((dataset, "head", s, split)) for s in SEEDS]
        if all(c is None for c in heads):
            continue
        expert = experts.get((task, split))
        expert_text = "-" if expert is None else f"{expert.galt_median():.2f} ({rate(expert)})"
        lines.append(f"- {split}: {galt_text(heads)}; expert {expert_text}")
    return "\n".join(lines)


def ablation_table(ablation, head_first, policies):
    task = DATASET_TASKS[head_first]
    lines = [f"| {task}, GR1T2, id, fixed camera | " + " | ".join(f"seed {s}" for s in SEEDS) + " | mean (sd) |",
             "|---|" + "---|" * (len(SEEDS) + 1)]
    first = [policies.get((head_first, "fixed", s, "id")) for s in SEEDS]
    still = [policies.get((ablation, "fixed", s, "id")) for s in SEEDS]
    lines.append("| trained on head-first demonstrations | " + " | ".join(rate(c) for c in first) + f" | {spread(first)} |")
    lines.append("| trained on head-still demonstrations | " + " | ".join(rate(c) for c in still) + f" | {spread(still)} |")
    lines.append("| McNemar (head-still-only : head-first-only) | "
                 + " | ".join(paired(b, a) for a, b in zip(first, still)) + " | |")
    return "\n".join(lines)


def render(root):
    policies, experts = load_cells(root)
    if not policies:
        raise ValueError(f"{root}: no evaluation cell named <dataset>_<camera>_<seed>_<split> with a summary.json")
    parts = []
    for dataset in DATASET_TASKS:
        if any(key[0] == dataset for key in policies):
            parts.append(task_table(dataset, policies, experts))
    for ablation, head_first in ABLATION.items():
        if any(key[0] == ablation for key in policies):
            parts.append(ablation_table(ablation, head_first, policies))
    return "\n\n".join(parts) + "\n"


def tables_command(program, description, cells_help, render_tables, argv=None):
    """The command line of a table module: CELLS [--out FILE]; prints what `render_tables(CELLS)`
    returns, exit 1 with the error on stderr when the folder does not hold the cells it needs."""
    parser = argparse.ArgumentParser(prog=program, description=description)
    parser.add_argument("cells", help=cells_help)
    parser.add_argument("--out", help="also write the tables to this Markdown file")
    args = parser.parse_args(argv)
    try:
        text = render_tables(args.cells)
    except (OSError, ValueError, KeyError) as error:
        print(f"{program}: {error}", file=sys.stderr)
        return 1
    print(text, end="")
    if args.out:
        Path(args.out).write_text(text)
    return 0


def main(argv=None):
    return tables_command("tavis_baseline.table", __doc__.splitlines()[0],
                          "folder of evaluation cells (WORK/eval of tools/baseline/gpu_table_runs.sh)", render, argv)


if __name__ == "__main__":
    sys.exit(main())
