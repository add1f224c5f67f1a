"""The websocket server of serving protocol v1 over openpi's msgpack-numpy transport: on
websockets' new asyncio API where it exists (>= 13, what a LeRobot environment has; written from
its documentation, not run here), else on the legacy API of Debian's python3-websockets 10.4.

Each connection first gets the metadata map, then every request (per-env or batched) is answered
with {"actions", "server_timing": {"infer_ms", "prev_total_ms"}}; an error sends its traceback as
a text frame and closes with 1011, as openpi's server does. Inference runs in a worker thread
under one lock, so a connection waiting on the policy does not stall the others' I/O.

Each connection is one client session with its own env slots: per-episode state is keyed by
(connection, env_index) and dropped when the connection closes. A peer is hostile until checked:
a frame longer than max_request_bytes is refused from its header (close 1009), a connection
that has not finished its opening handshake within handshake_timeout_s, or that sends no request
for idle_timeout_s, is closed, and only one request per connection is read ahead."""

import asyncio
import concurrent.futures
import http
import itertools
import threading
import time
import traceback

import websockets

try:  # websockets >= 13
    from websockets.asyncio.server import serve as _serve_asyncio
except ImportError:  # Debian's 10.4: only the legacy API
    _serve_asyncio = None
    from .legacy_handshake import timed_handshake_protocol

from . import msgpack_numpy
from .contract import CONTRACT_KEY, complete_contract
from .episodes import EpisodeTracker
from .observations import split_request

PROTOCOL_VERSION = 1
MIB = 1 << 20
# The largest request tavis sends by default-sized images: a batched request of 96 envs with three
# 320x240 RGB cameras is 96 * 3 * 240 * 320 * 3 bytes = 63.3 MiB (224x224: 41.3 MiB), plus
# states and ids (under 0.1 MiB). 128 MiB leaves twice that; `--max-request-mb` raises it.
DEFAULT_MAX_REQUEST_MB = 128
HANDSHAKE_TIMEOUT_S = 10.0
# Between two requests of a connection the client only steps its envs (milliseconds); 300 s also
# covers a slow first reset. A connection closed for idling reconnects on its next request.
DEFAULT_IDLE_TIMEOUT_S = 300.0
IDLE_CLOSE_CODE = 1000


class PolicyServer:
    """served: an object with name, metadata (dict), history_length, infer(observations, starts)
    -> (N, H, 19) float32, close(), and optionally reply_extras(observations, batched) -> dict and
    consecutive_steps (bool, default history_length > 1: whether every step must be asked) and
    forget(connection) (drops a closed connection's per-slot state). Its state is keyed by each
    observation's slot, (connection, env_index)."""

    def __init__(self, served, host="127.0.0.1", port=8000, workers=4, max_request_mb=DEFAULT_MAX_REQUEST_MB,
                 idle_timeout_s=DEFAULT_IDLE_TIMEOUT_S, handshake_timeout_s=HANDSHAKE_TIMEOUT_S):
        if not max_request_mb > 0 or not idle_timeout_s > 0 or not handshake_timeout_s > 0:
            raise ValueError(f"max_request_mb {max_request_mb}, idle_timeout_s {idle_timeout_s} and "
                             f"handshake_timeout_s {handshake_timeout_s} must be positive")
        self.served = served
        self.host = host
        self.port = port
        self.max_request_bytes = int(max_request_mb * MIB)
        self.idle_timeout_s = idle_timeout_s
        self.handshake_timeout_s = handshake_timeout_s
        self._connection_ids = itertools.count()
        self.open_connections = 0
        consecutive_steps = getattr(served, "consecutive_steps", served.history_length > 1)
        self.tracker = EpisodeTracker(consecutive_steps=consecutive_steps)
        self._lock = threading.Lock()
        self._executor = concurrent.futures.ThreadPoolExecutor(max_workers=workers,
                                                               thread_name_prefix="tavis-server-infer")
        self.metadata = {**served.metadata, "policy": served.name, "batched_requests": True, "stateful": True,
                         "action_dim": 19, "protocol": PROTOCOL_VERSION}
        self.metadata.setdefault("action_horizon", 1)
        if self.metadata.get(CONTRACT_KEY) is not None:  # what the policy was trained on (contract.py)
            self.metadata[CONTRACT_KEY] = complete_contract(self.metadata[CONTRACT_KEY], self.metadata["action_horizon"],
                                                            served.history_length, consecutive_steps)

    def answer(self, request, connection=0):
        """The reply map to one decoded request of `connection` (runs in a worker thread)."""
        observations, batched = split_request(request, connection)
        with self._lock:
            start = time.monotonic()
            starts = self.tracker.check(observations)
            actions = self.served.infer(observations, starts)
            infer_ms = (time.monotonic() - start) * 1000.0
            extras = (self.served.reply_extras(observations, batched)
                      if hasattr(self.served, "reply_extras") else {})
        reply = {"actions": actions if batched else actions[0], "server_timing": {"infer_ms": infer_ms}}
        reply.update(extras)
        return reply

    def forget(self, connection):
        """Drops a closed connection's per-slot state (runs in a worker thread, under the lock)."""
        with self._lock:
            self.tracker.forget(connection)
            if hasattr(self.served, "forget"):
                self.served.forget(connection)

    async def _handle(self, websocket, path=None):
        connection = next(self._connection_ids)
        self.open_connections += 1
        try:
            await self._serve_connection(websocket, connection)
        finally:
            self.open_connections -= 1
            await asyncio.get_running_loop().run_in_executor(self._executor, self.forget, connection)

    async def _serve_connection(self, websocket, connection):
        loop = asyncio.get_running_loop()
        await websocket.send(msgpack_numpy.packb(self.metadata))
        prev_total_ms = None
        while True:
            try:
                try:
                    message = await asyncio.wait_for(websocket.recv(), self.idle_timeout_s)
                except asyncio.TimeoutError:
                    await websocket.close(code=IDLE_CLOSE_CODE, reason=f"no request for {self.idle_timeout_s} s")
                    return
                received = time.monotonic()
                if isinstance(message, str):
                    raise ValueError("requests are binary msgpack frames, got a text frame")
                request = msgpack_numpy.unpackb(message)
                del message  # the frame's bytes: not kept while the policy runs
                reply = await loop.run_in_executor(self._executor, self.answer, request, connection)
                if prev_total_ms is not None:
                    reply["server_timing"]["prev_total_ms"] = prev_total_ms
                await websocket.send(msgpack_numpy.packb(reply))
                prev_total_ms = (time.monotonic() - received) * 1000.0
            except websockets.ConnectionClosed:
                return
            except Exception:
                try:
                    await websocket.send(traceback.format_exc())
                    await websocket.close(code=1011,
                                          reason="Internal server error. Traceback included in previous frame.")
                except websockets.ConnectionClosed:
                    pass
                return

    @staticmethod
    async def _health_legacy(path, request_headers):
        if path == "/healthz":
            return http.HTTPStatus.OK, [], b"OK\n"
        return None

    @staticmethod
    def _health_asyncio(connection, request):
        if request.path == "/healthz":
            return connection.respond(http.HTTPStatus.OK, "OK\n")
        return None

    def _listen(self):
        # max_queue 1: the protocol has one request in flight per connection, so reading ahead
        # more frames would only let a peer park max_request_bytes each in memory.
        limits = {"compression": None, "max_size": self.max_request_bytes, "max_queue": 1}
        if _serve_asyncio is not None:
            return _serve_asyncio(self._handle, self.host, self.port, open_timeout=self.handshake_timeout_s,
                                  process_request=self._health_asyncio, **limits)
        return websockets.serve(self._handle, self.host, self.port, process_request=self._health_legacy,
                                create_protocol=timed_handshake_protocol(self.handshake_timeout_s), **limits)

    async def serve(self, ready=None, stop=None):
        """Serves until `stop` (an asyncio.Event) is set, or forever; calls ready(port) once listening."""
        async with self._listen() as server:
            port = server.sockets[0].getsockname()[1]
            if ready:
                ready(port)
            await (stop.wait() if stop else asyncio.Future())

    def close(self):
        self._executor.shutdown(wait=True)
        self.served.close()
