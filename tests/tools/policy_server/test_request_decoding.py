"""The server's msgpack-numpy decoder takes nothing from a peer unchecked: only numeric and bool
dtypes, a shape of non-negative ints, data of exactly the shape's bytes. An object array used to
turn the peer's bytes into object pointers (SIGSEGV once torch read the batch); the echo stand-in
accepted it silently."""

import os

import msgpack
import numpy as np
import pytest
import websockets

from conftest import connect, observation, run
from openpi_msgpack_numpy import packb as client_packb
from tavis_server.msgpack_numpy import packb, unpackb

HERE = os.path.dirname(os.path.abspath(__file__))


def ndarray(dtype, shape, data):
    return {b"__ndarray__": True, b"dtype": dtype, b"shape": shape, b"data": data}


@pytest.mark.parametrize("dtype", ["|b1", "|i1", "|u1", "<i2", "<u2", "<i4", "<u4", "<i8", "<u8", "<f2", "<f4",
                                   "<f8"])
def test_numeric_and_bool_arrays_come_through(dtype):
    array = np.arange(6).reshape(2, 3).astype(np.dtype(dtype)) if dtype != "|b1" else np.eye(2, 3, dtype=bool)
    decoded = unpackb(packb({"a": array, "s": array[0, 1]}))
    assert decoded["a"].dtype == array.dtype and decoded["a"].shape == (2, 3)
    assert (decoded["a"] == array).all() and decoded["s"] == array[0, 1]
    if dtype != "<f8":  # np.float64 is a Python float, which msgpack packs as itself
        assert decoded["s"].dtype == array.dtype


@pytest.mark.parametrize("fields, message", [
    (ndarray("|O", [1], b"\x41" * 8), "ndarray dtype '|O' is not accepted"),
    (ndarray("O", [1], b"\x41" * 8), "ndarray dtype 'O' is not accepted"),
    (ndarray("|V8", [1], b"\0" * 8), "ndarray dtype '|V8' is not accepted"),
    (ndarray("i4,O", [1], b"\0" * 12), "ndarray dtype 'i4,O' is not accepted"),
    (ndarray("<c8", [1], b"\0" * 8), "ndarray dtype '<c8' is not accepted"),
    (ndarray("<U2", [1], b"\0" * 8), "ndarray dtype '<U2' is not accepted"),
    (ndarray("|S4", [1], b"\0" * 4), "ndarray dtype '|S4' is not accepted"),
    (ndarray("<M8[s]", [1], b"\0" * 8), "ndarray dtype '<M8[s]' is not accepted"),
    (ndarray(">f4", [1], b"\0" * 4), "ndarray dtype '>f4' is not accepted"),
    (ndarray(b"<f4", [1], b"\0" * 4), "ndarray dtype b'<f4' is not accepted"),
    (ndarray("<f4", [2, 3], b"\0" * 20), "dtype <f4 and shape [2, 3] needs 24 bytes of data, got 20"),
    (ndarray("<f4", [2 ** 40, 2 ** 40], b"\0" * 4), "needs 4835703278458516698824704 bytes of data, got 4"),
    (ndarray("<f4", [-1], b""), "ndarray shape [-1] is not a list of at most 32 non-negative ints"),
    (ndarray("<f4", [1.0], b"\0" * 4), "ndarray shape [1.0] is not a list"),
    (ndarray("<f4", [True], b"\0" * 4), "ndarray shape [True] is not a list"),
    (ndarray("<f4", 4, b"\0" * 16), "ndarray shape 4 is not a list"),
    (ndarray("|u1", [1] * 33, b"\0"), "is not a list of at most 32 non-negative ints"),
    (ndarray("<f4", [1], "abcd"), "ndarray data is a str, not a msgpack bin"),
    (ndarray("|b1", [2], b"\x01\x07"), "bool ndarray holds a byte other than 0 or 1"),
    ({b"__ndarray__": True}, "ndarray dtype None is not accepted"),
    ({b"__npgeneric__": True, b"dtype": "|O", b"data": 1}, "npgeneric dtype '|O' is not accepted"),
    ({b"__npgeneric__": True, b"dtype": "|u1", b"data": 300}, "npgeneric of dtype |u1 cannot hold 300"),
    ({b"__npgeneric__": True, b"dtype": "<f4", b"data": "1.0"}, "npgeneric of dtype <f4 cannot hold '1.0'"),
    ({b"__npgeneric__": True, b"dtype": "|b1", b"data": 1}, "npgeneric of dtype |b1 cannot hold 1"),
])
def test_anything_else_is_a_value_error_naming_it(fields, message):
    with pytest.raises(ValueError) as error:
        unpackb(msgpack.packb({"observation.state": fields}))
    assert message in str(error.value)


def object_array_request():
    """A valid per-env request whose state is an object array of 16 peer-chosen pointer bytes."""
    body = msgpack.unpackb(client_packb({**observation(0, 0, 0), "observation.state": None}))
    body["observation.state"] = ndarray("|O", [2], b"\x41" * 16)
    return msgpack.packb(body)


async def send_raw_then_valid(url, frame):
    """Sends `frame` on one connection (its reply: a traceback and close 1011), then a valid
    request on a new one; returns (traceback, close code, the valid reply)."""
    async with websockets.connect(url, compression=None, max_size=None) as websocket:
        await websocket.recv()
        await websocket.send(frame)
        traceback = await websocket.recv()
        with pytest.raises(websockets.ConnectionClosed) as closed:
            await websocket.recv()
    async with connect(url) as client:
        return traceback, closed.value.code, await client.ask(observation(1, 0, 0))


@pytest.mark.parametrize("policy", ["echo", "history_policy:HistoryPolicy"])
def test_an_object_array_gets_an_error_frame_and_the_server_serves_on(cli_server, policy):
    server = cli_server("--policy", policy, pythonpath=[HERE])
    traceback, code, reply = run(send_raw_then_valid(server.url, object_array_request()))
    assert isinstance(traceback, str) and "ndarray dtype '|O' is not accepted" in traceback
    assert code == 1011
    assert reply["actions"].shape[-1] == 19
    assert server.process.poll() is None, "the server died"
    assert server.stop() == 0
