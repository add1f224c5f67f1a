"""The task and robot a checkpoint was trained for (dataset_origin.py): recorded in config.json from
the `tavis demos` dataset, declared by serve.py in the observation contract, and absent (declared
by nobody) for a dataset of several tasks, one not written by `tavis demos`, and an older
checkpoint."""

import json
import shutil
from pathlib import Path

import pytest

from tavis_baseline import checkpoint, train
from tavis_baseline.dataset_origin import recorded_task_and_robot
from tavis_baseline.serve import observation_contract
from tiny_training import TINY

REPO = Path(__file__).resolve().parents[3]
PUBLISHED = REPO / "docs" / "baselines" / "checkpoints" / "conditional-pick_gr1t2_head_flow_seed0"


@pytest.fixture(scope="module")
def trained(demo_dataset, tmp_path_factory):
    out = tmp_path_factory.mktemp("origin") / "ckpt"
    assert train.main(["--dataset", str(demo_dataset), "--out", str(out), *TINY]) == 0
    return out


def test_the_checkpoint_records_and_declares_its_datasets_task_and_robot(trained):
    config = json.loads((trained / "config.json").read_text())
    assert (config["task"], config["robot"]) == ("clutter-pick-cube", "gr1t2")
    contract = observation_contract(checkpoint.load(trained).config, trained)
    assert (contract["task"], contract["robot"]) == ("clutter-pick-cube", "gr1t2")


def test_an_older_checkpoint_loads_and_declares_neither(trained, tmp_path):
    old = tmp_path / "old"
    shutil.copytree(trained, old)
    config = json.loads((old / "config.json").read_text())
    del config["task"], config["robot"]  # as written before the fields
    (old / "config.json").write_text(json.dumps(config))
    contract = observation_contract(checkpoint.load(old).config, old)
    assert "task" not in contract and "robot" not in contract and "checkpoint_sha256" in contract


def test_the_published_checkpoint_declares_conditional_pick_on_gr1t2():
    contract = observation_contract(checkpoint.load(PUBLISHED).config, PUBLISHED)
    assert (contract["task"], contract["robot"]) == ("conditional-pick", "gr1t2")


def dataset_meta(root, report):
    """A dataset folder with meta/info.json of robot gr1t2 and `report` as tavis_demos.json (None: none)."""
    root.mkdir()
    info = {"robot_type": "gr1t2"}
    if report is not None:
        (root / "tavis_demos.json").write_text(report if isinstance(report, str) else json.dumps(report))
    return root, info


def test_several_tasks_declare_no_task_and_a_foreign_dataset_neither(tmp_path):
    two = {"robot": "gr1t2", "tasks": [{"task": "conditional-pick"}, {"task": "wait-then-act"}]}
    assert recorded_task_and_robot(*dataset_meta(tmp_path / "two", two)) == (None, "gr1t2")
    one = {"robot": "gr1t2", "tasks": [{"task": "wait-then-act"}]}
    assert recorded_task_and_robot(*dataset_meta(tmp_path / "one", one)) == ("wait-then-act", "gr1t2")
    assert recorded_task_and_robot(*dataset_meta(tmp_path / "foreign", None)) == (None, None)


@pytest.mark.parametrize("report", ["{not json", json.dumps({"robot": "gr1t2"}), json.dumps({"tasks": [7]})])
def test_a_broken_report_is_refused_naming_it(tmp_path, report):
    root, info = dataset_meta(tmp_path / "broken", report)
    with pytest.raises(ValueError, match="tavis_demos.json is not the report"):
        recorded_task_and_robot(root, info)


def test_training_on_a_broken_report_fails_naming_it(demo_dataset, tmp_path, capsys):
    root = tmp_path / "broken"
    shutil.copytree(demo_dataset, root)
    (root / "tavis_demos.json").write_text("{not json")
    assert train.main(["--dataset", str(root), "--out", str(tmp_path / "ckpt"), *TINY]) == 2
    assert "tavis_demos.json is not the report" in capsys.readouterr().err
