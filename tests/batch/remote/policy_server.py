"""A stand-in openpi policy server for the C++ client's tests, run with /usr/bin/python3 on
Debian's python3-websockets 10.4 (legacy API), python3-msgpack and python3-numpy. It follows
openpi's websocket_policy_server as policy-interfaces.md section A1 describes it: /healthz
answers 200 "OK\\n"; each connection first gets the metadata; then every observation is answered
with a reply map, or, when the policy raises, with the traceback as a text frame and close 1011.

The policy is a deterministic function the tests recompute in C++ (exact in float64):
  offset = (sum of all uint8 array bytes % 1024) / 8 + utf8_len(prompt) * 0.25
  actions[t, d] = (state[d % len(state)] * (t + 1) + offset + d) * action_scale,
                  t < horizon, d < action_dim
where state is "observation/state" (the libero layout), "observation.state" (tavis) or "state"
(aloha). Every reply also carries "received": each array of the request by its key path joined
with "|" -> [dtype, shape], and each str -> "str", so the tests see the layout Python decoded.
Server-wide faults for the tests of a whole cell: --fail-at-request N (the policy raises on
the server's N-th request, counting from 0 over all connections), --nan-entry D (actions[0, D]
is NaN) and --actions-dtype DTYPE (actions sent with that numpy dtype, e.g. "<i8"). Test-only observation keys: "test/actions_dtype" ("<f4" or "<f8", default "<f8"), "test/raise"
(the policy raises), "test/close_after_reply" (the server closes the connection with 1000 after
replying), "test/delay_s" (the reply is sent that many seconds late), "test/pad_bytes" (the reply
carries that many more bytes), "test/broken_actions" ("short_data": fewer bytes than the shape
needs, "huge_shape": a 2^40 x 2^40 shape, "bad_dtype": the dtype "zz9")."""

import argparse
import asyncio
import http
import time
import traceback

import numpy as np
import websockets

from openpi_msgpack_numpy import Packer, unpackb


def uint8_byte_sum(value):
    if isinstance(value, np.ndarray) and value.dtype == np.uint8:
        return int(value.sum(dtype=np.uint64))
    if isinstance(value, dict):
        return sum(uint8_byte_sum(item) for item in value.values())
    return 0


def structure(value, path=()):
    if isinstance(value, dict):
        found = {}
        for key, item in value.items():
            found.update(structure(item, path + (str(key),)))
        return found
    if isinstance(value, np.ndarray):
        return {"|".join(path): [value.dtype.str, list(value.shape)]}
    if isinstance(value, str):
        return {"|".join(path): "str"}
    return {}


class TestPolicy:
    def __init__(self, horizon, action_dim, action_scale, fail_at_request, nan_entry, actions_dtype):
        self.requests = 0
        self.fail_at_request = fail_at_request
        self.nan_entry = nan_entry
        self.actions_dtype = actions_dtype
        self.horizon = horizon
        self.action_dim = action_dim
        self.action_scale = action_scale
        self.metadata = {"reset_pose": [0, -1.5, 1.5, 0, 0, 0], "action_horizon": horizon,
                         "action_dim": action_dim, "server": "tavis test policy"}

    def infer(self, obs):
        request = self.requests
        self.requests += 1
        if "test/raise" in obs:
            raise RuntimeError(f"test policy asked to fail: {obs['test/raise']}")
        if request == self.fail_at_request:
            raise RuntimeError(f"test policy asked to fail at request {request}")
        state_key = next(key for key in ("observation/state", "observation.state", "state") if key in obs)
        state = [float(x) for x in np.asarray(obs[state_key]).reshape(-1)]
        image_sum = uint8_byte_sum(obs)
        offset = (image_sum % 1024) / 8 + len(obs.get("prompt", "").encode("utf-8")) * 0.25
        actions = np.array([[state[d % len(state)] * (t + 1) + offset + d for d in range(self.action_dim)]
                            for t in range(self.horizon)], dtype=np.float64) * self.action_scale
        if self.nan_entry >= 0:
            actions[0, self.nan_entry] = np.nan
        dtype = self.actions_dtype or obs.get("test/actions_dtype", "<f8")
        reply = {"actions": actions.astype(np.dtype(dtype)), "image_sum": image_sum, "received": structure(obs)}
        if "test/pad_bytes" in obs:
            reply["padding"] = bytes(int(obs["test/pad_bytes"]))
        broken = {"short_data": (b"\0" * 8, "<f8", [self.horizon, self.action_dim]),
                  "huge_shape": (b"\0" * 8, "<f8", [2 ** 40, 2 ** 40]),
                  "bad_dtype": (b"\0" * 8, "zz9", [1])}.get(obs.get("test/broken_actions"))
        if broken is not None:  # msgpack-numpy's map, written by hand: numpy would not build it
            reply["actions"] = {b"__ndarray__": True, b"data": broken[0], b"dtype": broken[1], b"shape": broken[2]}
        return reply


def serve(args):
    policy = TestPolicy(args.horizon, args.action_dim, args.action_scale, args.fail_at_request, args.nan_entry,
                        args.actions_dtype)
    packer = Packer()
    connections = 0

    async def handler(websocket, path=None):
        nonlocal connections
        connections += 1
        connection = connections
        await websocket.send(packer.pack(policy.metadata))
        prev_total_ms = None
        request = 0
        while True:
            try:
                start = time.monotonic()
                obs = unpackb(await websocket.recv())
                infer_start = time.monotonic()
                await asyncio.sleep(float(obs.get("test/delay_s", 0.0)))
                reply = policy.infer(obs)
                infer_ms = (time.monotonic() - infer_start) * 1000
                reply["connection"] = connection
                reply["request"] = request
                reply["policy_timing"] = {"infer_ms": infer_ms}
                reply["server_timing"] = {"infer_ms": infer_ms}
                if prev_total_ms is not None:
                    reply["server_timing"]["prev_total_ms"] = prev_total_ms
                await websocket.send(packer.pack(reply))
                prev_total_ms = (time.monotonic() - start) * 1000
                request += 1
                if obs.get("test/close_after_reply"):
                    await websocket.close(code=1000, reason="test asked to close")
                    return
            except websockets.ConnectionClosed:
                return
            except Exception:
                await websocket.send(traceback.format_exc())
                await websocket.close(code=1011, reason="Internal server error. Traceback included in previous frame.")
                return

    def health_check(path, request_headers):
        if path == "/healthz":
            return http.HTTPStatus.OK, [], b"OK\n"
        return None

    async def run():
        async with websockets.serve(handler, "127.0.0.1", args.port, compression=None, max_size=None,
                                    process_request=health_check, ping_interval=args.ping_interval,
                                    ping_timeout=args.ping_timeout):
            print(f"policy server listening on 127.0.0.1:{args.port}", flush=True)
            await asyncio.sleep(args.lifetime)

    time.sleep(args.startup_delay)
    asyncio.run(run())


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--port", type=int, required=True)
    parser.add_argument("--horizon", type=int, default=10)
    parser.add_argument("--action-dim", type=int, default=7)
    parser.add_argument("--action-scale", type=float, default=1.0,
                        help="scales every action, e.g. 1e-3 for arm targets near the robot")
    parser.add_argument("--fail-at-request", type=int, default=-1)
    parser.add_argument("--nan-entry", type=int, default=-1)
    parser.add_argument("--actions-dtype", default="", help="numpy dtype of every reply's actions, e.g. <i8")
    parser.add_argument("--ping-interval", type=float, default=20.0)
    parser.add_argument("--ping-timeout", type=float, default=20.0)
    parser.add_argument("--startup-delay", type=float, default=0.0, help="seconds before listening, like a model load")
    parser.add_argument("--lifetime", type=float, default=120.0, help="seconds to serve before exiting")
    serve(parser.parse_args())
