"""The camera encoders (--vision cnn | resnet18) and the random crop (--crop-ratio): a small
ResNet-18 learns on the CPU, its checkpoint is rebuilt and served through a whole cell, old
checkpoints load as the cnn they were, and the crop is one place per sample drawn from the step's
generator (training) or the centre (validation and serving)."""

import json

import numpy as np
import pytest
import torch

from test_flow_head import served_cell
from test_train import log_losses, run
from tavis_baseline import checkpoint
from tavis_baseline.augment import center_crop, random_crop
from tavis_baseline.config import BaselineConfig
from tavis_baseline.policy import BaselinePolicy
from tavis_baseline.vision import ResNet18Encoder

RESNET = ["--vision", "resnet18", "--vision-width", "8", "--crop-ratio", "0.9"]


def untrained(**settings):
    config = BaselineConfig(**{"history_stride": 2, **settings})
    return BaselinePolicy(config, torch.zeros(34), torch.ones(34), torch.zeros(19), torch.ones(19))


def test_resnet18_loss_falls_in_100_steps_and_its_checkpoint_rebuilds(demo_dataset, tmp_path):
    out = tmp_path / "resnet"
    # One history frame: half the encoder's images, so that the test costs about the cnn's.
    assert run(demo_dataset, out, *RESNET, "--history-frames", "1", "--steps", "100", "--seed", "1", "--lr", "1e-3") == 0
    losses = log_losses(out)
    assert len(losses) == 10 and np.mean(losses[-2:]) < 0.7 * losses[0], losses
    config = json.loads((out / "config.json").read_text())
    assert (config["vision"], config["vision_width"], config["crop_ratio"]) == ("resnet18", 8, 0.9)
    assert config["shift_px"] == 0  # resnet18's default augmentation is the crop alone
    policy = checkpoint.load(out)  # strict: every saved weight has its place in the rebuilt model
    assert all(isinstance(encoder, ResNet18Encoder) for encoder in policy.encoders)
    assert policy.config.crop_size == [22, 29]  # 0.9 of 24x32
    assert policy.metadata["vision"] == "resnet18" and policy.metadata["crop_hw"] == [22, 29]


def test_a_served_resnet18_checkpoint_completes_a_cell(demo_dataset, tmp_path):
    ckpt = tmp_path / "resnet"
    assert run(demo_dataset, ckpt, *RESNET, "--steps", "2") == 0
    records = served_cell(ckpt, tmp_path / "cell")
    assert [record["episode"] for record in records] == [0, 1]
    summary = json.loads((tmp_path / "cell" / "summary.json").read_text())
    assert summary["server_metadata"][0]["vision"] == "resnet18"


def test_a_checkpoint_without_vision_fields_loads_as_the_cnn_it_was(demo_dataset, tmp_path):
    ckpt = tmp_path / "cnn"
    assert run(demo_dataset, ckpt, "--steps", "2") == 0
    config = json.loads((ckpt / "config.json").read_text())
    assert (config["vision"], config["crop_ratio"], config["shift_px"]) == ("cnn", 1.0, 4)
    for name in ("vision", "vision_width", "crop_ratio"):  # as written before the settings
        del config[name]
    (ckpt / "config.json").write_text(json.dumps(config))
    policy = checkpoint.load(ckpt)
    assert policy.config.vision == "cnn" and policy.config.crop_size == policy.config.image_size


@pytest.mark.parametrize("vision", ["cnn", "resnet18"])
@pytest.mark.parametrize("height,width", [(128, 128), (120, 160)])
def test_both_encoders_take_larger_images_with_a_crop(vision, height, width):
    policy = untrained(image_size=[height, width], vision=vision, vision_width=8, crop_ratio=0.9, cnn_widths=[8, 8, 8, 8],
                       history_frames=1)
    assert policy.config.crop_size == [round(height * 0.9), round(width * 0.9)]
    frames = [torch.rand(1, 1, 3, *policy.config.crop_size) for _ in policy.config.image_keys]
    loss = policy.loss(frames, torch.rand(1, 1, 34), torch.rand(1, 20, 19), torch.zeros(1, 20, dtype=torch.bool))
    loss.backward()
    assert torch.isfinite(loss) and all(p.grad is not None for p in policy.encoders.parameters())


def test_the_crop_is_one_place_per_sample_and_the_centre_when_served():
    index = torch.arange(12 * 16, dtype=torch.float32).view(12, 16)  # a pixel's value is its place
    images = index.expand(3000, 2, 3, 12, 16)
    cropped = random_crop(images, (10, 12), torch.Generator().manual_seed(0))
    assert cropped.shape == (3000, 2, 3, 10, 12)
    assert torch.equal(cropped[:, :1].expand_as(cropped), cropped)  # the same for history and channels
    top, left = (cropped[:, 0, 0, 0, 0] // 16).long(), (cropped[:, 0, 0, 0, 0] % 16).long()
    rows, cols = top[:, None, None] + torch.arange(10)[:, None], left[:, None, None] + torch.arange(12)
    assert torch.equal(cropped[:, 0, 0], index[rows, cols])
    for offsets, places in ((top, 3), (left, 5)):  # every place 0..H-h and 0..W-w, uniformly
        counts = torch.bincount(offsets, minlength=places)
        assert counts.numel() == places and counts.min() > 3000 / places * 0.8, counts
    drawn_on_device = random_crop(images, (10, 12))  # the CUDA graph's way: no CPU generator
    assert torch.equal(drawn_on_device[:, :1].expand_as(drawn_on_device), drawn_on_device)
    assert torch.equal(center_crop(images[:1], (10, 12))[0, 0, 0], index[1:11, 2:14])

    # A crop as large as the image draws nothing: the cnn's default keeps the step's random stream.
    generator = torch.Generator().manual_seed(5)
    assert random_crop(images, (12, 16), generator) is images
    assert torch.equal(generator.get_state(), torch.Generator().manual_seed(5).get_state())

    # Served, the policy sees the centre of what it is sent (after the resize to image_size).
    policy = untrained(image_size=[24, 32], vision="resnet18", vision_width=8, crop_ratio=0.75)
    batch = {key: torch.rand(1, policy.config.n_obs_steps, 3, 24, 32) for key in policy.config.image_keys}
    batch["observation.state"] = torch.rand(1, policy.config.n_obs_steps, 34)
    images_in, _ = policy._inputs(batch)
    assert torch.equal(images_in[0], batch[policy.config.image_keys[0]][:, [0, 2], :, 3:21, 4:28])


def test_bad_vision_settings_are_refused(demo_dataset, tmp_path, capsys):
    for bad, message in ((["--crop-ratio", "1.5"], "--crop-ratio"), (["--vision-width", "2"], "--vision-width"),
                         (["--vision", "vit"], "--vision")):
        with pytest.raises(SystemExit):
            run(demo_dataset, tmp_path / "x", *bad)
        assert message in capsys.readouterr().err
    assert run(demo_dataset, tmp_path / "y", "--crop-ratio", "0.1", "--steps", "1") == 2
    assert "crop_ratio 0.1" in capsys.readouterr().err
