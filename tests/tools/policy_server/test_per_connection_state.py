"""Per-episode state is per connection: two clients (two cells of a sweep, side by side) both
number their envs from 0, and each keeps its own episode check, observation history, action
queue and policy copy; a closed connection's state is dropped. The server used to key it by
env_index alone, so the second cell's step 0 after the first's step 10 failed ("comes after step
10; steps must grow") or, worse, mixed the two cells' histories."""

import asyncio
import time

import pytest
import torch

from conftest import connect, observation, run
from history_policy import HistoryPolicy, SelectOnlyPolicy, expected_image_values
from tavis_server import LeRobotServedPolicy, StatefulCheckPolicy


def lerobot(policy, **options):
    return LeRobotServedPolicy(policy, name="history", device="cpu", torch=torch, **options)


def wait_until(condition, what):
    deadline = time.monotonic() + 10
    while not condition():
        assert time.monotonic() < deadline, what
        time.sleep(0.02)


async def interleaved(url, steps, seeds=(0, 1)):
    """Two connections ask env 0, episode 0, steps 0..steps-1 in turn, the first two steps ahead of
    the second; each connection's observations are drawn with its own seed. Returns per
    connection the (request, reply) pairs."""
    async with connect(url) as first, connect(url) as second:
        clients = (first, second)
        asked = ([], [])
        for step in range(steps + 2):
            for index, lag in ((0, 0), (1, 2)):
                if 0 <= step - lag < steps:
                    request = observation(0, 0, step - lag, seed=seeds[index])
                    asked[index].append((request, await clients[index].ask(request)))
        return asked


@pytest.mark.parametrize("action_queue", ["off", "on"])
def test_two_connections_on_env_0_keep_their_own_history_and_queue(serve, action_queue):
    policy = HistoryPolicy(n_obs_steps=2, chunk=3)
    server = serve(lerobot(policy, action_queue=action_queue))
    asked = run(interleaved(server.url, steps=12))
    for pairs in asked:
        for step, (request, reply) in enumerate(pairs):
            actions = reply["actions"]
            assert actions.shape[-1] == 19
            row = actions[0]
            if action_queue == "off":
                # This connection's history: its own previous step and this one, its own image.
                assert [round(float(value) * 1000) for value in row[:3]] == [max(step - 1, 0), step, 0]
                mean, pixel = expected_image_values(request["observation.images.OBS_HEAD"])
                assert row[7] == pytest.approx(mean, rel=1e-5) and row[8] == pytest.approx(pixel)
    if action_queue == "on":
        # A forward pass every 3 steps per connection: 4 each, each over one env.
        assert policy.batch_sizes == [1] * 8
    wait_until(lambda: not server.server.served._histories and not server.server.tracker._slots,
               "the closed connections' state is still kept")
    assert not server.server.served._queues._chunks


def test_the_select_action_path_keeps_a_policy_copy_per_connection(serve):
    server = serve(lerobot(SelectOnlyPolicy()))
    asked = run(interleaved(server.url, steps=4))
    for pairs in asked:
        # calls since this copy's reset, and the step: each connection's copy counts only its own.
        assert [[round(float(value) * 1000) for value in reply["actions"][0, :2]] for _, reply in pairs] == [
            [step + 1, step] for step in range(4)]
    wait_until(lambda: not server.server.served._copies, "the closed connections' policy copies are still kept")


def test_the_stateful_stand_in_records_each_connection_apart(serve):
    standin = StatefulCheckPolicy(history=2)
    server = serve(standin)
    asked = run(interleaved(server.url, steps=3))
    received = [[reply["received"] for _, reply in pairs] for pairs in asked]
    connections = {entry["connection"] for entries in received for entry in entries}
    assert len(connections) == 2
    for entries in received:
        assert entries[-1]["steps"] == [0, 1, 2] and entries[-1]["is_first"] == [True, False, False]
    assert [(entry["env_index"], entry["episode_index"], entry["steps"]) for entry in standin.report()["episodes"]] == [
        (0, 0, [0, 1, 2]), (0, 0, [0, 1, 2])]


def test_an_episode_does_not_carry_over_to_another_connection(serve):
    server = serve(lerobot(HistoryPolicy(n_obs_steps=2), action_queue="off"))

    async def session():
        async with connect(server.url) as first:
            await first.ask(observation(0, 0, 0))
            async with connect(server.url) as second:
                with pytest.raises(AssertionError, match="env 0 episode 0 step 1: the episode's first observation"):
                    await second.ask(observation(0, 0, 1))
            return await first.ask(observation(0, 0, 1))

    reply = run(session())
    assert [round(float(value) * 1000) for value in reply["actions"][0, :3]] == [0, 1, 0]


def test_many_connections_leave_no_state_behind(serve):
    server = serve(lerobot(HistoryPolicy(n_obs_steps=2), action_queue="on"))

    async def one(index):
        async with connect(server.url) as client:
            for step in range(3):
                await client.ask(observation(index % 4, index, step))

    async def all_of_them():
        await asyncio.gather(*(one(index) for index in range(40)))

    run(all_of_them())
    wait_until(lambda: server.server.open_connections == 0 and not server.server.tracker._slots
               and not server.server.served._histories and not server.server.served._queues._chunks,
               "state of closed connections is kept")
