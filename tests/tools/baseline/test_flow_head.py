"""The flow-matching head (--head flow): it learns on the CPU, a saved checkpoint serves a whole
cell to `tavis eval`, and its served records repeat run to run (its noise is a function of the
seed and the observation, not of a global random stream)."""

import json

import numpy as np
import torch

from conftest import run_tavis
from test_serve import HEIGHT, WIDTH, Server
from test_train import FAST, log_losses, run
from tavis_baseline import checkpoint


def test_flow_loss_falls_in_100_steps(demo_dataset, tmp_path):
    out = tmp_path / "flow"
    assert run(demo_dataset, out, "--head", "flow", "--flow-width", "64", "--steps", "100", "--seed", "1",
               "--lr", "1e-3") == 0
    losses = log_losses(out)
    assert len(losses) == 10 and np.mean(losses[-2:]) < 0.7 * losses[0], losses
    assert json.loads((out / "config.json").read_text())["head"] == "flow"


def test_flow_chunks_depend_on_the_observation_only(demo_dataset, tmp_path):
    out = tmp_path / "flow"
    assert run(demo_dataset, out, "--head", "flow", "--steps", "2") == 0
    policy = checkpoint.load(out)
    config = policy.config
    assert config.flow_steps == 10 and policy.metadata["head"] == "flow"
    batch = {key: torch.rand(3, config.n_obs_steps, 3, 24, 32) for key in config.image_keys}
    batch["observation.state"] = torch.rand(3, config.n_obs_steps, config.state_dim)
    torch.manual_seed(123)
    first = policy.predict_action_chunk(batch)
    torch.manual_seed(456)  # the global stream does not matter
    again = policy.predict_action_chunk(batch)
    alone = policy.predict_action_chunk({key: value[1:2] for key, value in batch.items()})
    assert torch.equal(first, again)
    # Nor which envs share the batch: the same noise (the network's batched arithmetic may differ
    # in the last bits).
    images, state = policy._inputs(batch)
    lone_images, lone_state = policy._inputs({key: value[1:2] for key, value in batch.items()})
    assert torch.equal(policy.serving_noise(images, state)[1:2], policy.serving_noise(lone_images, lone_state))
    assert torch.allclose(first[1:2], alone, atol=1e-5)
    assert not torch.equal(first[0], first[1])  # different observations, different noise


def served_cell(ckpt, out):
    server = Server(ckpt)
    try:
        run_tavis("eval", "--task", "clutter-pick-cube", "--robot", "gr1t2", "--seed", "3", "--episodes", "2",
                  "--envs", "2", "--policy", "openpi", "--server", server.url, "--replan-steps", "1",
                  "--image-size", f"{WIDTH}x{HEIGHT}", "--quiet", "--out", str(out))
    finally:
        server.stop()
    return [json.loads(line) for line in (out / "episodes.jsonl").read_text().splitlines()]


def test_a_served_flow_checkpoint_completes_a_cell_the_same_twice(demo_dataset, tmp_path):
    ckpt = tmp_path / "flow"
    assert run(demo_dataset, ckpt, "--head", "flow", "--steps", "2") == 0
    first = served_cell(ckpt, tmp_path / "a")
    second = served_cell(ckpt, tmp_path / "b")
    assert len(first) == 2 and first == second
    summary = json.loads((tmp_path / "a" / "summary.json").read_text())
    assert summary["server_metadata"][0]["head"] == "flow"
