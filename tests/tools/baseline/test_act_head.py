"""The ACT head (--head act): it learns on the CPU, its served chunks are a function of the
observation (z = 0), a saved checkpoint serves a whole cell to `tavis eval` with and without
temporal ensembling, the same records run after run, and the ensembled replies are what the
policy's own chunks ensemble to."""

import json

import numpy as np
import pytest
import torch

from test_flow_head import served_cell
from test_serve import own_chunks, serve_steps
from test_train import log_losses, run
from tavis_baseline import checkpoint, serve
from tavis_baseline.temporal_ensemble import TemporalEnsemble

TINY_ACT = ["--head", "act", "--act-d-model", "32", "--act-heads", "4", "--act-encoder-layers", "1",
            "--act-vae-layers", "1", "--act-feedforward", "64", "--act-latent-dim", "8"]


@pytest.fixture(scope="module")
def act_checkpoints(demo_dataset, tmp_path_factory):
    """Two tiny act checkpoints of 2 steps: "ensembled" stores temporal ensembling (m = 0.01),
    "queued" a queue of 4 rows (test_train's FAST)."""
    folder = tmp_path_factory.mktemp("act")
    made = {"ensembled": folder / "ensembled", "queued": folder / "queued"}
    assert run(demo_dataset, made["ensembled"], *TINY_ACT, "--steps", "2", "--executed-steps", "1",
               "--temporal-ensemble", "0.01") == 0
    assert run(demo_dataset, made["queued"], *TINY_ACT, "--steps", "2") == 0
    return made


def test_act_loss_falls_in_100_steps(demo_dataset, tmp_path):
    out = tmp_path / "act"
    assert run(demo_dataset, out, *TINY_ACT, "--steps", "100", "--seed", "1", "--lr", "1e-3") == 0
    losses = log_losses(out)
    assert len(losses) == 10 and np.mean(losses[-2:]) < 0.7 * losses[0], losses
    config = json.loads((out / "config.json").read_text())
    assert config["head"] == "act" and config["act_d_model"] == 32 and config["act_kl_weight"] == 10.0


def test_act_chunks_depend_on_the_observation_only(act_checkpoints):
    policy = checkpoint.load(act_checkpoints["queued"])
    config = policy.config
    assert policy.metadata["head"] == "act" and policy.metadata["act"]["latent_dim"] == 8
    batch = {key: torch.rand(3, config.n_obs_steps, 3, 24, 32) for key in config.image_keys}
    batch["observation.state"] = torch.rand(3, config.n_obs_steps, config.state_dim)
    torch.manual_seed(123)
    first = policy.predict_action_chunk(batch)
    torch.manual_seed(456)  # z = 0 and no dropout when served: the global stream does not matter
    assert torch.equal(first, policy.predict_action_chunk(batch))
    assert first.shape == (3, 4, 19) and not torch.equal(first[0], first[1])


def test_select_action_ensembles_a_forward_pass_per_call_until_reset(act_checkpoints):
    policy = checkpoint.load(act_checkpoints["ensembled"])
    config = policy.config
    assert config.temporal_ensemble == 0.01 and config.executed_steps == 1
    batches = []
    for seed in range(3):
        generator = torch.Generator().manual_seed(seed)
        batch = {key: torch.rand(2, config.n_obs_steps, 3, 24, 32, generator=generator) for key in config.image_keys}
        batch["observation.state"] = torch.rand(2, config.n_obs_steps, config.state_dim, generator=generator)
        batches.append(batch)
    chunks = [policy.predict_action_chunk(batch) for batch in batches]
    assert chunks[0].shape == (2, config.chunk_size, 19)  # every row, to be averaged in
    ensemble = TemporalEnsemble(0.01)
    policy.reset()
    for batch, chunk in zip(batches, chunks):
        assert torch.allclose(policy.select_action(batch), torch.from_numpy(ensemble.add(chunk.numpy())), atol=1e-6)
    policy.reset()  # a new episode: nothing earlier is averaged in
    assert torch.allclose(policy.select_action(batches[2]), chunks[2][:, 0], atol=1e-6)


def test_served_temporal_ensembling_averages_the_policys_own_chunks(act_checkpoints):
    requests, metadata, replies, _ = serve_steps(act_checkpoints["queued"], "--temporal-ensemble", "0.5")
    assert metadata["temporal_ensemble"] == 0.5 and metadata["executed_steps"] == 1
    assert metadata["action_queue"] is False and metadata["n_action_steps"] == 1 and metadata["action_horizon"] == 1
    assert metadata["chunk_execution"].startswith("temporal ensembling (m = 0.5)")
    ensemble = TemporalEnsemble(0.5)
    chunks = own_chunks(act_checkpoints["queued"], requests)
    expected = [ensemble.add(chunk) for chunk in chunks]
    for step, reply in enumerate(replies):
        assert reply.shape == (1, 19)
        np.testing.assert_allclose(reply[0], expected[step], atol=1e-5, err_msg=f"step {step}")
    # ... which re-planning (the first row of each step's own chunk) would not be.
    assert not np.allclose(replies[3][0], chunks[3][0], atol=1e-5)


def test_a_served_act_checkpoint_completes_a_cell_the_same_twice_with_and_without_ensembling(act_checkpoints,
                                                                                              tmp_path):
    first = served_cell(act_checkpoints["ensembled"], tmp_path / "a")
    second = served_cell(act_checkpoints["ensembled"], tmp_path / "b")
    assert len(first) == 2 and first == second
    [metadata] = json.loads((tmp_path / "a" / "summary.json").read_text())["server_metadata"]
    assert metadata["head"] == "act" and metadata["temporal_ensemble"] == 0.01
    assert metadata["chunk_execution"].startswith("temporal ensembling (m = 0.01)")
    queued = served_cell(act_checkpoints["queued"], tmp_path / "c")
    assert len(queued) == 2
    [metadata] = json.loads((tmp_path / "c" / "summary.json").read_text())["server_metadata"]
    assert "temporal_ensemble" not in metadata and metadata["chunk_execution"].startswith("queue of 4 rows")


def test_bad_act_and_ensembling_options_are_refused_before_anything_is_written(demo_dataset, act_checkpoints,
                                                                             tmp_path, capsys):
    for extra, message in ((["--executed-steps", "1", "--temporal-ensemble", "-1"], "temporal_ensemble -1.0"),
                           (["--temporal-ensemble", "0.01", "--executed-steps", "4"], "--executed-steps 4"),
                           (["--act-d-model", "30"], "act_d_model a multiple of act_heads")):
        with pytest.raises(SystemExit) as exited:
            run(demo_dataset, tmp_path / "out", *TINY_ACT, *extra)
        assert exited.value.code == 2 and message in capsys.readouterr().err
        assert not (tmp_path / "out").exists()
    ckpt = str(act_checkpoints["ensembled"])
    assert serve.main([ckpt, "--temporal-ensemble", "0.01", "--executed-steps", "4"]) == 2
    assert "--executed-steps 4 must be 1" in capsys.readouterr().err
    assert serve.main([ckpt, "--temporal-ensemble", "nan"]) == 2
    assert "--temporal-ensemble nan" in capsys.readouterr().err
