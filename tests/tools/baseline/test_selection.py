"""tavis_baseline.selection: the selection table and the success-vs-demonstrations curve read from
cell folders named <dataset>_<recipe>_<demonstrations>, with the checkpoint's training.json beside."""

import json

from tavis_baseline import selection


def write_cell(folder, successes, stages=None, training=None, execution=None):
    folder.mkdir(parents=True)
    with open(folder / "episodes.jsonl", "w") as records:
        for episode, success in enumerate(successes):
            records.write(json.dumps({"episode": episode, "success": bool(success)}) + "\n")
    wins = sum(map(bool, successes))
    summary = {"n_episodes": len(successes), "n_successful": wins,
               "ends": {"success": wins, "time_out": len(successes) - wins}, "stages": stages or []}
    if execution is not None:
        summary["server_metadata"] = [{"chunk_execution": execution + ": details"}]
    (folder / "summary.json").write_text(json.dumps(summary))
    if training is not None:
        (folder / "training.json").write_text(json.dumps(training))


def test_rows_name_vision_head_and_cost_and_the_curve_orders_by_demonstrations(tmp_path):
    write_cell(tmp_path / "wta_l1_2000", [1, 1, 0, 0], [{"stage": "target_grasped", "reached": 3}],
               {"steps_done": 12000, "wall_s": 300.0, "validation_l1": 0.05})
    write_cell(tmp_path / "wta_l1_200", [1, 0, 0, 0], training={"steps_done": 15000, "wall_s": 300.0})
    write_cell(tmp_path / "wta_rn18flow_2000", [0, 0, 0, 0])
    write_cell(tmp_path / "wta_l1_2000_te", [1, 1, 1, 0], execution="temporal ensembling")
    write_cell(tmp_path / "expert_wait-then-act_id", [1, 1, 1, 1])
    write_cell(tmp_path / "not_a_cell", [1])  # ignored: no demonstrations count in its name
    text = selection.render(tmp_path)
    rows = [line for line in text.splitlines() if line.startswith("| ")]
    assert rows[0].startswith("| wait-then-act: vision | head | demos |")
    assert "| CNN | L1 (deterministic) | 200 | - | 15,000 | 5.0 | - | 1/4 = 25.0 %" in rows[1]
    assert "| CNN | L1 (deterministic) | 2,000 | - | 12,000 | 5.0 | 0.0500 | 2/4 = 50.0 %" in rows[2]
    assert "grasped 3" in rows[2] and "success 2, time_out 2" in rows[2]
    assert "| CNN | L1 (deterministic) | 2,000 | temporal ensembling | - |" in rows[3] and "3/4 = 75.0 %" in rows[3]
    assert rows[4].startswith("| ResNet-18 + spatial softmax | flow matching | 2,000 | - | - |")
    assert rows[5].startswith("| expert |") and "4/4 = 100.0 %" in rows[5]
    assert "- wait-then-act, CNN, L1 (deterministic): 200: 25.0 %; 2,000: 50.0 %" in text
    assert "ResNet-18 + spatial softmax, flow" not in text  # one size only: no curve


def test_a_folder_without_selection_cells_is_an_error_naming_it(tmp_path):
    write_cell(tmp_path / "expert_wait-then-act_id", [1])
    assert selection.main([str(tmp_path)]) == 1
