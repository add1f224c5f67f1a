"""The in-memory loader (tavis_baseline.dataset) against readers and renderers we did not write it
with: the Parquet columns as hyparquet reads them (tests/js/read_parquet.mjs, under Node), and the
frames as `tavis render` draws the same scene at the same control tick."""

import json
import os
import subprocess
from pathlib import Path

import av
import numpy as np
import pytest
import torch

from conftest import CONTROL_HZ, FPS, HEIGHT, SEED, WIDTH, run_tavis
from tavis_baseline.dataset import DemoDataset

CAMERAS = {"head": "observation.images.OBS_HEAD", "left_wrist": "observation.images.OBS_WRIST_LEFT"}


@pytest.fixture(scope="module")
def loaded(demo_dataset):
    return DemoDataset(demo_dataset, list(CAMERAS.values()))


def hyparquet_rows(path):
    js_dir = Path(os.environ.get("TAVIS_JS_DIR", Path(__file__).resolve().parents[2] / "js"))
    if not (js_dir / "node_modules" / "hyparquet").is_dir():
        raise RuntimeError(f"{js_dir}/node_modules lacks hyparquet: run .ci/install-deps")
    result = subprocess.run(["node", str(js_dir / "read_parquet.mjs"), str(path)], capture_output=True, text=True,
                            timeout=120, check=True)
    return json.loads(result.stdout)["hyparquet"]["rows"]


def test_columns_equal_what_hyparquet_reads(demo_dataset, loaded):
    rows = hyparquet_rows(demo_dataset / "data" / "chunk-000" / "file-000.parquet")
    assert len(rows) == len(loaded) > 0
    np.testing.assert_array_equal(loaded.action, np.array([row["action"] for row in rows], np.float32))
    np.testing.assert_array_equal(loaded.state, np.array([row["observation.state"] for row in rows], np.float32))
    np.testing.assert_array_equal(loaded.row_episode, [int(row["episode_index"]) for row in rows])
    np.testing.assert_array_equal(loaded.frame_index, [int(row["frame_index"]) for row in rows])
    assert loaded.state.shape[1] == 34 and loaded.action.shape[1] == 19


def read_png(path):
    with av.open(str(path)) as container:
        return next(container.decode(video=0)).to_ndarray(format="rgb24")


def psnr(a, b):
    mse = np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2)
    return float("inf") if mse == 0 else 10 * np.log10(255.0 ** 2 / mse)


def test_frames_equal_tavis_render_of_the_same_tick(demo_dataset, loaded, tmp_path):
    # Frame t of an episode is the observation after the action of control tick stride*t, i.e.
    # after stride*t + 1 ticks (batch/dataset/demo_recorder.h); `tavis render --steps N` draws the
    # scene after N ticks. A frame 3 frames off must match worse: the alignment is what is tested.
    episode, frame = 1, 12
    stride = CONTROL_HZ // FPS
    row = int(np.flatnonzero((loaded.row_episode == episode) & (loaded.frame_index == frame))[0])
    scores = {}
    for shift in (0, 3):
        ticks = stride * (frame + shift) + 1
        out = tmp_path / f"ticks{ticks}"
        run_tavis("render", "--task", "clutter-pick-cube", "--robot", "gr1t2", "--seed", str(SEED), "--episode",
                  str(episode), "--width", str(WIDTH), "--height", str(HEIGHT), "--steps", str(ticks), "--out", str(out))
        for camera, key in CAMERAS.items():
            rendered = read_png(out / f"tick{ticks}_{camera}.png")
            loaded_frame = loaded.images[key][row].permute(1, 2, 0).numpy()
            assert rendered.shape == loaded_frame.shape == (HEIGHT, WIDTH, 3)
            scores[camera, shift] = psnr(loaded_frame, rendered)
    for camera in CAMERAS:
        assert scores[camera, 0] >= 30, scores
    assert scores["head", 0] > scores["head", 3] + 3, scores


def test_frames_resized_on_decode(demo_dataset, loaded):
    small = DemoDataset(demo_dataset, [CAMERAS["head"]], image_size=(24, 32), episodes=[2])
    assert small.images[CAMERAS["head"]].shape == (len(small), 3, 24, 32)
    rows = np.flatnonzero(loaded.row_episode == 2)
    np.testing.assert_array_equal(small.action, loaded.action[rows])
    full = loaded.images[CAMERAS["head"]][rows].float()
    shrunk = torch.nn.functional.interpolate(full, size=(24, 32), mode="area")
    assert torch.mean(torch.abs(shrunk - small.images[CAMERAS["head"]].float())) < 8


def test_sample_windows_at_episode_edges(loaded):
    # The first and last rows of episode 1, with a history reaching 2 back and a chunk 3 ahead.
    rows = np.flatnonzero(loaded.row_episode == 1)
    first, last = int(rows[0]), int(rows[-1])
    batch = loaded.sample(torch.tensor([first, last]), obs_offsets=[-2, 0], action_offsets=[1, 2, 3])
    assert batch["observation.state_is_pad"].tolist() == [[True, False], [False, False]]
    assert batch["action_is_pad"].tolist() == [[False, False, False], [True, True, True]]
    np.testing.assert_array_equal(batch["observation.state"][0].numpy(), loaded.state[[first, first]])
    np.testing.assert_array_equal(batch["action"][1].numpy(), loaded.action[[last] * 3])
    np.testing.assert_array_equal(batch["action"][0].numpy(), loaded.action[first + 1:first + 4])
    head = loaded.images[CAMERAS["head"]]
    assert torch.equal(batch[CAMERAS["head"]][1], head[[last - 2, last]])


def test_unknown_camera_and_missing_dataset_are_named(demo_dataset, tmp_path):
    with pytest.raises(ValueError, match="OBS_NOPE"):
        DemoDataset(demo_dataset, ["observation.images.OBS_NOPE"])
    with pytest.raises(ValueError, match="info.json is missing"):
        DemoDataset(tmp_path, [CAMERAS["head"]])
    with pytest.raises(ValueError, match=r"asked for \[7\]"):
        DemoDataset(demo_dataset, [CAMERAS["head"]], episodes=[7])


def test_opencv_frames_equal_pyav_frames(demo_dataset, loaded):
    # GPU machines often have OpenCV and no PyAV: both decoders must give the same frames.
    import cv2  # noqa: F401  (python3-opencv, .ci/install-deps)
    other = DemoDataset(demo_dataset, list(CAMERAS.values()), video_backend="opencv")
    for key in CAMERAS.values():
        assert other.images[key].shape == loaded.images[key].shape
        assert psnr(other.images[key].numpy(), loaded.images[key].numpy()) >= 40
