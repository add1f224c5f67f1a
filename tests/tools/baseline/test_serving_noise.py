"""The flow head's serving noise: a function of (the checkpoint's noise_seed, the request's
episode_index and step), which tavis_server passes in every batch. The same episode and step get
the same chunk whatever env runs them and whatever shares the batch, so a served cell repeats run
after run (and with any --envs); another seed, episode or step gets another chunk, even for the
same observation. A batch without the ids (not from tavis_server) falls back to the observation."""

import asyncio
import json
import shutil

import numpy as np
import pytest
import torch

from test_serve import HEIGHT, WIDTH, Server, ask_steps
from test_train import run
from tavis_baseline import checkpoint


@pytest.fixture(scope="module")
def flow_checkpoint(demo_dataset, tmp_path_factory):
    out = tmp_path_factory.mktemp("noise") / "flow"
    assert run(demo_dataset, out, "--head", "flow", "--flow-width", "16", "--steps", "2", "--executed-steps", "1") == 0
    return out


def still_batch(policy, episodes, steps, envs=None, picture=0):
    """A batch of len(episodes) envs whose history holds one observation repeated (the
    `picture`-th), with tavis_server's ids."""
    config = policy.config
    generator = torch.Generator().manual_seed(picture)
    envs_and_steps = (len(episodes), config.n_obs_steps)
    batch = {key: torch.rand(1, 1, 3, HEIGHT, WIDTH, generator=generator).expand(*envs_and_steps, -1, -1, -1)
             for key in config.image_keys}
    batch["observation.state"] = torch.rand(1, 1, config.state_dim, generator=generator).expand(*envs_and_steps, -1)
    batch.update(env_index=torch.tensor(envs if envs is not None else list(range(len(episodes)))),
                 episode_index=torch.tensor(episodes), step=torch.tensor(steps))
    return batch


def test_the_noise_follows_seed_episode_and_step_not_the_env_or_the_observation(flow_checkpoint, tmp_path):
    policy = checkpoint.load(flow_checkpoint)
    chunk = policy.predict_action_chunk
    first = chunk(still_batch(policy, [5, 5, 6], [1, 2, 1]))
    # The same observation at another step or in another episode: another chunk.
    assert not torch.allclose(first[0], first[1]) and not torch.allclose(first[0], first[2])
    # The same (episode, step) in another env, alone in its batch: the same chunk.
    assert torch.allclose(chunk(still_batch(policy, [5], [1], envs=[3]))[0], first[0], atol=1e-5)
    # ... and the same noise for another observation (only the network's input differs).
    images, state = policy._inputs(still_batch(policy, [5], [1], picture=1))
    other = policy.serving_noise(images, state, [(5, 1)])
    images, state = policy._inputs(still_batch(policy, [5], [1]))
    assert torch.equal(other, policy.serving_noise(images, state, [(5, 1)]))
    assert policy.metadata["noise"].startswith("from (noise_seed, episode_index, step)")

    # Another noise_seed (the training --seed), the same weights: another chunk.
    reseeded = tmp_path / "reseeded"
    shutil.copytree(flow_checkpoint, reseeded)
    config = json.loads((reseeded / "config.json").read_text())
    config["noise_seed"] += 1
    (reseeded / "config.json").write_text(json.dumps(config))
    assert not torch.allclose(checkpoint.load(reseeded).predict_action_chunk(still_batch(policy, [5], [1]))[0], first[0])

    # Ids that do not match the batch are refused, naming them.
    with pytest.raises(ValueError, match="episode_index"):
        chunk({**still_batch(policy, [5, 5], [1, 2]), "episode_index": torch.tensor([5])})


def still_requests(episode, env, steps):
    rng = np.random.default_rng(11)
    arrays = {f"observation.images.{camera}": rng.integers(0, 256, (HEIGHT, WIDTH, 3), dtype=np.uint8)
              for camera in ("OBS_HEAD", "OBS_WRIST_LEFT", "OBS_WRIST_RIGHT")}
    arrays["observation.state"] = rng.standard_normal(34).astype(np.float32)
    return [dict(arrays, prompt="pick the cube", env_index=env, episode_index=episode, step=step, is_first=step == 0)
            for step in range(steps)]


def test_served_replies_repeat_and_follow_the_requests_ids(flow_checkpoint):
    def served(requests):
        server = Server(flow_checkpoint)
        try:
            _, replies = asyncio.run(asyncio.wait_for(ask_steps(server.url, requests), 120))
        finally:
            server.stop()
        return replies

    requests = still_requests(episode=7, env=0, steps=3) + still_requests(episode=7, env=1, steps=3)
    first, again = served(requests), served(requests)
    assert all(np.array_equal(a, b) for a, b in zip(first, again))  # run to run, bit for bit
    # One observation throughout, yet each step its own chunk; env 1's episode 7 is env 0's.
    assert not np.allclose(first[1], first[2])
    for step in range(3):
        np.testing.assert_allclose(first[3 + step], first[step], atol=1e-5)
