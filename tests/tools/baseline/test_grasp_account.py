"""tools/baseline/grasp_account.py: per-episode grasp figures of a served cell against the
expert's, on hand-made cells whose answers are known."""

import gzip
import json

import grasp_account

ROWS, COLUMNS = 12, 19


def trajectory(right_close=None, left_close=None, right_z=0.30, left_grip_peak=-1.0):
    """A 12-step canonical action trajectory: hands at rest at (0.3, +-0.2, 0.3), the right hand
    descending to right_z from step 4, a gripper closing (+1) from its close step on."""
    rows = []
    for step in range(ROWS):
        row = [0.0] * COLUMNS
        row[0:3] = [0.3, 0.2, 0.3]
        row[7:10] = [0.3, -0.2, right_z if step >= 4 else 0.3]
        row[17] = 1.0 if left_close is not None and step >= left_close else left_grip_peak
        row[18] = 1.0 if right_close is not None and step >= right_close else -1.0
        rows.append(row)
    return rows


def write_cell(folder, trajectories, successes, compressed=False):
    """A cell's episodes.jsonl and actions/: plain episode_<i>.csv as older cells kept them, or the
    episode_<i>.csv.gz cells keep now."""
    (folder / "actions").mkdir(parents=True)
    with open(folder / "episodes.jsonl", "w") as records:
        for episode, (rows, success) in enumerate(zip(trajectories, successes)):
            records.write(json.dumps({"episode": episode, "success": success}) + "\n")
            name = folder / "actions" / f"episode_{episode}.csv{'.gz' if compressed else ''}"
            with (gzip.open(name, "wt") if compressed else open(name, "w")) as csv:
                csv.writelines(",".join(f"{value:.6f}" for value in row) + "\n" for row in rows)
    return folder


def test_the_height_and_timing_of_a_close_are_measured_against_the_experts():
    expert = trajectory(right_close=6, right_z=0.21)
    policy = trajectory(right_close=7, right_z=0.25)
    figures = grasp_account.account(policy, expert)
    assert figures["arm"] == "right"
    assert (figures["expert_close_step"], figures["policy_close_step"]) == (6, 7)
    assert figures["closed_steps"] == ROWS - 7
    assert abs(figures["height_above_grasp_m"] - 0.04) < 1e-9
    assert abs(figures["horizontal_from_grasp_m"]) < 1e-9
    assert not figures["other_arm_closed_further"]
    assert abs(figures["closest_to_grasp_m"] - 0.04) < 1e-9  # its hand stops 4 cm above the grasp point


def test_a_policy_closing_the_other_arms_gripper_further_is_flagged():
    expert = trajectory(right_close=6, right_z=0.21)
    policy = trajectory(right_close=None, left_grip_peak=0.4)  # right never closes, left half-closes
    figures = grasp_account.account(policy, expert)
    assert figures["other_arm_closed_further"]
    assert figures["policy_close_step"] is None
    assert "height_above_grasp_m" not in figures


def test_an_expert_that_never_closes_gives_no_account():
    assert grasp_account.account(trajectory(), trajectory()) is None


def test_the_command_prints_each_episode_and_the_summary(tmp_path, capsys):
    expert = write_cell(tmp_path / "expert", [trajectory(right_close=6, right_z=0.21)] * 2, [True, True])
    policy = write_cell(tmp_path / "policy", [trajectory(right_close=6, right_z=0.215),
                                              trajectory(right_close=8, right_z=0.26)], [True, False])
    assert grasp_account.main([str(policy), str(expert)]) == 0
    out = capsys.readouterr().out
    assert "| 0 | yes | right | no | 6 / 6 | 6 | 0.5 | +0.5 | 0.0 |" in out
    assert "| 1 | no | right | no | 8 / 6 | 4 | 5.0 | +5.0 | 0.0 |" in out
    assert "failures: 1 closed, hand above the grasp point median +5.0 cm" in out


def test_a_cell_without_actions_is_refused_naming_the_file(tmp_path, capsys):
    expert = write_cell(tmp_path / "expert", [trajectory(right_close=6)], [True])
    policy = tmp_path / "policy"
    policy.mkdir()
    (policy / "episodes.jsonl").write_text(json.dumps({"episode": 0, "success": False}) + "\n")
    assert grasp_account.main([str(policy), str(expert)]) == 2
    assert "episode_0.csv" in capsys.readouterr().err


def test_compressed_actions_give_the_same_account_as_plain_ones(tmp_path, capsys):
    trajectories = [trajectory(right_close=6, right_z=0.215), trajectory(right_close=8, right_z=0.26)]
    expert = write_cell(tmp_path / "expert", [trajectory(right_close=6, right_z=0.21)] * 2, [True, True])
    plain = write_cell(tmp_path / "plain", trajectories, [True, False])
    compressed = write_cell(tmp_path / "compressed", trajectories, [True, False], compressed=True)
    assert grasp_account.main([str(plain), str(expert)]) == 0
    from_plain = capsys.readouterr().out
    assert grasp_account.main([str(compressed), str(expert)]) == 0
    assert capsys.readouterr().out == from_plain
    assert "| 1 | no | right | no | 8 / 6 | 4 | 5.0 | +5.0 | 0.0 |" in from_plain
