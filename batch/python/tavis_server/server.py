"""The websocket server of serving protocol v1 over openpi's msgpack-numpy transport: on
websockets' new asyncio API where it exists (>= 13, what a LeRobot environment has; written from
its documentation, not run here), else on the legacy API of Debian's python3-websockets 10.4.

Each connection first gets the metadata map, then every request (per-env or batched) is answered
with {"actions", "server_timing": {"infer_ms", "prev_total_ms"}}; an error sends its traceback as
a text frame and closes with 1011, as openpi's server does. Inference runs in a worker thread
under one lock, so a connection waiting on the policy does not stall the others' I/O."""

import asyncio
import concurrent.futures
import http
import threading
import time
import traceback

import websockets

try:  # websockets >= 13
    from websockets.asyncio.server import serve as _serve_asyncio
except ImportError:  # Debian's 10.4: only the legacy API
    _serve_asyncio = None

from . import msgpack_numpy
from .episodes import EpisodeTracker
from .observations import split_request

PROTOCOL_VERSION = 1


class PolicyServer:
    """served: an object with name, metadata (dict), history_length, infer(observations, starts)
    -> (N, H, 19) float32, close(), and optionally reply_extras(observations, batched) -> dict and
    consecutive_steps (bool, default history_length > 1: whether every step must be asked)."""

    def __init__(self, served, host="127.0.0.1", port=8000, workers=4):
        self.served = served
        self.host = host
        self.port = port
        self.tracker = EpisodeTracker(consecutive_steps=getattr(served, "consecutive_steps", served.history_length > 1))
        self._lock = threading.Lock()
        self._executor = concurrent.futures.ThreadPoolExecutor(max_workers=workers,
                                                               thread_name_prefix="tavis-server-infer")
        self.metadata = {**served.metadata, "policy": served.name, "batched_requests": True, "stateful": True,
                         "action_dim": 19, "protocol": PROTOCOL_VERSION}
        self.metadata.setdefault("action_horizon", 1)

    def answer(self, request):
        """The reply map to one decoded request (runs in a worker thread)."""
        observations, batched = split_request(request)
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

    async def _handle(self, websocket, path=None):
        loop = asyncio.get_running_loop()
        await websocket.send(msgpack_numpy.packb(self.metadata))
        prev_total_ms = None
        while True:
            try:
                message = await websocket.recv()
                received = time.monotonic()
                if isinstance(message, str):
                    raise ValueError("requests are binary msgpack frames, got a text frame")
                request = msgpack_numpy.unpackb(message)
                reply = await loop.run_in_executor(self._executor, self.answer, request)
                if prev_total_ms is not None:
                    reply["server_timing"]["prev_total_ms"] = prev_total_ms
                await websocket.send(msgpack_numpy.packb(reply))
                prev_total_ms = (time.monotonic() - received) * 1000.0
            except websockets.ConnectionClosed:
                return
            except Exception:
                await websocket.send(traceback.format_exc())
                await websocket.close(code=1011, reason="Internal server error. Traceback included in previous frame.")
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
        if _serve_asyncio is not None:
            return _serve_asyncio(self._handle, self.host, self.port, compression=None, max_size=None,
                                  process_request=self._health_asyncio)
        return websockets.serve(self._handle, self.host, self.port, compression=None, max_size=None,
                                process_request=self._health_legacy)

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
