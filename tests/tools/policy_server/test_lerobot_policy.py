"""A LeRobot-interface policy behind the server: per-(env, episode) history, one forward pass per
batched request, batched answers equal to per-env ones, the select_action slow path, processors."""

import numpy as np
import pytest
import torch

from conftest import batched, connect, observation, run
from history_policy import HistoryPolicy, SelectOnlyPolicy, expected_image_values
from tavis_server import LeRobotServedPolicy


def served(policy, **options):
    return LeRobotServedPolicy(policy, name="history", device="cpu", torch=torch, **options)


def ids(actions):
    """(oldest step, newest step, episode) the history policy read, from a chunk's first row."""
    return tuple(int(round(value * 1000)) for value in actions[0, :3])


# The history tests below turn the action queue off (it is on by default for n_obs_steps > 1,
# test_action_queue.py) so that every request is a forward pass whose inputs they can read back.


def test_history_is_kept_per_env_and_episode(serve):
    policy = HistoryPolicy(n_obs_steps=2, chunk=4)
    server = serve(served(policy, action_queue="off"))

    async def session():
        async with connect(server.url) as client:
            replies = {}
            # Two envs interleaved; env 1 starts its next episode at the end.
            for env, episode, step in [(0, 3, 0), (1, 8, 0), (0, 3, 1), (1, 8, 1), (0, 3, 2), (1, 8, 2), (1, 9, 0),
                                       (1, 9, 1)]:
                replies[(env, episode, step)] = await client.ask(observation(env, episode, step))
            return replies

    replies = run(session())
    # At is_first the history is two copies of the first observation; then (previous, current).
    assert ids(replies[(0, 3, 0)]["actions"]) == (0, 0, 3)
    assert ids(replies[(0, 3, 1)]["actions"]) == (0, 1, 3)
    assert ids(replies[(0, 3, 2)]["actions"]) == (1, 2, 3)
    assert ids(replies[(1, 8, 2)]["actions"]) == (1, 2, 8)
    assert ids(replies[(1, 9, 0)]["actions"]) == (0, 0, 9)  # the new episode forgot episode 8
    assert ids(replies[(1, 9, 1)]["actions"]) == (0, 1, 9)
    reply = replies[(0, 3, 2)]
    assert reply["actions"].shape == (4, 19) and reply["actions"].dtype == np.float32
    np.testing.assert_allclose(reply["actions"][:, 14], np.arange(4) * 1e-3, atol=1e-7)
    # Images reached the policy as float CHW in [0, 1], stacked over the history.
    image = observation(0, 3, 2)["observation.images.OBS_HEAD"]
    mean, pixel = expected_image_values(image)
    assert reply["actions"][0, 7] == pytest.approx(mean, rel=1e-5)
    assert reply["actions"][0, 8] == pixel
    assert policy.seen[0]["observation.images.OBS_HEAD"] == (torch.float32, (1, 2, 3, 6, 8))
    assert policy.seen[0]["observation.state"] == (torch.float32, (1, 2, 19))
    assert reply["actions"][0, 9] == pytest.approx(len("pick the cube") * 1e-3)
    assert "infer_ms" in reply["server_timing"]


def test_one_forward_pass_per_batched_request(serve):
    policy = HistoryPolicy(n_obs_steps=2, chunk=3)
    server = serve(served(policy, action_queue="off"))

    async def session():
        async with connect(server.url) as client:
            first = await client.ask(batched([observation(env, env + 10, 0) for env in range(3)]))
            second = await client.ask(batched([observation(env, env + 10, 1) for env in (0, 2)]))
            return first, second

    first, second = run(session())
    assert policy.batch_sizes == [3, 2] and policy.select_action_calls == 0
    assert first["actions"].shape == (3, 3, 19)
    assert second["actions"].shape == (2, 3, 19)
    assert [ids(chunk) for chunk in second["actions"]] == [(0, 1, 10), (0, 1, 12)]
    assert "prev_total_ms" in second["server_timing"] and "infer_ms" in second["server_timing"]


def test_batched_answers_equal_per_env_answers(serve):
    schedule = [[(0, 5, 0), (1, 6, 0), (2, 7, 0)], [(0, 5, 1), (1, 6, 1), (2, 7, 1)], [(0, 5, 2), (2, 7, 2)],
                [(1, 8, 0), (2, 7, 3)]]
    per_env_server = serve(served(HistoryPolicy(), action_queue="off"))
    batched_policy = HistoryPolicy()
    batched_server = serve(served(batched_policy, action_queue="off"))

    async def session():
        per_env, together = [], []
        async with connect(per_env_server.url) as client:
            for tick in schedule:
                per_env.append(np.stack([(await client.ask(observation(*ids_)))["actions"] for ids_ in tick]))
        async with connect(batched_server.url) as client:
            for tick in schedule:
                together.append((await client.ask(batched([observation(*ids_) for ids_ in tick])))["actions"])
        return per_env, together

    per_env, together = run(session())
    assert batched_policy.batch_sizes == [3, 3, 2, 2]
    for tick, (alone, batch) in enumerate(zip(per_env, together)):
        np.testing.assert_allclose(batch, alone, rtol=1e-6, atol=1e-7, err_msg=f"tick {tick}")
    assert [ids(chunk) for chunk in together[3]] == [(0, 0, 8), (2, 3, 7)]


def test_single_observation_policies_get_unstacked_batches(serve):
    policy = HistoryPolicy(n_obs_steps=1, chunk=2)
    server = serve(served(policy))

    async def session():
        async with connect(server.url) as client:
            await client.ask(batched([observation(env, 0, 0) for env in range(2)]))
            # n_obs_steps 1: a chunked client may skip steps.
            return await client.ask(batched([observation(env, 0, 5) for env in range(2)]))

    reply = run(session())
    assert policy.seen[1]["observation.images.OBS_HEAD"] == (torch.float32, (2, 3, 6, 8))
    assert policy.seen[1]["observation.state"] == (torch.float32, (2, 19))
    assert [ids(chunk) for chunk in reply["actions"]] == [(5, 5, 0), (5, 5, 0)]


def test_select_action_policies_get_one_copy_per_env(serve):
    SelectOnlyPolicy.total_calls = 0
    template = SelectOnlyPolicy()
    server = serve(served(template))

    async def session():
        async with connect(server.url) as client:
            metadata = client.metadata
            a = [await client.ask(observation(0, 1, step)) for step in range(3)]
            b = await client.ask(batched([observation(0, 1, 3), observation(1, 2, 0)]))
            c = await client.ask(observation(0, 4, 0))  # env 0's next episode resets its copy
            return metadata, a, b, c

    metadata, a, b, c = run(session())
    assert metadata["action_horizon"] == 1 and metadata["inference"] == "select_action per env"
    assert [reply["actions"].shape for reply in a] == [(1, 19)] * 3
    assert [round(reply["actions"][0, 0] * 1000) for reply in a] == [1, 2, 3]  # env 0's copy counts on
    assert b["actions"].shape == (2, 1, 19)
    assert [round(value * 1000) for value in b["actions"][:, 0, 0]] == [4, 1]  # env 1's copy is its own
    assert [round(value * 1000) for value in b["actions"][:, 0, 1]] == [3, 0]  # the step it was given
    assert round(c["actions"][0, 0] * 1000) == 1
    assert SelectOnlyPolicy.total_calls == 6 and template.calls_since_reset == 0  # the template is untouched


def test_processors_wrap_the_policy(serve):
    policy = HistoryPolicy(n_obs_steps=1, chunk=2)

    def preprocess(batch):
        batch = dict(batch)
        batch["observation.state"] = batch["observation.state"] + 100.0  # the step read back is +100
        return batch

    def postprocess(actions):
        return actions * torch.tensor([0.5] + [1.0] * 18)

    server = serve(served(policy, preprocess=preprocess, postprocess=postprocess))

    async def session():
        async with connect(server.url) as client:
            return await client.ask(observation(0, 0, 0))

    reply = run(session())
    assert reply["actions"][0, 0] == pytest.approx(0.5 * 100 * 1e-3)
    assert reply["actions"][0, 1] == pytest.approx(100 * 1e-3)


def test_n_action_steps_limits_the_chunk(serve):
    policy = HistoryPolicy(n_obs_steps=1, chunk=6)
    policy.config.n_action_steps = 4
    server = serve(served(policy))

    async def session():
        async with connect(server.url) as client:
            return client.metadata, await client.ask(observation(0, 0, 0))

    metadata, reply = run(session())
    assert metadata["action_horizon"] == 4
    assert reply["actions"].shape == (4, 19)
