"""The trainer and the trained policy's LeRobot interface, on the CPU."""

import json

import numpy as np
import pytest
import torch

from tavis_baseline import checkpoint, train
from tavis_baseline.config import NECK_ACTION_DIMS

FAST = ["--batch-size", "16", "--image-size", "32x24", "--threads", "2", "--warmup-steps", "10", "--log-every", "10",
        "--chunk-size", "8", "--n-action-steps", "4", "--history-stride", "4"]


def run(dataset, out, *extra):
    return train.main(["--dataset", str(dataset), "--out", str(out), *FAST, *extra])


def log_losses(folder):
    return [json.loads(line)["loss"] for line in (folder / "train_log.jsonl").read_text().splitlines()]


def test_loss_falls_in_100_steps(demo_dataset, tmp_path):
    out = tmp_path / "head"
    assert run(demo_dataset, out, "--steps", "100", "--seed", "1", "--lr", "1e-3") == 0
    losses = log_losses(out)
    assert len(losses) == 10
    assert np.mean(losses[-2:]) < 0.7 * losses[0], losses
    summary = json.loads((out / "training.json").read_text())
    assert summary["steps_done"] == 100 and summary["stopped"] == "steps"


def test_same_seed_same_weights_on_cpu(demo_dataset, tmp_path):
    weights = []
    for name, seed in (("a", 4), ("b", 4), ("c", 5)):
        assert run(demo_dataset, tmp_path / name, "--steps", "3", "--seed", str(seed)) == 0
        weights.append(torch.load(tmp_path / name / "model.pt"))
    assert all(torch.equal(weights[0][key], weights[1][key]) for key in weights[0])
    assert not all(torch.equal(weights[0][key], weights[2][key]) for key in weights[0])


def test_time_budget_stops_cleanly_with_a_checkpoint(demo_dataset, tmp_path):
    out = tmp_path / "budget"
    assert run(demo_dataset, out, "--steps", "100000", "--time-budget-s", "0.01") == 0
    summary = json.loads((out / "training.json").read_text())
    assert summary["stopped"] == "time_budget" and summary["steps_done"] < 100000
    checkpoint.load(out)  # loads


def test_fixed_checkpoint_serves_through_lerobots_interface(demo_dataset, tmp_path):
    out = tmp_path / "fixed"
    assert run(demo_dataset, out, "--camera", "fixed", "--steps", "2", "--val-episodes", "1") == 0
    assert "validation_l1" in json.loads((out / "training.json").read_text())
    policy = checkpoint.load(out)
    config = policy.config
    assert config.image_keys[0] == "observation.images.OBS_FIXED"
    assert config.n_obs_steps == 5 and config.history_positions == [0, 4]
    # What tavis_server sends: n_obs_steps stacked observations, images float CHW at the client's size.
    batch = {key: torch.rand(3, config.n_obs_steps, 3, 240, 320) for key in config.image_keys}
    batch["observation.state"] = torch.rand(3, config.n_obs_steps, config.state_dim)
    chunk = policy.predict_action_chunk(batch)
    assert chunk.shape == (3, config.n_action_steps, 19)
    assert torch.all(chunk[..., NECK_ACTION_DIMS] == 0)
    policy.reset()
    actions = [policy.select_action(batch) for _ in range(config.n_action_steps)]
    assert torch.equal(torch.stack(actions, 1), chunk)  # the queue hands out the chunk row by row
    with pytest.raises(KeyError, match="OBS_FIXED"):
        policy.predict_action_chunk({"observation.state": batch["observation.state"]})


def test_bad_arguments_fail_before_anything_is_lost(demo_dataset, tmp_path, capsys):
    out = tmp_path / "kept"
    out.mkdir()
    (out / "model.pt").write_text("earlier")
    assert run(demo_dataset, out, "--steps", "1") == 2
    assert "not empty" in capsys.readouterr().err
    assert (out / "model.pt").read_text() == "earlier"
    assert run(tmp_path / "nothing", tmp_path / "x", "--steps", "1") == 2
    assert "nothing" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        run(demo_dataset, tmp_path / "y", "--image-size", "96")


CHECKPOINT_FILES = ("config.json", "stats.json", "model.pt", "training.json", "train_log.jsonl")


def folder_bytes(folder):
    return {path.name: path.read_bytes() for path in sorted(folder.iterdir())}


def test_overwrite_keeps_the_old_checkpoint_whole_until_the_new_one_is_saved(demo_dataset, tmp_path, monkeypatch):
    out = tmp_path / "ckpt"
    assert run(demo_dataset, out, "--steps", "2", "--seed", "1", "--log-every", "1") == 0
    before = folder_bytes(out)
    assert sorted(before) == sorted(CHECKPOINT_FILES) and len(log_losses(out)) == 2

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    # Interrupted before its first save (Ctrl-C at the save), then inside the save after some new
    # files were written: either way the old checkpoint, log included, is as it was.
    for module, name in ((checkpoint, "save"), (torch, "save")):
        monkeypatch.setattr(module, name, interrupted)
        with pytest.raises(KeyboardInterrupt):
            run(demo_dataset, out, "--steps", "1", "--seed", "2", "--overwrite")
        monkeypatch.undo()
        after = folder_bytes(out)
        assert {name: after[name] for name in CHECKPOINT_FILES} == before, name

    # The leftovers of those runs are the trainer's own: the next --overwrite replaces them, and the
    # checkpoint it saves holds the new run's log alone.
    assert run(demo_dataset, out, "--steps", "1", "--seed", "2", "--overwrite") == 0
    assert sorted(path.name for path in out.iterdir()) == sorted(CHECKPOINT_FILES)
    assert len(log_losses(out)) == 1
    assert (out / "model.pt").read_bytes() != before["model.pt"]


def test_overwrite_replaces_only_a_checkpoint(demo_dataset, tmp_path, capsys):
    out = tmp_path / "mixed"
    assert run(demo_dataset, out, "--steps", "2") == 0
    (out / "notes.txt").write_text("mine")
    (out / "plots").mkdir()
    before = folder_bytes(out / "plots"), (out / "model.pt").read_bytes()
    assert run(demo_dataset, out, "--steps", "2", "--seed", "9", "--overwrite") == 2
    error = capsys.readouterr().err
    assert "notes.txt" in error and "plots" in error and "did not write" in error
    assert (out / "notes.txt").read_text() == "mine" and (folder_bytes(out / "plots"), (out / "model.pt").read_bytes()) == before


def test_the_rate_is_logged_and_summarised(demo_dataset, tmp_path):
    out = tmp_path / "rate"
    assert run(demo_dataset, out, "--steps", "4", "--log-every", "2", "--no-compile") == 0
    summary = json.loads((out / "training.json").read_text())
    assert summary["step_mode"] == "eager"  # the CPU path, whatever the flag
    assert summary["steps_per_s"] > 0 and summary["samples_per_s"] == pytest.approx(16 * summary["steps_per_s"], rel=0.01, abs=0.1)
    for line in (out / "train_log.jsonl").read_text().splitlines():
        entry = json.loads(line)
        assert entry["samples_per_s"] == pytest.approx(16 * entry["steps_per_s"])


def test_device_side_sampling_draws_what_the_eager_step_draws(demo_dataset):
    # The CUDA-graph step samples on the GPU: offsets as device tensors, shifts drawn there. Here on
    # the CPU: the windows equal the list-offset ones, and the shifts are the same distribution.
    from tavis_baseline.augment import random_shift, random_shift_on_device, shift_by
    from tavis_baseline.dataset import DemoDataset
    from tavis_baseline.train_step import batch_loss

    images = torch.rand(5, 2, 3, 12, 16)
    assert torch.equal(shift_by(images, 4, torch.full((5,), 4), torch.full((5,), 4)), images)
    torch.manual_seed(0)
    ramp = torch.arange(16.0).expand(4000, 1, 1, 12, 16)  # column index: the shift is readable
    device_dx = random_shift_on_device(ramp, 4)[:, 0, 0, 6, 8] - 4  # = dx (column 8 + dx of the padded ramp)
    eager_dx = random_shift(ramp, 4, torch.Generator().manual_seed(1))[:, 0, 0, 6, 8] - 4
    for drawn in (device_dx, eager_dx):
        counts = torch.bincount(drawn.long(), minlength=9)
        assert counts.numel() == 9 and counts.min() > 4000 / 9 * 0.8, counts

    data = DemoDataset(demo_dataset, ["observation.images.OBS_HEAD", "observation.images.OBS_WRIST_LEFT",
                                      "observation.images.OBS_WRIST_RIGHT"], image_size=(24, 32), episodes=[0])
    from tavis_baseline.train import arguments, build_policy
    policy = build_policy(data, arguments(["--dataset", "x", "--out", "y", *FAST]))
    rows = torch.tensor([0, 3, len(data) - 1])
    offsets = (torch.tensor(policy.config.obs_offsets), torch.tensor(policy.config.action_offsets))
    with torch.no_grad():
        assert torch.equal(batch_loss(policy, data, rows, None, augment=False),
                           batch_loss(policy, data, rows, None, augment=False, offsets=offsets))


def test_the_graphed_step_survives_saves_and_validation_between_steps(demo_dataset, tmp_path, monkeypatch):
    # The compiled CUDA run's step (train_step.GraphedStep: rows and shifts drawn on the device, its
    # own optimizer loop), with saves and validation between steps, as far as the CPU allows: here
    # it runs uncaptured. On CUDA the captured step crashed at the first save with validation, when
    # tensors the graph read had been freed and the validation's allocations reused them.
    monkeypatch.setattr(train, "can_compile", lambda device: True)
    out = tmp_path / "graphed"
    assert run(demo_dataset, out, "--steps", "6", "--save-every", "2", "--log-every", "2", "--val-episodes", "1") == 0
    summary = json.loads((out / "training.json").read_text())
    assert summary["step_mode"] == "device-sampled, uncaptured" and summary["steps_done"] == 6
    assert np.isfinite(summary["validation_l1"])
    losses = log_losses(out)
    assert len(losses) == 3 and np.all(np.isfinite(losses))
    checkpoint.load(out)
