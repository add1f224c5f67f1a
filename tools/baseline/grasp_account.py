"""Where a served policy's grasps go wrong, episode by episode, from its actions against the
scripted expert's on the same scenes (docs/baselines.md, "Seeds of the chosen recipe").

    python3 tools/baseline/grasp_account.py POLICY_CELL EXPERT_CELL

POLICY_CELL: a served `tavis eval` cell (it keeps DIR/actions/episode_<i>.csv); EXPERT_CELL: the
expert on the same task, split and seed with `--expert-hz 20` (so one row per 20 Hz policy step,
as the policy's). Both folders hold episodes.jsonl. The arm is the one whose gripper the expert
closes; the grasp point is the expert's commanded hand position at its first closed row. Per
episode it prints the policy's success, whether the other arm's gripper closed further than the
grasping arm's (the two arms averaged), when each closed, how close the policy's commanded hand
came to the expert's grasp point, and where it was when the policy first closed (height difference and
horizontal distance). Pure Python: the standard library alone, so any Python 3 runs it.

Columns are the canonical action's (kinematics/action_layout.h, docs/cli.md): left hand
position 0-2, right hand 7-9, grippers 17 (left) and 18 (right), -1 open and +1 closed."""

import argparse
import json
import gzip
import statistics
import sys
from pathlib import Path

HAND = (0, 7)      # first position column of each arm's commanded hand
GRIPPER = (17, 18)


def read_actions(actions, episode):
    """Episode `episode`'s rows from a cell's actions/ folder: episode_<i>.csv as older cells saved
    them, else the gzip-compressed episode_<i>.csv.gz cells save now."""
    plain = Path(actions) / f"episode_{episode}.csv"
    compressed = Path(actions) / f"episode_{episode}.csv.gz"
    path = compressed if not plain.exists() and compressed.exists() else plain
    with (gzip.open(path, "rt") if path.suffix == ".gz" else open(path)) as rows:
        return [[float(value) for value in line.split(",")] for line in rows if line.strip()]


def read_records(cell):
    with open(Path(cell) / "episodes.jsonl") as lines:
        return {record["episode"]: record for record in map(json.loads, lines)}


def first_closed(actions, gripper):
    """The first row whose gripper command is closing (> 0), or None."""
    return next((step for step, row in enumerate(actions) if row[gripper] > 0), None)


def distance(a, b):
    return sum((x - y) ** 2 for x, y in zip(a, b)) ** 0.5


def account(policy_actions, expert_actions):
    """One episode's figures, or None when the expert never closes (no grasp to compare with)."""
    arm = max((0, 1), key=lambda a: max(row[GRIPPER[a]] for row in expert_actions))
    expert_close = first_closed(expert_actions, GRIPPER[arm])
    if expert_close is None:
        return None
    grasp = expert_actions[expert_close][HAND[arm]:HAND[arm] + 3]
    policy_close = first_closed(policy_actions, GRIPPER[arm])
    figures = {
        "arm": ("left", "right")[arm],
        "other_arm_closed_further": max(row[GRIPPER[1 - arm]] for row in policy_actions)
        > max(row[GRIPPER[arm]] for row in policy_actions),
        "expert_close_step": expert_close,
        "policy_close_step": policy_close,
        "closed_steps": sum(row[GRIPPER[arm]] > 0 for row in policy_actions),
        "closest_to_grasp_m": min(distance(row[HAND[arm]:HAND[arm] + 3], grasp) for row in policy_actions),
    }
    if policy_close is not None:
        hand = policy_actions[policy_close][HAND[arm]:HAND[arm] + 3]
        figures["height_above_grasp_m"] = hand[2] - grasp[2]
        figures["horizontal_from_grasp_m"] = ((hand[0] - grasp[0]) ** 2 + (hand[1] - grasp[1]) ** 2) ** 0.5
    return figures


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("policy_cell", help="a served cell with actions/episode_<i>.csv(.gz)")
    parser.add_argument("expert_cell", help="the expert's cell on the same scenes, --expert-hz 20")
    args = parser.parse_args(argv)
    try:
        policy, expert = read_records(args.policy_cell), read_records(args.expert_cell)
        rows = []
        for episode in sorted(set(policy) & set(expert)):
            figures = account(read_actions(Path(args.policy_cell) / "actions", episode),
                              read_actions(Path(args.expert_cell) / "actions", episode))
            if figures is not None:
                rows.append((episode, policy[episode]["success"], figures))
    except (OSError, ValueError, KeyError) as error:
        print(f"grasp_account.py: {error}", file=sys.stderr)
        return 2
    if not rows:
        print("grasp_account.py: no episode of both cells has an expert grasp", file=sys.stderr)
        return 2
    print("| episode | success | arm | other arm closed further | close step (policy / expert) "
          "| closed steps | closest to grasp (cm) | hand above grasp (cm) | hand from grasp, horizontal (cm) |")
    print("|---:|---|---|---|---|---:|---:|---:|---:|")
    for episode, success, f in rows:
        above = f.get("height_above_grasp_m")
        aside = f.get("horizontal_from_grasp_m")
        print(f"| {episode} | {'yes' if success else 'no'} | {f['arm']} | {'yes' if f['other_arm_closed_further'] else 'no'} "
              f"| {f['policy_close_step'] if f['policy_close_step'] is not None else 'never'} / {f['expert_close_step']} "
              f"| {f['closed_steps']} | {100 * f['closest_to_grasp_m']:.1f} | {'-' if above is None else f'{100 * above:+.1f}'} "
              f"| {'-' if aside is None else f'{100 * aside:.1f}'} |")
    for label, wanted in (("successes", True), ("failures", False)):
        heights = [100 * f["height_above_grasp_m"] for _, s, f in rows if s == wanted and "height_above_grasp_m" in f]
        if heights:
            print(f"{label}: {len(heights)} closed, hand above the grasp point median {statistics.median(heights):+.1f} cm "
                  f"({min(heights):+.1f} to {max(heights):+.1f})")
    averaged = sum(f["other_arm_closed_further"] for _, _, f in rows)
    print(f"other arm's gripper closed further than the grasping arm's: {averaged} of {len(rows)} episodes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
