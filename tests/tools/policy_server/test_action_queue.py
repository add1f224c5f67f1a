"""The server-side action queue (LeRobot's select_action schedule): a Diffusion-shaped policy with
n_obs_steps 2 asked at every step gets one forward pass per n_action_steps steps per env, each
reply the queued row for the step asked, and one pass over only the envs whose queue ran out."""

import numpy as np
import pytest
import torch

from conftest import batched, connect, expect_error, observation, run
from history_policy import DiffusionLikePolicy
from tavis_server import LeRobotServedPolicy


def served(policy, **options):
    return LeRobotServedPolicy(policy, name="diffusion-like", device="cpu", torch=torch, **options)


def decode(row):
    """(oldest history step, newest history step, episode, horizon index, forward pass) of one row."""
    return tuple(int(round(float(row[index]) * 1000)) for index in (0, 1, 2, 14, 15))


def test_sixteen_steps_cost_two_forward_passes_and_replay_the_chunks_in_order(serve):
    policy = DiffusionLikePolicy()
    server = serve(served(policy))

    async def session():
        async with connect(server.url) as client:
            return client.metadata, [await client.ask(observation(0, 3, step)) for step in range(16)]

    metadata, replies = run(session())
    assert metadata["action_queue"] is True and metadata["action_horizon"] == 1
    assert metadata["n_action_steps"] == 8 and metadata["n_obs_steps"] == 2
    assert policy.batch_sizes == [1, 1]
    # The history at each pass: two copies of step 0, then the two latest observations (7, 8).
    assert policy.histories == [[(3, [0, 0])], [(3, [7, 8])]]
    assert all(reply["actions"].shape == (1, 19) and reply["actions"].dtype == np.float32 for reply in replies)
    rows = [decode(reply["actions"][0]) for reply in replies]
    # Steps 0-7 execute horizon rows 1..8 of the pass at step 0, steps 8-15 those of the pass at step 8.
    assert rows == ([(0, 0, 3, index, 1) for index in range(1, 9)] +
                    [(7, 8, 3, index, 2) for index in range(1, 9)])


def test_a_batched_request_runs_one_pass_over_only_the_envs_whose_queue_ran_out(serve):
    policy = DiffusionLikePolicy()
    server = serve(served(policy))
    # Envs 0 and 1 start together (episodes 10, 11); env 2 (episode 12) joins three steps later.
    ticks = []
    for tick in range(12):
        envs = [(0, 10, tick), (1, 11, tick)]
        if tick >= 3:
            envs.append((2, 12, tick - 3))
        ticks.append(envs)

    async def session():
        async with connect(server.url) as client:
            return [await client.ask(batched([observation(*ids) for ids in tick])) for tick in ticks]

    replies = run(session())
    # Passes: tick 0 (envs 0, 1), tick 3 (env 2 alone), tick 8 (envs 0, 1), tick 11 (env 2 at its step 8).
    assert policy.batch_sizes == [2, 1, 2, 1]
    assert policy.histories == [[(10, [0, 0]), (11, [0, 0])], [(12, [0, 0])],
                                [(10, [7, 8]), (11, [7, 8])], [(12, [7, 8])]]
    for tick, (envs, reply) in enumerate(zip(ticks, replies)):
        assert reply["actions"].shape == (len(envs), 1, 19), f"tick {tick}"
    assert decode(replies[3]["actions"][0, 0]) == (0, 0, 10, 4, 1)  # env 0 from its queue
    assert decode(replies[3]["actions"][2, 0]) == (0, 0, 12, 1, 2)  # env 2's fresh chunk
    assert decode(replies[8]["actions"][1, 0]) == (7, 8, 11, 1, 3)
    assert decode(replies[8]["actions"][2, 0]) == (0, 0, 12, 6, 2)
    assert decode(replies[11]["actions"][2, 0]) == (7, 8, 12, 1, 4)
    assert decode(replies[11]["actions"][0, 0]) == (7, 8, 10, 4, 3)


def test_batched_and_per_env_requests_get_the_same_actions(serve):
    schedule = [[(0, 5, step), (1, 6, step)] for step in range(10)]
    per_env_policy, batched_policy = DiffusionLikePolicy(), DiffusionLikePolicy()
    per_env_server, batched_server = serve(served(per_env_policy)), serve(served(batched_policy))

    async def session():
        per_env, together = [], []
        async with connect(per_env_server.url) as client:
            for tick in schedule:
                per_env.append(np.stack([(await client.ask(observation(*ids)))["actions"] for ids in tick]))
        async with connect(batched_server.url) as client:
            for tick in schedule:
                together.append((await client.ask(batched([observation(*ids) for ids in tick])))["actions"])
        return per_env, together

    per_env, together = run(session())
    assert per_env_policy.batch_sizes == [1, 1, 1, 1] and batched_policy.batch_sizes == [2, 2]
    for tick, (alone, batch) in enumerate(zip(per_env, together)):
        # Entry 15 counts forward passes, which differ by design; every other entry must agree.
        np.testing.assert_allclose(np.delete(batch, 15, axis=-1), np.delete(alone, 15, axis=-1),
                                   rtol=1e-6, atol=1e-7, err_msg=f"tick {tick}")


def test_is_first_resets_the_queue_and_the_history(serve):
    policy = DiffusionLikePolicy()
    server = serve(served(policy))

    async def session():
        async with connect(server.url) as client:
            first = [await client.ask(observation(0, 1, step)) for step in range(3)]
            # Env 0's next episode starts with five rows of episode 1's chunk still queued.
            second = [await client.ask(observation(0, 2, step)) for step in range(2)]
            return first, second

    first, second = run(session())
    assert policy.histories == [[(1, [0, 0])], [(2, [0, 0])]]
    assert [decode(reply["actions"][0]) for reply in first] == [(0, 0, 1, index, 1) for index in (1, 2, 3)]
    assert [decode(reply["actions"][0]) for reply in second] == [(0, 0, 2, index, 2) for index in (1, 2)]


def test_a_skipped_step_is_an_error_and_leaves_the_queue_as_it_was(serve):
    policy = DiffusionLikePolicy()
    server = serve(served(policy))
    traceback, code = run(expect_error(server.url, [observation(0, 4, 0), observation(0, 4, 1), observation(0, 4, 3)]))
    assert "env 0 episode 4 step 3: skips from step 1" in traceback and "--replan-steps 1" in traceback
    assert code == 1011
    # The error closed that connection and its state went with it; on one connection (the server's
    # own entry point, connection 9) the rejected request changes nothing: step 2 is row 3 of the
    # chunk of that connection's pass (the server's second forward pass).
    for step in (0, 1):
        server.server.answer(observation(0, 4, step), connection=9)
    with pytest.raises(ValueError, match="skips from step 1"):
        server.server.answer(observation(0, 4, 3), connection=9)
    reply = server.server.answer(observation(0, 4, 2), connection=9)
    assert decode(reply["actions"][0]) == (0, 0, 4, 3, 2) and policy.batch_sizes == [1, 1]


def test_queue_off_replans_at_every_step_with_the_whole_chunk(serve):
    policy = DiffusionLikePolicy()
    server = serve(served(policy, action_queue="off"))

    async def session():
        async with connect(server.url) as client:
            return client.metadata, [await client.ask(observation(0, 0, step)) for step in range(3)]

    metadata, replies = run(session())
    assert metadata["action_queue"] is False and metadata["action_horizon"] == 8
    assert policy.batch_sizes == [1, 1, 1]
    assert replies[2]["actions"].shape == (8, 19)
    assert [decode(row)[3] for row in replies[2]["actions"]] == list(range(1, 9))


def test_queue_on_without_a_history_and_a_server_n_action_steps(serve):
    policy = DiffusionLikePolicy(n_obs_steps=1, horizon=16, n_action_steps=8)
    server = serve(served(policy, action_queue="on", n_action_steps=3))

    async def session():
        async with connect(server.url) as client:
            replies = [await client.ask(observation(0, 0, step)) for step in range(7)]
            return client.metadata, replies

    metadata, replies = run(session())
    assert metadata["action_queue"] is True and metadata["n_action_steps"] == 3
    assert policy.config.n_action_steps == 3  # written where LeRobot's models read it
    assert policy.batch_sizes == [1, 1, 1]  # passes at steps 0, 3, 6
    # n_obs_steps 1: the chunk starts at horizon row 0.
    assert [decode(reply["actions"][0])[3:] for reply in replies] == [(0, 1), (1, 1), (2, 1), (0, 2), (1, 2),
                                                                       (2, 2), (0, 3)]


def test_n_obs_steps_one_keeps_chunk_replies_by_default(serve):
    policy = DiffusionLikePolicy(n_obs_steps=1)
    server = serve(served(policy))

    async def session():
        async with connect(server.url) as client:
            return client.metadata, [await client.ask(observation(0, 0, step)) for step in (0, 8)]

    metadata, replies = run(session())
    assert metadata["action_queue"] is False and metadata["action_horizon"] == 8
    assert [reply["actions"].shape for reply in replies] == [(8, 19), (8, 19)]


@pytest.mark.parametrize("options, message", [
    ({"action_queue": "sometimes"}, "action queue mode 'sometimes' is not one of auto, on, off"),
    ({"n_action_steps": 0}, "n_action_steps 0 must be an integer of at least 1"),
])
def test_bad_queue_options_name_the_value(options, message):
    with pytest.raises(ValueError, match=message):
        served(DiffusionLikePolicy(), **options)
