"""Issue 46, acceptance 2: the reference server survives random and mutated msgpack requests.

A seeded generator (the same requests every run) sends 10,000 frames to the server serving a
LeRobot-interface policy with an observation history and an action queue (history_policy.py's
HistoryPolicy through LeRobotServedPolicy and torch, as a checkpoint is served), and 1,000 to the
echo stand-in: valid per-env and batched requests, the same with flipped or truncated bytes, wrong
dtypes (|O, V, c, U, S, M8, nonsense), shapes that do not match their data, huge shapes and ranks,
deep nesting, non-map top levels, random msgpack and random bytes, text frames and frames over
--max-request-mb. Every frame must get a valid reply (a map with float32 (..., 19) actions), or an
error frame followed by close 1011, or (only for an oversize frame) close 1009; after a close the
client reconnects. A valid request must get a valid reply. At the end the server still answers,
and its peak RSS (VmHWM) is at most RSS_GROWTH_BOUND_MIB above its RSS after the first request
(docs/serving.md has the measured values). Loopback only."""

import asyncio
import os
import time

import msgpack
import numpy as np
import pytest
import websockets

from conftest import batched, observation
from openpi_msgpack_numpy import packb, unpackb

HERE = os.path.dirname(os.path.abspath(__file__))
MAX_REQUEST_MB = 1
RSS_GROWTH_BOUND_MIB = 96
ENVS = 4
BAD_DTYPES = ["|O", "O", "|V8", "<c8", "<c16", "<U2", "|S4", "<M8[s]", "<m8", "i4,O", ">f4", "float128", "xyz", ""]


def memory_mib(pid):
    """(VmRSS, VmHWM) of a process in MiB."""
    fields = {}
    with open(f"/proc/{pid}/status") as status:
        for line in status:
            key, _, value = line.partition(":")
            fields[key] = value.strip()
    return int(fields["VmRSS"].split()[0]) / 1024, int(fields["VmHWM"].split()[0]) / 1024


class Episodes:
    """The next valid request of each env slot on the current connection."""

    def __init__(self, rng):
        self.rng = rng
        self.steps = {}  # env -> (episode, last step)
        self.episode = 0

    def reset(self):
        self.steps = {}

    def next(self, env):
        current = self.steps.get(env)
        if current is None or self.rng.random() < 0.05:
            self.episode += 1
            current = (self.episode, -1)
        return env, current[0], current[1] + 1

    def request(self):
        """(a valid request, its ids) per-env or batched over distinct envs."""
        if self.rng.random() < 0.6:
            ids = [self.next(int(self.rng.integers(ENVS)))]
            return observation(*ids[0], seed=int(self.rng.integers(1 << 30))), ids
        envs = self.rng.choice(ENVS, size=int(self.rng.integers(1, ENVS + 1)), replace=False)
        ids = [self.next(int(env)) for env in envs]
        return batched([observation(*entry, seed=int(self.rng.integers(1 << 30))) for entry in ids]), ids

    def accepted(self, ids):
        for env, episode, step in ids:
            self.steps[env] = (episode, step)


def raw_map(request):
    """A request as plain msgpack structures (arrays as their bin-keyed maps), to mutate."""
    return msgpack.unpackb(packb(request))


def array_keys(body):
    return [key for key, value in body.items() if isinstance(value, dict) and b"__ndarray__" in value]


def mutate(rng, encoded, body):
    """One hostile frame derived from a valid request: bytes or a str (a text frame)."""
    kind = int(rng.integers(12))
    keys = array_keys(body)
    key = keys[int(rng.integers(len(keys)))]
    if kind == 0:  # flipped bytes
        data = bytearray(encoded)
        for position in rng.integers(0, len(data), size=int(rng.integers(1, 9))):
            data[position] ^= int(rng.integers(1, 256))
        return bytes(data)
    if kind == 1:  # truncated
        return encoded[:int(rng.integers(0, len(encoded)))]
    if kind == 2:  # a wrong dtype
        body[key][b"dtype"] = BAD_DTYPES[int(rng.integers(len(BAD_DTYPES)))]
    elif kind == 3:  # shape and data disagree
        shape = list(body[key][b"shape"])
        shape[int(rng.integers(len(shape)))] += int(rng.integers(1, 4))
        body[key][b"shape"] = shape
    elif kind == 4:  # data too short or too long
        data = body[key][b"data"]
        body[key][b"data"] = data[:-1] if rng.random() < 0.5 else data + b"\0"
    elif kind == 5:  # huge shapes and ranks
        body[key][b"shape"] = [[2 ** 40, 2 ** 40], [2 ** 62], [1] * 33, [-1], [0] * 64, [2 ** 64 - 1]][int(rng.integers(6))]
    elif kind == 6:  # shape, dtype or data of the wrong msgpack type
        field = [b"shape", b"dtype", b"data"][int(rng.integers(3))]
        body[key][field] = [None, 3.5, "x", {b"a": 1}, [[1]], True][int(rng.integers(6))]
    elif kind == 7:  # deep nesting
        depth = int(rng.integers(100, 5000))
        return (b"\x91" if rng.random() < 0.5 else b"\x81\xa1k") * depth + b"\xc0"
    elif kind == 8:  # a valid msgpack value that is not a map
        return msgpack.packb([5, [1, 2], "text", None, b"bin", 2.5, [body]][int(rng.integers(7))])
    elif kind == 9:  # protocol fields of the wrong type or value
        field = ["env_index", "step", "episode_index", "is_first", "batch_size", "task", "prompt"][int(rng.integers(7))]
        body[field] = [-1, 2 ** 63 - 1, "zero", None, [1, 2], 1.5, {"a": 1}, True][int(rng.integers(8))]
    elif kind == 10:  # random bytes
        return rng.bytes(int(rng.integers(0, 512)))
    else:  # a text frame
        return "".join(chr(int(c)) for c in rng.integers(32, 0x2FF, size=int(rng.integers(0, 64))))
    return msgpack.packb(body)


def oversize(rng):
    return rng.bytes((MAX_REQUEST_MB << 20) + int(rng.integers(1, 1024)))


def check_reply(reply, where):
    assert isinstance(reply, dict), f"{where}: reply {type(reply).__name__}"
    actions = reply["actions"]
    assert isinstance(actions, np.ndarray) and actions.dtype == np.float32 and actions.shape[-1] == 19, where
    assert isinstance(reply["server_timing"]["infer_ms"], float), where


async def fuzz_connection(url, count, rng):
    """Sends `count` frames, one connection at a time; returns a tally of the outcomes."""
    episodes = Episodes(rng)
    tally = {"valid": 0, "accepted mutant": 0, "error frame": 0, "oversize": 0}
    websocket = None
    for index in range(count):
        if websocket is None:
            websocket = await websockets.connect(url, compression=None, max_size=None)
            assert isinstance(unpackb(await websocket.recv()), dict)
            episodes.reset()
        request, ids = episodes.request()
        roll = rng.random()
        if roll < 0.2:
            frame, kind = packb(request), "valid"
        elif roll < 0.21:
            frame, kind = oversize(rng), "oversize"
        else:
            frame, kind = mutate(rng, packb(request), raw_map(request)), "mutant"
        where = f"frame {index} ({kind})"
        await websocket.send(frame)
        try:
            reply = await websocket.recv()
        except websockets.ConnectionClosed as closed:
            assert kind == "oversize" and closed.code == 1009, f"{where}: closed {closed.code} without an error frame"
            tally["oversize"] += 1
            websocket = None
            continue
        assert kind != "oversize", f"{where}: an oversize frame was answered"
        if isinstance(reply, str):
            assert kind == "mutant", f"{where}: a valid request got an error:\n{reply}"
            assert "Traceback" in reply, where
            with pytest.raises(websockets.ConnectionClosed) as closed:
                await websocket.recv()
            assert closed.value.code == 1011, f"{where}: error frame then close {closed.value.code}"
            tally["error frame"] += 1
            websocket = None
            continue
        check_reply(unpackb(reply), where)
        if kind == "valid":
            episodes.accepted(ids)
            tally["valid"] += 1
        else:  # a mutation the protocol accepts (a flipped pixel): its state is unknown, start afresh
            tally["accepted mutant"] += 1
            await websocket.close()
            websocket = None
    if websocket is not None:
        await websocket.close()
    return tally


async def fuzz(url, count, seed, clients=4):
    """`clients` clients side by side (as a sweep's cells are), each with its own seeded stream of
    count / clients frames; returns the tally of all outcomes."""
    tallies = await asyncio.gather(*(fuzz_connection(url, count // clients, np.random.default_rng([seed, client]))
                                     for client in range(clients)))
    return {key: sum(tally[key] for tally in tallies) for key in tallies[0]}


async def one_valid(url):
    async with websockets.connect(url, compression=None, max_size=None) as websocket:
        await websocket.recv()
        await websocket.send(packb(batched([observation(env, 0, 0) for env in range(ENVS)])))
        reply = unpackb(await websocket.recv())
    check_reply(reply, "the last request")
    return reply


@pytest.mark.parametrize("policy, count", [
    (["--policy", "history_policy:HistoryPolicy", "--policy-arg", "n_obs_steps=2", "--policy-arg", "chunk=4"], 10000),
    (["--policy", "echo"], 1000),
], ids=["lerobot-history", "echo"])
def test_the_server_survives_random_and_mutated_requests(cli_server, policy, count):
    server = cli_server(*policy, "--max-request-mb", str(MAX_REQUEST_MB), pythonpath=[HERE])
    asyncio.run(one_valid(server.url))
    start_rss, _ = memory_mib(server.process.pid)
    began = time.monotonic()
    tally = asyncio.run(fuzz(server.url, count, seed=46))
    seconds = time.monotonic() - began
    assert server.process.poll() is None, "the server died"
    asyncio.run(one_valid(server.url))
    rss, peak = memory_mib(server.process.pid)
    print(f"{policy[1]}: {count} frames in {seconds:.1f} s, {tally}; RSS {start_rss:.0f} MiB after the first "
          f"request, {rss:.0f} MiB at the end, peak {peak:.0f} MiB")
    assert sum(tally.values()) == count and min(tally.values()) > 0
    assert peak - start_rss <= RSS_GROWTH_BOUND_MIB, f"peak RSS {peak:.0f} MiB, {start_rss:.0f} MiB at the start"
    assert server.stop() == 0
