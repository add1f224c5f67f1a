"""Helpers for the policy server's tests: a server in a background thread (so a test can look at
its policy), the CLI as a subprocess, and a client on Debian's websockets 10.4 legacy API that
decodes with the test directory's own msgpack-numpy copy, not the server's encoder."""

import asyncio
import contextlib
import http.client
import os
import subprocess
import sys
import threading

import numpy as np
import pytest
import websockets

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
SERVER_PACKAGE_DIR = os.path.join(REPO, "tools", "policy_server")
sys.path.insert(0, SERVER_PACKAGE_DIR)
sys.path.insert(0, os.path.join(REPO, "tests", "batch", "remote"))

from openpi_msgpack_numpy import packb, unpackb  # noqa: E402

from tavis_server.server import PolicyServer  # noqa: E402

IMAGE_SHAPE = (6, 8, 3)
STATE_DIM = 19


def observation(env_index, episode_index, step, seed=0, prompt="pick the cube"):
    """A per-env request whose state[0] is the step and state[1] the episode, and whose image pixels
    are a function of (env, episode, step, seed)."""
    rng = np.random.default_rng([env_index, episode_index, step, seed])
    state = rng.standard_normal(STATE_DIM).astype(np.float32)
    state[0], state[1] = step, episode_index
    return {"observation.images.OBS_HEAD": rng.integers(0, 256, IMAGE_SHAPE, dtype=np.uint8),
            "observation.images.OBS_WRIST_LEFT": rng.integers(0, 256, IMAGE_SHAPE, dtype=np.uint8),
            "observation.state": state, "prompt": prompt, "task": prompt,
            "env_index": env_index, "episode_index": episode_index, "step": step, "is_first": step == 0}


def batched(requests):
    """The batched form of per-env requests, as PROTOCOL.md stacks them."""
    result = {"batch_size": len(requests)}
    for key in requests[0]:
        values = [request[key] for request in requests]
        if key in ("prompt", "task"):
            result[key] = values
        elif key == "is_first":
            result[key] = np.array(values, dtype=bool)
        elif key in ("env_index", "episode_index", "step"):
            result[key] = np.array(values, dtype=np.int64)
        else:
            result[key] = np.stack(values)
    return result


class RunningServer:
    """A PolicyServer (options: its keyword arguments) on a free port in a thread with its own event loop."""

    def __init__(self, served, **options):
        self.server = PolicyServer(served, host="127.0.0.1", port=0, **options)
        self.port = None
        self._ready = threading.Event()
        self._loop = asyncio.new_event_loop()
        self._stop = None
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()
        assert self._ready.wait(30), "the server did not start listening"

    def _run(self):
        asyncio.set_event_loop(self._loop)
        self._stop = asyncio.Event()

        def ready(port):
            self.port = port
            self._ready.set()

        self._loop.run_until_complete(self.server.serve(ready=ready, stop=self._stop))

    @property
    def url(self):
        return f"ws://127.0.0.1:{self.port}"

    def close(self):
        self._loop.call_soon_threadsafe(self._stop.set)
        self._thread.join(30)
        self.server.close()


@pytest.fixture
def serve():
    """serve(served, **options) -> RunningServer; every server is stopped at the test's end."""
    servers = []

    def start(served, **options):
        servers.append(RunningServer(served, **options))
        return servers[-1]

    yield start
    for server in servers:
        server.close()


class Client:
    """One connection: metadata on connect, then request/reply maps."""

    def __init__(self, websocket, metadata):
        self.websocket = websocket
        self.metadata = metadata

    async def ask(self, request):
        await self.websocket.send(packb(request))
        reply = await self.websocket.recv()
        if isinstance(reply, str):
            raise AssertionError(f"server error:\n{reply}")
        return unpackb(reply)


@contextlib.asynccontextmanager
async def connect(url):
    async with websockets.connect(url, compression=None, max_size=None) as websocket:
        yield Client(websocket, unpackb(await websocket.recv()))


def run(coroutine):
    return asyncio.run(asyncio.wait_for(coroutine, 60))


def get(port, path):
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    connection.request("GET", path)
    response = connection.getresponse()
    return response.status, response.read()


class CliServer:
    """python3 -m tavis_server ARGS on a free port, started and waited for by its ready line."""

    def __init__(self, args, pythonpath=()):
        environment = dict(os.environ, PYTHONPATH=os.pathsep.join([SERVER_PACKAGE_DIR, *pythonpath]))
        self.process = subprocess.Popen([sys.executable, "-m", "tavis_server", "--port", "0", *args],
                                        env=environment, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = self.process.stdout.readline()
        if not line.startswith("tavis_server: serving "):
            self.process.kill()
            raise AssertionError(f"no ready line: {line!r} {self.process.stderr.read()}")
        self.ready_line = line.strip()
        self.url = line.split(" on ")[1].strip()
        self.port = int(self.url.rsplit(":", 1)[1])

    def stop(self):
        self.process.terminate()
        return self.process.wait(30)


@pytest.fixture
def cli_server():
    servers = []

    def start(*args, pythonpath=()):
        servers.append(CliServer(args, pythonpath))
        return servers[-1]

    yield start
    for server in servers:
        if server.process.poll() is None:
            server.process.kill()
            server.process.wait()


async def expect_error(url, requests):
    """Sends requests until one is answered with a traceback; returns (traceback, close code)."""
    async with websockets.connect(url, compression=None, max_size=None) as websocket:
        unpackb(await websocket.recv())
        for request in requests:
            await websocket.send(packb(request))
            reply = await websocket.recv()
            if isinstance(reply, str):
                with pytest.raises(websockets.ConnectionClosed) as closed:
                    await websocket.recv()
                return reply, closed.value.code
    raise AssertionError("every request was answered")
