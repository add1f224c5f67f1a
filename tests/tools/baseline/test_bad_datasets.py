"""Datasets the trainer must refuse with a message naming the file and the bad key or value: each
is a copy of the good test dataset with one thing broken."""

import json
import shutil

import pytest

from tavis_baseline import train
from tavis_baseline.dataset import DemoDataset

HEAD = ["observation.images.OBS_HEAD"]


@pytest.fixture
def copy_of(demo_dataset, tmp_path):
    def make(edit_info=None):
        root = tmp_path / "bad"
        shutil.copytree(demo_dataset, root)
        if edit_info is not None:
            path = root / "meta" / "info.json"
            info = json.loads(path.read_text())
            edit_info(info)
            path.write_text(json.dumps(info))
        return root
    return make


def refused(root, *patterns):
    with pytest.raises(ValueError) as caught:
        DemoDataset(root, HEAD)
    message = str(caught.value)
    for pattern in patterns:
        assert pattern in message, message
    return message


@pytest.mark.parametrize("key", ["fps", "features", "video_path", "total_frames", "total_episodes"])
def test_a_missing_info_key_is_named_with_the_file(copy_of, key):
    root = copy_of(lambda info: info.pop(key))
    refused(root, str(root / "meta" / "info.json"), repr(key))


def test_the_trainer_names_the_file_not_a_bare_key(copy_of, tmp_path, capsys):
    root = copy_of(lambda info: info.pop("fps"))
    assert train.main(["--dataset", str(root), "--out", str(tmp_path / "out"), "--steps", "1"]) == 2
    error = capsys.readouterr().err.strip()
    assert error == f"tavis_baseline.train: {root / 'meta' / 'info.json'} has no 'fps'"
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_a_missing_feature_shape_is_named(copy_of):
    root = copy_of(lambda info: info["features"]["action"].pop("shape"))
    refused(root, "info.json", "features['action']", "'shape'")


@pytest.mark.parametrize("template", ["../../etc/x", "/etc/passwd", "videos/../../../x/{video_key}.mp4"])
def test_a_video_path_outside_the_dataset_is_refused(copy_of, template):
    root = copy_of(lambda info: info.update(video_path=template))
    refused(root, str(root / "meta" / "info.json"), repr(template), "not a path inside the dataset")


def test_a_video_path_that_does_not_format_is_named(copy_of):
    root = copy_of(lambda info: info.update(video_path="videos/{camera}/x.mp4"))
    refused(root, "info.json", "'videos/{camera}/x.mp4'", "does not format")


@pytest.mark.parametrize("key", ["total_frames", "total_episodes"])
def test_totals_that_disagree_with_the_data_name_both_numbers(copy_of, demo_dataset, key):
    said = json.loads((demo_dataset / "meta" / "info.json").read_text())[key]
    root = copy_of(lambda info: info.update({key: said + 1}))
    message = refused(root, "info.json", f"{key} {said + 1}")
    assert f" {said}:" in message, message


def test_unreadable_json_and_a_missing_stats_file_are_named(copy_of):
    root = copy_of()
    (root / "meta" / "info.json").write_text("{ not json")
    refused(root, str(root / "meta" / "info.json"), "not valid JSON")
    shutil.rmtree(root)
    root = copy_of()
    (root / "meta" / "stats.json").unlink()
    refused(root, str(root / "meta" / "stats.json"), "missing")


def test_a_missing_parquet_column_is_a_value_error_naming_the_file(copy_of):
    root = copy_of(lambda info: info["features"].update({"observation.images.OBS_HEAD_X": {"dtype": "video", "shape": [72, 96, 3]}}))
    with pytest.raises(ValueError, match=r"episodes.*has no column 'videos/observation.images.OBS_HEAD_X/chunk_index'"):
        DemoDataset(root, ["observation.images.OBS_HEAD_X"])


def test_bad_statistics_name_the_stats_file(copy_of, tmp_path, capsys):
    root = copy_of()
    path = root / "meta" / "stats.json"
    stats = json.loads(path.read_text())
    stats["action"]["std"] = "wide"
    path.write_text(json.dumps(stats))
    assert train.main(["--dataset", str(root), "--out", str(tmp_path / "out"), "--steps", "1", "--image-size", "32x24"]) == 2
    assert f"{path}: the mean/std of 'action' are not lists of numbers" in capsys.readouterr().err
