"""Serves a trained checkpoint to `tavis eval --policy openpi` through tavis_server.

    python3 -m tavis_baseline.serve CKPT_DIR --port 8000 [--device cuda] [--host 127.0.0.1] [--executed-steps K]
        [--temporal-ensemble M]

runs tavis_server with the chunk execution the checkpoint's config.json holds (executed_steps,
default 10, docs/baselines.md "Chunk execution"):

    executed_steps k > 1 (a queue of k rows): python3 -m tavis_server --policy tavis_baseline.serve:make_policy \\
        --policy-arg checkpoint_dir=CKPT_DIR --action-queue on --n-action-steps k --port 8000
    executed_steps 1 (re-plan every step): ... --action-queue off --n-action-steps 1
    temporal ensembling (temporal_ensemble M): python3 -m tavis_server --policy tavis_baseline.serve:make_policy \
        --policy-arg checkpoint_dir=CKPT_DIR --policy-arg temporal_ensemble=M --port 8000 (the factory
        returns ensembled_serving.py's served object: no queue, a forward pass every step)

--executed-steps K serves the checkpoint with K instead, --temporal-ensemble M with temporal
ensembling (the metadata the server sends, which `tavis eval` copies into summary.json's
server_metadata, says which: executed_steps, chunk_execution, temporal_ensemble, action_queue,
n_action_steps). The policy keeps an observation history
(config.n_obs_steps consecutive steps), so tavis_server wants every policy step asked: run the
client with `--replan-steps 1`.
"""

import argparse
import hashlib
import os
import sys

from . import checkpoint
from .temporal_ensemble import check_coefficient


def make_policy(checkpoint_dir, device="cpu", executed_steps=None, temporal_ensemble=None):
    """The tavis_server factory: the checkpoint's policy on `device`, ready to serve, or under temporal
    ensembling tavis_server's served object for it. executed_steps and temporal_ensemble, when
    either is given, replace the checkpoint's chunk execution (executed_steps alone turns ensembling
    off). A checkpoint older than the setting is said so on stderr."""
    notes = []
    policy = checkpoint.load(checkpoint_dir, device, notes=notes)
    if executed_steps is not None or temporal_ensemble is not None:
        policy.config.execute_with(1 if executed_steps is None else executed_steps, temporal_ensemble)  # validates
    for note in notes:
        print(f"tavis_baseline.serve: {note}", file=sys.stderr, flush=True)
    policy.declared_contract = observation_contract(policy.config, checkpoint_dir)
    if policy.config.temporal_ensemble is not None:
        from .ensembled_serving import EnsembledServedPolicy  # imports tavis_server, which only serving needs
        return EnsembledServedPolicy(policy, "tavis_baseline.serve:make_policy", device)
    return policy


def observation_contract(config, checkpoint_dir):
    """What the checkpoint was trained on, for the metadata frame's observation_contract (tavis_server's
    contract.py adds n_obs_steps, chunk_length and executed_steps from how it serves; docs/serving.md):
    its cameras' image keys (the fixed camera's under the fixed protocol, with head's key beside it as
    the tavis layout has), the training image size, observation.state's length, model.pt's SHA-256, and
    the task and robot the config says it was trained for, when it says (an older checkpoint's does
    not: it declares neither, and is served to any cell as before)."""
    keys = config.image_keys
    cameras = {"head": keys[0]} if config.camera == "head" else {"head": "observation.images.OBS_HEAD", "fixed": keys[0]}
    cameras.update({"left_wrist": keys[1], "right_wrist": keys[2]})
    height, width = config.image_size
    digest = hashlib.sha256()
    with open(os.path.join(checkpoint_dir, "model.pt"), "rb") as weights:
        for block in iter(lambda: weights.read(1 << 20), b""):
            digest.update(block)
    contract = {"version": 1, "cameras": cameras, "image_width": int(width), "image_height": int(height),
                "state": {"key": "observation.state", "size": int(config.state_dim)},
                "checkpoint_sha256": digest.hexdigest()}
    contract.update({name: getattr(config, name) for name in ("task", "robot") if getattr(config, name) is not None})
    return contract


def server_arguments(checkpoint_dir, executed_steps, port, host, device, seed=None, temporal_ensemble=None):
    """tavis_server's command line serving `checkpoint_dir` with `executed_steps` rows per forward pass:
    1 is no queue and 1-row replies (every step a forward pass); k > 1 the server's queue of k rows;
    temporal_ensemble M: make_policy's ensembled served object, which keeps no queue of its own."""
    if temporal_ensemble is not None:
        queue = ["--policy-arg", f"temporal_ensemble={temporal_ensemble!r}"]
    elif executed_steps == 1:
        queue = ["--action-queue", "off", "--n-action-steps", "1"]
    else:
        queue = ["--action-queue", "on", "--n-action-steps", str(executed_steps)]
    result = ["--policy", "tavis_baseline.serve:make_policy", "--policy-arg", f"checkpoint_dir={checkpoint_dir}",
              *queue, "--port", str(port), "--host", host, "--device", device]
    if seed is not None:
        result += ["--seed", str(seed)]
    return result


def positive(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} must be at least 1")
    return value


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m tavis_baseline.serve", description=__doc__.splitlines()[0])
    parser.add_argument("checkpoint", help="a folder written by tavis_baseline.train")
    parser.add_argument("--port", type=int, default=8000, help="0: a free port (printed)")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--seed", type=int, default=None)
    parser.add_argument("--executed-steps", type=positive, default=None, metavar="K",
                        help="rows of each predicted chunk executed per forward pass (1: re-plan every step; "
                             "default: the checkpoint's executed_steps)")
    parser.add_argument("--temporal-ensemble", type=float, default=None, metavar="M",
                        help="serve with ACT's temporal ensembling: a forward pass every step, each step's action the "
                             "exp(-M * i)-weighted mean of every chunk's row for it (ACT: M = 0.01; default: the "
                             "checkpoint's temporal_ensemble, off once --executed-steps is given)")
    args = parser.parse_args(argv)
    try:
        config = checkpoint.load(args.checkpoint, "cpu").config  # a bad folder fails here, with its own message
        executed_steps = config.executed_steps if args.executed_steps is None else args.executed_steps
        if executed_steps > config.chunk_size:
            raise ValueError(f"--executed-steps {executed_steps}: the checkpoint predicts chunks of "
                             f"{config.chunk_size} rows")
        temporal_ensemble = args.temporal_ensemble
        if temporal_ensemble is None and args.executed_steps is None:
            temporal_ensemble = config.temporal_ensemble
        if temporal_ensemble is not None:
            temporal_ensemble = check_coefficient(temporal_ensemble, "--temporal-ensemble")
            if args.executed_steps not in (None, 1):
                raise ValueError(f"--temporal-ensemble runs a forward pass every step: --executed-steps "
                                 f"{args.executed_steps} must be 1 or left out")
            executed_steps = 1
    except ValueError as error:
        print(f"tavis_baseline.serve: {error}", file=sys.stderr)
        return 2
    try:
        from tavis_server import cli
    except ImportError:
        print("tavis_baseline.serve: the tavis_server package is not importable (tools/policy_server on PYTHONPATH?)",
              file=sys.stderr)
        return 2
    arguments = server_arguments(args.checkpoint, executed_steps, args.port, args.host, args.device, args.seed,
                                 temporal_ensemble)
    if args.executed_steps is not None and temporal_ensemble is None:
        arguments += ["--policy-arg", f"executed_steps={executed_steps}"]
    return cli.main(arguments)


if __name__ == "__main__":
    sys.exit(main())
