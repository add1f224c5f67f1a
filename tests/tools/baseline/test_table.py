"""tavis_baseline.table: Wilson intervals and exact McNemar against values computed independently
(the Wilson interval that `tavis eval` writes, closed-form binomial tails), and the table built from cell folders laid out as
tools/baseline/gpu_table_runs.sh writes them."""

import json

import pytest

from tavis_baseline import table


def write_cell(folder, successes, galt_median=None):
    folder.mkdir(parents=True)
    with open(folder / "episodes.jsonl", "w") as records:
        for episode, success in enumerate(successes):
            records.write(json.dumps({"episode": episode, "success": bool(success), "end": "x"}) + "\n")
    summary = {"n_episodes": len(successes), "n_successful": sum(map(bool, successes))}
    if galt_median is not None:
        summary["galt"] = {"median_s": galt_median, "n_valid": sum(map(bool, successes))}
    (folder / "summary.json").write_text(json.dumps(summary))


def test_wilson_matches_the_closed_form_values():
    # 13/96: the interval `tavis eval` (C++, batch/statistics) wrote into a cell's summary.json.
    assert table.wilson(13, 96) == pytest.approx((0.0808762979676279, 0.21801314290671703), abs=1e-12)
    low, high = table.wilson(0, 96)
    assert low == pytest.approx(0.0, abs=1e-12) and round(100 * high, 1) == 3.8
    low, high = table.wilson(96, 96)
    assert round(100 * low, 1) == 96.2 and high == 1.0


def test_mcnemar_exact_is_the_two_sided_binomial_tail():
    assert table.mcnemar_exact(13, 0) == pytest.approx(2 * 0.5 ** 13)
    # 5 : 2 discordant pairs: 2 * P(X <= 2 | n=7, 1/2) = 2 * (1 + 7 + 21) / 128
    assert table.mcnemar_exact(5, 2) == pytest.approx(2 * 29 / 128)
    assert table.mcnemar_exact(3, 3) == 1.0
    assert table.mcnemar_exact(0, 0) == 1.0


def test_table_pairs_head_and_fixed_by_episode_and_reports_spread(tmp_path):
    episodes = 10
    heads = {0: [1, 1, 1, 0, 0, 0, 0, 0, 0, 0], 1: [1, 1, 0, 0, 0, 0, 0, 0, 0, 0], 2: [1, 1, 1, 1, 0, 0, 0, 0, 0, 0]}
    fixed = {0: [0, 0, 0, 1, 0, 0, 0, 0, 0, 0], 1: [0] * episodes, 2: [1, 0, 0, 0, 0, 0, 0, 0, 0, 0]}
    for seed in (0, 1, 2):
        write_cell(tmp_path / f"cp_head_{seed}_id", heads[seed], galt_median=2.0 + seed / 10)
        write_cell(tmp_path / f"cp_fixed_{seed}_id", fixed[seed])
    write_cell(tmp_path / "expert_conditional-pick_id", [1] * episodes, galt_median=2.4)
    text = table.render(tmp_path)
    assert "| id, head | 3/10 = 30.0 % [10.8, 60.3] | 2/10 = 20.0 % [5.7, 51.0] | 4/10 = 40.0 % [16.8, 68.7] | 30.0 % (10.0) |" in text
    # Seed 0: head-only episodes 0, 1, 2; fixed-only episode 3 -> 3 : 1; seed 2: 3 : 0.
    assert f"3 : 1, p = {table.mcnemar_exact(3, 1):.2g}" in text
    assert f"3 : 0, p = {table.mcnemar_exact(3, 0):.2g}" in text
    assert "- id: 2.00 / 2.10 / 2.20; expert 2.40 (10/10" in text
    assert "wait-then-act" not in text


def test_a_missing_seed_shows_as_a_dash_and_the_ablation_pairs_with_head_first(tmp_path):
    write_cell(tmp_path / "wta_fixed_0_id", [0, 0, 0, 0])
    write_cell(tmp_path / "wtahs_fixed_0_id", [1, 1, 0, 0])
    write_cell(tmp_path / "wtahs_fixed_1_id", [1, 0, 0, 0])
    text = table.render(tmp_path)
    assert "| trained on head-first demonstrations | 0/4 = 0.0 % [0.0, 49.0] | - | - | 0.0 % (one seed) |" in text
    assert "| McNemar (head-still-only : head-first-only) | 2 : 0, p = 0.5 | - | - | |" in text


def test_inconsistent_cells_and_empty_folders_are_refused(tmp_path):
    write_cell(tmp_path / "cp_head_0_id", [1, 0])
    summary = tmp_path / "cp_head_0_id" / "summary.json"
    summary.write_text(json.dumps({"n_episodes": 3, "n_successful": 1}))
    with pytest.raises(ValueError, match="holds 2 episodes"):
        table.render(tmp_path)
    empty = tmp_path / "empty"
    empty.mkdir()
    assert table.main([str(empty)]) == 1
