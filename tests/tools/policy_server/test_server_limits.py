"""What a hostile or broken peer cannot do to the server: send a frame longer than
--max-request-mb (refused from its header, close 1009; it used to be read whole: 600 MB took the
RSS from 39 to 654 MB), hold a socket that never finishes its opening handshake, or hold a
connection that never sends a request; and the command line refuses bad ports, limits and
--policy-arg values with exit 2 naming them, no traceback."""

import os
import socket
import subprocess
import sys
import time

import pytest
import websockets

from conftest import SERVER_PACKAGE_DIR, connect, observation, run
from tavis_server import EchoPolicy
from tavis_server.server import DEFAULT_MAX_REQUEST_MB

HERE = os.path.dirname(os.path.abspath(__file__))


async def oversize_then_valid(url, size):
    """Sends `size` bytes as one binary frame; returns (its close code, a valid request's reply on a
    new connection)."""
    async with websockets.connect(url, compression=None, max_size=None) as websocket:
        await websocket.recv()
        await websocket.send(b"\x80" * size)
        with pytest.raises(websockets.ConnectionClosed) as closed:
            await websocket.recv()
    async with connect(url) as client:
        return closed.value.code, await client.ask(observation(0, 0, 0))


def test_a_frame_over_the_limit_is_refused_with_1009(serve):
    server = serve(EchoPolicy(), max_request_mb=1)
    code, reply = run(oversize_then_valid(server.url, (1 << 20) + 1))
    assert code == 1009
    assert reply["actions"].shape == (1, 19)


def test_the_default_limit_takes_the_largest_default_request():
    # A batched request of 96 envs with three 320x240 RGB cameras (the reference's size).
    assert 96 * 3 * 240 * 320 * 3 * 2 <= DEFAULT_MAX_REQUEST_MB << 20


def test_the_command_line_sets_the_limit(cli_server):
    server = cli_server("--policy", "echo", "--max-request-mb", "0.5")
    code, reply = run(oversize_then_valid(server.url, (1 << 19) + 1))
    assert code == 1009 and reply["actions"].shape == (1, 19)


def test_a_socket_that_never_handshakes_is_closed(serve):
    server = serve(EchoPolicy(), handshake_timeout_s=0.5)
    with socket.create_connection(("127.0.0.1", server.port), timeout=10) as silent:
        start = time.monotonic()
        answer = b""
        while chunk := silent.recv(4096):
            answer += chunk
        waited = time.monotonic() - start
    assert waited < 5 and answer.startswith(b"HTTP/1.1 400")
    assert b"no opening handshake within 0.5 s" in answer
    # Meanwhile and afterwards the server serves as before.
    assert run(ask_one(server.url))["actions"].shape == (1, 19)


async def ask_one(url):
    async with connect(url) as client:
        return await client.ask(observation(0, 0, 0))


def test_a_connection_that_sends_nothing_is_closed_and_forgotten(serve):
    server = serve(EchoPolicy(), idle_timeout_s=0.5)

    async def idle():
        async with connect(server.url) as client:
            await client.ask(observation(3, 0, 0))
            start = time.monotonic()
            with pytest.raises(websockets.ConnectionClosed) as closed:
                await client.websocket.recv()
            return time.monotonic() - start, closed.value.code, closed.value.reason

    waited, code, reason = run(idle())
    assert 0.4 < waited < 5 and code == 1000 and reason == "no request for 0.5 s"
    deadline = time.monotonic() + 10
    while server.server.tracker._slots and time.monotonic() < deadline:
        time.sleep(0.02)
    assert not server.server.tracker._slots and server.server.open_connections == 0


def run_cli(*args):
    environment = dict(os.environ, PYTHONPATH=os.pathsep.join([SERVER_PACKAGE_DIR, HERE]))
    return subprocess.run([sys.executable, "-m", "tavis_server", *args], env=environment, capture_output=True,
                          text=True, timeout=120)


@pytest.mark.parametrize("args, message", [
    (["--port", "-1"], "argument --port: '-1' is not a port number from 0 to 65535"),
    (["--port", "65536"], "argument --port: '65536' is not a port number from 0 to 65535"),
    (["--port", "http"], "argument --port: 'http' is not a port number from 0 to 65535"),
    (["--port", ""], "argument --port: '' is not a port number from 0 to 65535"),
    (["--max-request-mb", "0"], "argument --max-request-mb: '0' is not a positive number"),
    (["--max-request-mb", "-5"], "argument --max-request-mb: '-5' is not a positive number"),
    (["--max-request-mb", "nan"], "argument --max-request-mb: 'nan' is not a positive number"),
    (["--idle-timeout", "inf"], "argument --idle-timeout: 'inf' is not a positive number"),
    (["--seed", "-1"], "argument --seed: '-1' is not a seed from 0 to 2**32 - 1"),
    (["--seed", str(2 ** 70)], f"argument --seed: '{2 ** 70}' is not a seed"),
])
def test_bad_numbers_are_argparse_errors_naming_the_value(args, message):
    result = run_cli("--policy", "echo", *args)
    assert result.returncode == 2 and message in result.stderr
    assert "Traceback" not in result.stderr and result.stdout == ""


@pytest.mark.parametrize("args, message", [
    (["--policy", "echo", "--policy-arg", "chunk=2"],
     "--policy-arg 'chunk=2': the echo stand-in takes no --policy-arg"),
    (["--policy", "sleep", "--device", "cpu", "--policy-arg", "x"], "--policy-arg 'x': the sleep stand-in takes no"),
    (["--policy", "history_policy:HistoryPolicy", "--policy-arg", "=2"], "--policy-arg '=2' is not KEY=VALUE"),
    (["--policy", "history_policy:HistoryPolicy", "--policy-arg", " =2"], "--policy-arg ' =2' is not KEY=VALUE"),
    (["--policy", "history_policy:HistoryPolicy", "--policy-arg", "chunk=2", "--policy-arg", "chunk=3"],
     "--policy-arg 'chunk=3': chunk is given twice"),
])
def test_a_policy_arg_that_cannot_apply_is_an_error(args, message):
    result = run_cli("--port", "0", *args)
    assert result.returncode == 2 and message in result.stderr
    assert "Traceback" not in result.stderr and result.stdout == ""
