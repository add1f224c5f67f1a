"""Serves a trained checkpoint to `tavis eval --policy openpi` through tavis_server.

    python3 -m tavis_baseline.serve CKPT_DIR --port 8000 [--device cuda] [--host 127.0.0.1] [--executed-steps K]

runs tavis_server with the chunk execution the checkpoint's config.json holds (executed_steps,
default 10, docs/baselines.md "Chunk execution"):

    executed_steps k > 1 (a queue of k rows): python3 -m tavis_server --policy tavis_baseline.serve:make_policy \\
        --policy-arg checkpoint_dir=CKPT_DIR --action-queue on --n-action-steps k --port 8000
    executed_steps 1 (re-plan every step): ... --action-queue off --n-action-steps 1

--executed-steps K serves the checkpoint with K instead (the metadata the server sends, which
`tavis eval` copies into summary.json's server_metadata, says which: executed_steps,
chunk_execution, action_queue, n_action_steps). The policy keeps an observation history
(config.n_obs_steps consecutive steps), so tavis_server wants every policy step asked: run the
client with `--replan-steps 1`.
"""

import argparse
import sys

from . import checkpoint


def make_policy(checkpoint_dir, device="cpu", executed_steps=None):
    """The tavis_server factory: the checkpoint's policy on `device`, ready to serve; executed_steps
    replaces the checkpoint's setting. A checkpoint older than the setting is said so on stderr."""
    notes = []
    policy = checkpoint.load(checkpoint_dir, device, notes=notes)
    if executed_steps is not None:
        policy.config.n_action_steps = executed_steps  # validated there
    for note in notes:
        print(f"tavis_baseline.serve: {note}", file=sys.stderr, flush=True)
    return policy


def server_arguments(checkpoint_dir, executed_steps, port, host, device, seed=None):
    """tavis_server's command line serving `checkpoint_dir` with `executed_steps` rows per forward pass:
    1 is no queue and 1-row replies (every step a forward pass); k > 1 the server's queue of k rows."""
    queue = ["--action-queue", "off", "--n-action-steps", "1"] if executed_steps == 1 else \
        ["--action-queue", "on", "--n-action-steps", str(executed_steps)]
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
    args = parser.parse_args(argv)
    try:
        config = checkpoint.load(args.checkpoint, "cpu").config  # a bad folder fails here, with its own message
        executed_steps = config.executed_steps if args.executed_steps is None else args.executed_steps
        if executed_steps > config.chunk_size:
            raise ValueError(f"--executed-steps {executed_steps}: the checkpoint predicts chunks of "
                             f"{config.chunk_size} rows")
    except ValueError as error:
        print(f"tavis_baseline.serve: {error}", file=sys.stderr)
        return 2
    try:
        from tavis_server import cli
    except ImportError:
        print("tavis_baseline.serve: the tavis_server package is not importable (batch/python on PYTHONPATH?)",
              file=sys.stderr)
        return 2
    arguments = server_arguments(args.checkpoint, executed_steps, args.port, args.host, args.device, args.seed)
    if args.executed_steps is not None:
        arguments += ["--policy-arg", f"executed_steps={executed_steps}"]
    return cli.main(arguments)


if __name__ == "__main__":
    sys.exit(main())
