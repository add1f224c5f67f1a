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
with "|" -> [dtype, shape], and each str, bool, int and list -> "str", "bool", "int", "list", so the
tests see the layout Python decoded.
Server-wide faults for the tests of a whole cell: --fail-at-request N (the policy raises on
the server's N-th request, counting from 0 over all connections), --nan-entry D (actions[0, D]
is NaN) and --actions-dtype DTYPE (actions sent with that numpy dtype, e.g. "<i8"). Test-only observation keys: "test/actions_dtype" ("<f4" or "<f8", default "<f8"), "test/raise"
(the policy raises), "test/close_after_reply" (the server closes the connection with 1000 after
replying), "test/delay_s" (the reply is sent that many seconds late), "test/pad_bytes" (the reply
carries that many more bytes), "test/broken_actions" ("short_data": fewer bytes than the shape
needs, "huge_shape": a 2^40 x 2^40 shape, "bad_dtype": the dtype "zz9").

Serving modes (remote_policy.h): with --batched the metadata declares batched_requests and a
request carrying batch_size N is split into its N per-env requests (row i of every stacked value),
each answered by the function above, and the chunks are stacked (N x H x D), so a batched cell must
record exactly what a serial one does. --check-steps keeps, per env slot, the episode and the last
policy step received and fails (traceback) unless each episode's requests come as steps 0, 1, 2, ...
(horizon 1) with is_first on step 0 only; --steps-out FILE writes what it saw per (env, episode)
as JSON when it exits. --sleep-ms MS makes each forward pass (a message, whatever its batch size)
take MS ms, one pass at a time as on one GPU; --constant-action ROW answers that 19-entry CSV row in
every chunk row (a valid action for throughput runs). --replay-actions FILE (JSON {"episode": rows}, or a
folder of episode_<i>.csv as a cell's DIR/actions) answers rows[step : step + horizon] of the
request's episode (the last row past its end);
--record-dir DIR saves every per-env request as DIR/e<episode>_s<step>.npz (strings and scalars
as 0-d arrays). --no-healthz answers no /healthz, as servers without openpi's probe do."""

import argparse
import asyncio
import http
import json
import os
import signal
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


def structure_values(value, path=()):
    """Every leaf of a (nested) request by its key path joined with "|"."""
    if isinstance(value, dict):
        found = {}
        for key, item in value.items():
            found.update(structure_values(item, path + (str(key),)))
        return found
    return {"|".join(path): value}


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
    if isinstance(value, bool):
        return {"|".join(path): "bool"}
    if isinstance(value, int):
        return {"|".join(path): "int"}
    if isinstance(value, list):
        return {"|".join(path): "list"}
    return {}


def split_batch(obs):
    """The per-env requests of a batched request: row i of every stacked value."""
    count = int(obs["batch_size"])

    def row(value, i):
        if isinstance(value, dict):
            return {key: row(item, i) for key, item in value.items()}
        if isinstance(value, np.ndarray):
            item = value[i]
            return item.item() if item.ndim == 0 and value.dtype.kind in "bi" else item
        if isinstance(value, list):
            return value[i]
        return value

    return [row({key: value for key, value in obs.items() if key != "batch_size"}, i) for i in range(count)]


class StepChecker:
    """Fails unless every (env, episode) is asked at steps 0, 1, 2, ... with is_first on step 0."""

    def __init__(self):
        self.last = {}  # env_index -> (episode_index, last step)
        self.seen = {}  # "env/episode" -> {"steps": n, "first_flags": n}

    def check(self, obs):
        env, episode, step, first = (obs["env_index"], obs["episode_index"], obs["step"], bool(obs["is_first"]))
        previous = self.last.get(env)
        expected = 0 if previous is None or previous[0] != episode else previous[1] + 1
        if step != expected or first != (step == 0):
            raise RuntimeError(f"env {env} episode {episode}: got step {step} (is_first {first}), expected step {expected}")
        self.last[env] = (episode, step)
        entry = self.seen.setdefault(f"{env}/{episode}", {"steps": 0, "first_flags": 0})
        entry["steps"] += 1
        entry["first_flags"] += int(first)


class CsvEpisodes:
    """A served cell's DIR/actions (episode_<i>.csv, or .csv.gz as cells save them: one 19-wide row
    per policy step) by episode."""

    def __init__(self, folder):
        self.folder = folder
        self.loaded = {}

    def __getitem__(self, episode):
        if episode not in self.loaded:
            path = os.path.join(self.folder, f"episode_{episode}.csv")
            if not os.path.exists(path):
                path += ".gz"  # np.loadtxt reads gzip by the name
            rows = np.loadtxt(path, delimiter=",", ndmin=2)
            self.loaded[episode] = rows.tolist()
        return self.loaded[episode]


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
        self.step_checker = None
        self.recorder = None
        self.constant_action = None
        self.replay = None

    def infer_batch(self, obs):
        replies = [self.infer(single) for single in split_batch(obs)]
        return {"actions": np.stack([reply["actions"] for reply in replies]), "received": structure(obs)}

    def infer(self, obs):
        if self.step_checker is not None:
            self.step_checker.check(obs)
        if self.recorder is not None:
            self.recorder(obs)
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
        if self.constant_action is not None:
            actions = np.tile(self.constant_action, (self.horizon, 1))
        if self.replay is not None:
            rows = self.replay[str(obs["episode_index"])]
            actions = np.array([rows[min(obs["step"] + t, len(rows) - 1)] for t in range(self.horizon)], dtype=np.float64)
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
    if args.batched:
        policy.metadata["batched_requests"] = True
    if args.check_steps:
        policy.step_checker = StepChecker()
    if args.constant_action:
        policy.constant_action = np.array([float(x) for x in args.constant_action.split(",")], dtype=np.float64)
    if os.path.isdir(args.replay_actions):
        policy.replay = CsvEpisodes(args.replay_actions)
    elif args.replay_actions:
        with open(args.replay_actions) as file:
            policy.replay = json.load(file)
    if args.record_dir:
        os.makedirs(args.record_dir, exist_ok=True)

        def record(obs):
            flat = {}
            for key, value in structure_values(obs).items():
                flat[key] = np.asarray(value)
            np.savez(os.path.join(args.record_dir, f"e{obs['episode_index']}_s{obs['step']}.npz"), **flat)

        policy.recorder = record
    packer = Packer()
    connections = 0
    forward_pass = asyncio.Lock() if args.sleep_ms > 0 else None

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
                if forward_pass is not None:
                    async with forward_pass:
                        await asyncio.sleep(args.sleep_ms / 1000.0)
                reply = policy.infer_batch(obs) if "batch_size" in obs else policy.infer(obs)
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
        if path == "/healthz" and not args.no_healthz:
            return http.HTTPStatus.OK, [], b"OK\n"
        return None

    async def run():
        async with websockets.serve(handler, "127.0.0.1", args.port, compression=None, max_size=None,
                                    process_request=health_check, ping_interval=args.ping_interval,
                                    ping_timeout=args.ping_timeout):
            print(f"policy server listening on 127.0.0.1:{args.port}", flush=True)
            await asyncio.sleep(args.lifetime)

    def write_steps():
        if args.steps_out and policy.step_checker is not None:
            with open(args.steps_out + ".partial", "w") as file:
                json.dump(policy.step_checker.seen, file)
            os.replace(args.steps_out + ".partial", args.steps_out)

    def terminate(*_):
        write_steps()
        os._exit(0)

    signal.signal(signal.SIGTERM, terminate)
    time.sleep(args.startup_delay)
    try:
        asyncio.run(run())
    finally:
        write_steps()


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
    parser.add_argument("--batched", action="store_true", help="declare and answer batched requests")
    parser.add_argument("--check-steps", action="store_true", help="fail unless each episode asks at steps 0, 1, 2, ...")
    parser.add_argument("--steps-out", default="", help="with --check-steps: JSON of what was seen, written at exit")
    parser.add_argument("--sleep-ms", type=float, default=0.0, help="each forward pass takes this long, one at a time")
    parser.add_argument("--constant-action", default="", help="a CSV row answered in every chunk row")
    parser.add_argument("--replay-actions", default="", help='JSON {"episode": [[19 values], ...]} answered by step')
    parser.add_argument("--record-dir", default="", help="save every per-env request as e<episode>_s<step>.npz")
    parser.add_argument("--no-healthz", action="store_true", help="answer no /healthz")
    serve(parser.parse_args())
