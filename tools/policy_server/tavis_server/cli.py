"""python3 -m tavis_server: serve a policy to `tavis eval --policy openpi --server ws://HOST:PORT`.

  --policy echo | sleep | stateful          the built-in stand-ins (standins.py)
  --policy MODULE:FACTORY [--policy-arg K=V ...]
        FACTORY(**args) returns a LeRobot-interface policy, or (policy, preprocess, postprocess);
        it also gets device=... when its signature takes `device`. V is read as JSON when it parses
        (numbers, true/false, lists), else as a string.
  --action-queue auto|on|off, --n-action-steps N   LeRobot-interface policies: execute N rows of each
        chunk one per step from a server-side queue (auto: when n_obs_steps > 1; docs/serving.md)
  --contract FILE.json   the contract the policy was trained on, sent in the metadata frame (contract.py)
  --max-request-mb M, --idle-timeout S   a longer frame is refused (close 1009); a connection that
        sends no request for S seconds is closed (defaults in server.py)
Prints one line "tavis_server: serving POLICY on ws://HOST:PORT" once it listens (--port 0 picks a
free port, printed there); SIGTERM or SIGINT stops it (the stateful stand-in's record is final)."""

import argparse
import asyncio
import importlib
import inspect
import json
import signal
import sys

from .actions import NEUTRAL_ACTION, parse_action_row
from .contract import CONTRACT_KEY
from .lerobot_policy import ACTION_QUEUE_MODES, LeRobotServedPolicy
from .policy_batch import import_torch
from .server import DEFAULT_IDLE_TIMEOUT_S, DEFAULT_MAX_REQUEST_MB, PolicyServer
from .standins import EchoPolicy, SleepPolicy, StatefulCheckPolicy

STAND_INS = ("echo", "sleep", "stateful")


def _policy_args(pairs):
    args = {}
    for pair in pairs:
        key, separator, value = pair.partition("=")
        if not separator or not key.strip():
            raise ValueError(f"--policy-arg {pair!r} is not KEY=VALUE")
        if key in args:
            raise ValueError(f"--policy-arg {pair!r}: {key} is given twice")
        try:
            args[key] = json.loads(value)
        except json.JSONDecodeError:
            args[key] = value
    return args


def _factory(spec):
    module_name, separator, attribute = spec.partition(":")
    if not separator or not module_name or not attribute:
        raise ValueError(f"--policy {spec!r} is neither a stand-in ({', '.join(STAND_INS)}) nor MODULE:FACTORY")
    module = importlib.import_module(module_name)
    factory = getattr(module, attribute, None)
    if not callable(factory):
        raise ValueError(f"--policy {spec!r}: module {module_name} has no callable {attribute}")
    return factory


def _takes_device(factory):
    try:
        parameters = inspect.signature(factory).parameters.values()
    except (TypeError, ValueError):
        return False
    return any(p.name == "device" or p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters)


def _no_queue_options(options, what):
    """ValueError when queue options are given for a policy the server serves directly."""
    if options.action_queue != "auto" or options.n_action_steps is not None:
        raise ValueError(f"--action-queue/--n-action-steps apply to LeRobot-interface policies, not to {what}")


def build_served_policy(options):
    """The object PolicyServer serves, from the parsed command line."""
    if options.policy in STAND_INS and options.policy_arg:
        raise ValueError(f"--policy-arg {options.policy_arg[0]!r}: the {options.policy} stand-in takes no "
                         f"--policy-arg (its options are --chunk, --sleep-ms, --action-row, --history, --record)")
    row = parse_action_row(options.action_row) if options.action_row else NEUTRAL_ACTION
    if options.policy in ("echo", "stateful") or (options.policy == "sleep" and not options.device):
        _no_queue_options(options, f"the {options.policy} stand-in served directly")
    chunk = (10 if options.policy == "sleep" else 1) if options.chunk is None else options.chunk
    if options.policy == "echo":
        return EchoPolicy(chunk=chunk)
    if options.policy == "stateful":
        return StatefulCheckPolicy(chunk=chunk, history=options.history, record_path=options.record,
                                   action_row=row)
    if options.policy == "sleep":
        sleeper = SleepPolicy(options.sleep_ms, chunk, row)
        if not options.device:
            return sleeper  # nothing but the sleep
        # Like a checkpoint: input tensors built on the device, then the sleep.
        return LeRobotServedPolicy(sleeper, name="sleep", device=options.device, torch=import_torch(),
                                   action_queue=options.action_queue, n_action_steps=options.n_action_steps)
    torch = import_torch()
    device = options.device or "cpu"
    factory = _factory(options.policy)
    args = _policy_args(options.policy_arg)
    if _takes_device(factory):
        args.setdefault("device", device)
    made = factory(**args)
    if hasattr(made, "infer") and hasattr(made, "history_length"):  # already a served policy
        _no_queue_options(options, f"{options.policy}, which returned a served policy")
        return made
    policy, preprocess, postprocess = made if isinstance(made, tuple) else (made, None, None)
    if torch is not None and isinstance(policy, torch.nn.Module):
        policy = policy.to(device).eval()
    return LeRobotServedPolicy(policy, name=options.policy, device=device, preprocess=preprocess,
                               postprocess=postprocess, torch=torch, action_queue=options.action_queue,
                               n_action_steps=options.n_action_steps)


def _read_contract(path):
    """--contract FILE.json's object (checked with the server's own fields by PolicyServer)."""
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, json.JSONDecodeError) as error:
        raise ValueError(f"--contract {path}: {error}") from None


def _integer_in(text, low, high, what):
    """An int from low to high (inclusive) parsed from `text`, else argparse's error naming it."""
    try:
        value = int(text)
    except ValueError:
        value = None
    if value is None or not low <= value <= high:
        raise argparse.ArgumentTypeError(f"{text!r} is not {what}")
    return value


def _port(text):
    """argparse type: a TCP port, 0 (a free one) to 65535."""
    return _integer_in(text, 0, 65535, "a port number from 0 to 65535")


def _seed(text):
    """argparse type: what numpy's global generator takes."""
    return _integer_in(text, 0, 2 ** 32 - 1, "a seed from 0 to 2**32 - 1")


def _positive(text):
    """argparse type: a finite number above 0."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0 < value < float("inf"):
        raise argparse.ArgumentTypeError(f"{text!r} is not a positive number")
    return value


def parser():
    result = argparse.ArgumentParser(prog="python3 -m tavis_server", description=__doc__.splitlines()[0])
    result.add_argument("--policy", required=True, help="echo, sleep, stateful, or MODULE:FACTORY")
    result.add_argument("--policy-arg", action="append", default=[], metavar="K=V", help="FACTORY keyword argument")
    result.add_argument("--host", default="127.0.0.1")
    result.add_argument("--port", type=_port, default=8000, help="0: a free port (printed)")
    result.add_argument("--max-request-mb", type=_positive, default=DEFAULT_MAX_REQUEST_MB, metavar="MB",
                        help="the longest request frame read, in MiB; a longer one closes its connection with 1009 "
                             f"(default {DEFAULT_MAX_REQUEST_MB}: twice a batched request of 96 envs with three "
                             "320x240 cameras)")
    result.add_argument("--idle-timeout", type=_positive, default=DEFAULT_IDLE_TIMEOUT_S, metavar="S",
                        help="seconds a connection may wait between requests before it is closed (its per-env "
                             f"state goes with it; default {DEFAULT_IDLE_TIMEOUT_S:g})")
    result.add_argument("--device", default=None,
                        help="torch device of the policy and its inputs: cpu (default), cuda, cuda:1; the sleep "
                             "stand-in builds no inputs unless given one")
    result.add_argument("--action-queue", choices=ACTION_QUEUE_MODES, default="auto",
                        help="LeRobot-interface policies: answer each step from a per-env queue of n_action_steps "
                             "rows, a forward pass only when it is used up, as select_action does (auto: on when "
                             "n_obs_steps > 1; needs the client's --replan-steps 1)")
    result.add_argument("--n-action-steps", type=int, default=None, metavar="N",
                        help="LeRobot-interface policies: rows executed per chunk (sets config.n_action_steps; "
                             "default the policy's)")
    result.add_argument("--seed", type=_seed, default=None, help="seeds torch's and numpy's global generators")
    result.add_argument("--chunk", type=int, default=None, help="stand-ins: rows per reply (echo, stateful 1; sleep 10)")
    result.add_argument("--sleep-ms", type=float, default=30.0, help="sleep stand-in: milliseconds per forward pass")
    result.add_argument("--action-row", default="", metavar="CSV",
                        help="sleep/stateful stand-ins: the 19 comma-separated values of their action")
    result.add_argument("--history", type=int, default=1,
                        help="stateful stand-in: observation history length (> 1: steps must be consecutive)")
    result.add_argument("--contract", default=None, metavar="JSON",
                        help="a JSON file of the contract the policy was trained on (cameras, image_width, "
                             "image_height, state, checkpoint_sha256, task, robot), sent in the metadata frame as "
                             "observation_contract with the server's n_obs_steps, chunk_length and executed_steps "
                             "(docs/serving.md); it replaces one the policy declares")
    result.add_argument("--record", default=None, metavar="JSON",
                        help="stateful stand-in: file rewritten after every request with the steps received")
    return result


async def _run(server):
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    for signum in (signal.SIGTERM, signal.SIGINT):
        loop.add_signal_handler(signum, stop.set)

    def ready(port):
        print(f"tavis_server: serving {server.served.name} on ws://{server.host}:{port}", flush=True)

    await server.serve(ready=ready, stop=stop)


def main(argv=None):
    options = parser().parse_args(argv)
    try:
        if options.seed is not None:
            import numpy
            numpy.random.seed(options.seed)
            if options.policy not in STAND_INS and import_torch() is not None:
                import_torch().manual_seed(options.seed)
        served = build_served_policy(options)
        if options.contract is not None:
            served.metadata = {**served.metadata, CONTRACT_KEY: _read_contract(options.contract)}
        server = PolicyServer(served, host=options.host, port=options.port, max_request_mb=options.max_request_mb,
                              idle_timeout_s=options.idle_timeout)
    except (ValueError, ImportError) as error:
        print(f"tavis_server: {error}", file=sys.stderr)
        return 2
    try:
        asyncio.run(_run(server))
    except OSError as error:
        print(f"tavis_server: cannot listen on {options.host}:{options.port}: {error}", file=sys.stderr)
        return 1
    finally:
        server.close()
    return 0
