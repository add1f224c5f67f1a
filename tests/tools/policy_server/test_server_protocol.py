"""The server's side of serving protocol v1: metadata, /healthz, openpi's error convention,
request checks, and connections served concurrently."""

import asyncio
import threading

import pytest
import torch

from conftest import batched, connect, expect_error, get, observation, run
from history_policy import HistoryPolicy
from tavis_server import EchoPolicy, LeRobotServedPolicy


def history_server(serve, action_queue="auto", **options):
    return serve(LeRobotServedPolicy(HistoryPolicy(**options), name="history", device="cpu", torch=torch,
                                     action_queue=action_queue))


def test_metadata_and_healthz(serve):
    server = history_server(serve, n_obs_steps=2, chunk=5)
    assert get(server.port, "/healthz") == (200, b"OK\n")

    async def session():
        async with connect(server.url) as client:
            return client.metadata

    metadata = run(session())
    assert metadata["batched_requests"] is True and metadata["stateful"] is True
    assert metadata["policy"] == "history"
    # n_obs_steps 2 queues actions by default: one row per reply, 5 steps per chunk.
    assert metadata["action_horizon"] == 1 and metadata["action_dim"] == 19
    assert metadata["action_queue"] is True and metadata["n_action_steps"] == 5
    assert metadata["n_obs_steps"] == 2 and metadata["protocol"] == 1


@pytest.mark.parametrize("requests, message", [
    ([observation(0, 1, 0), observation(0, 1, 2)], "env 0 episode 1 step 2: skips from step 0"),
    ([observation(0, 1, 0), observation(0, 1, 1), observation(0, 1, 1)], "comes after step 1"),
    ([observation(0, 1, 0), observation(0, 2, 1)], "the episode's first observation (step 0, is_first) never came"),
    ([{**observation(0, 1, 0), "is_first": False}], "is_first=False, but is_first is true exactly at step 0"),
    ([{key: value for key, value in observation(0, 1, 0).items() if key != "step"}], "missing step"),
    ([{**observation(0, 1, 0), "episode_index": "one"}], "episode_index must be an integer"),
    ([batched([observation(0, 1, 0), observation(0, 2, 0)])], "env_index [0, 0] names an env twice"),
    ([{**batched([observation(0, 1, 0), observation(1, 2, 0)]), "batch_size": 3}],
     "must be an array of leading length batch_size=3"),
    ([{**batched([observation(0, 1, 0), observation(1, 2, 0)]), "task": ["only one"]}],
     "task must be a list of batch_size=2 str"),
])
def test_bad_requests_get_a_traceback_and_close_1011(serve, requests, message):
    server = history_server(serve, n_obs_steps=2)
    traceback, code = run(expect_error(server.url, requests))
    assert message in traceback and "Traceback" in traceback
    assert code == 1011


def test_a_rejected_request_leaves_the_episode_state_as_it_was(serve):
    # An error closes its connection, whose state goes with it; within one connection (the server's
    # own entry point) a rejected request changes nothing.
    server = history_server(serve, n_obs_steps=2, action_queue="off").server  # every request a forward pass
    server.answer(observation(0, 1, 0))
    server.answer(observation(0, 1, 1))
    with pytest.raises(ValueError, match="env 0 episode 1 step 3: skips from step 1"):
        server.answer(batched([observation(1, 5, 0), observation(0, 1, 3)]))
    reply = server.answer(observation(0, 1, 2))  # env 0 still expects step 2; env 1 never started
    assert [round(value * 1000) for value in reply["actions"][0, :3]] == [1, 2, 1]
    with pytest.raises(ValueError, match="env 1 episode 5 step 1: the episode's first observation"):
        server.answer(observation(1, 5, 1))


def test_steps_may_skip_without_a_history(serve):
    server = history_server(serve, n_obs_steps=1)

    async def session():
        async with connect(server.url) as client:
            return [await client.ask(observation(0, 1, step)) for step in (0, 8, 16)]

    assert [round(reply["actions"][0, 1] * 1000) for reply in run(session())] == [0, 8, 16]


class GatedEcho(EchoPolicy):
    """The echo stand-in, whose inference waits until the test opens the gate."""

    def __init__(self):
        super().__init__(chunk=1)
        self.gate = threading.Event()
        self.entered = threading.Event()

    def infer(self, observations, starts):
        self.entered.set()
        assert self.gate.wait(30)
        return super().infer(observations, starts)


def test_two_connections_are_served_concurrently(serve):
    policy = GatedEcho()
    server = serve(policy)

    async def session():
        async with connect(server.url) as first, connect(server.url) as second:
            pending = asyncio.ensure_future(first.ask(observation(0, 4, 0)))
            await asyncio.get_running_loop().run_in_executor(None, policy.entered.wait, 30)
            # The first connection's inference is under way: the server still answers I/O.
            async with connect(server.url) as third:
                assert third.metadata["policy"] == "echo"
            status = await asyncio.get_running_loop().run_in_executor(None, get, server.port, "/healthz")
            assert status == (200, b"OK\n") and not pending.done()
            queued = asyncio.ensure_future(second.ask(observation(1, 7, 0)))
            policy.gate.set()
            return await pending, await queued

    first, second = run(session())
    assert [round(value * 1000) for value in first["actions"][0, :3]] == [0, 4, 0]
    assert [round(value * 1000) for value in second["actions"][0, :3]] == [1, 7, 0]
