"""Serves a trained checkpoint to `tavis eval --policy openpi` through tavis_server.

    python3 -m tavis_baseline.serve CKPT_DIR --port 8000 [--device cuda] [--host 127.0.0.1]

is the same as

    python3 -m tavis_server --policy tavis_baseline.serve:make_policy --policy-arg checkpoint_dir=CKPT_DIR --port 8000

The policy keeps an observation history (config.n_obs_steps consecutive steps), so tavis_server
wants every policy step asked: run the client with `--replan-steps 1` (docs/baselines.md).
"""

import argparse
import sys

from . import checkpoint


def make_policy(checkpoint_dir, device="cpu"):
    """The tavis_server factory: the checkpoint's policy on `device`, ready to serve."""
    return checkpoint.load(checkpoint_dir, device)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m tavis_baseline.serve", description=__doc__.splitlines()[0])
    parser.add_argument("checkpoint", help="a folder written by tavis_baseline.train")
    parser.add_argument("--port", type=int, default=8000, help="0: a free port (printed)")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--seed", type=int, default=None)
    args = parser.parse_args(argv)
    try:
        checkpoint.load(args.checkpoint, "cpu")  # a bad folder fails here, with its own message
    except ValueError as error:
        print(f"tavis_baseline.serve: {error}", file=sys.stderr)
        return 2
    try:
        from tavis_server import cli
    except ImportError:
        print("tavis_baseline.serve: the tavis_server package is not importable (batch/python on PYTHONPATH?)",
              file=sys.stderr)
        return 2
    server_args = ["--policy", "tavis_baseline.serve:make_policy", "--policy-arg", f"checkpoint_dir={args.checkpoint}",
                   "--port", str(args.port), "--host", args.host, "--device", args.device]
    if args.seed is not None:
        server_args += ["--seed", str(args.seed)]
    return cli.main(server_args)


if __name__ == "__main__":
    sys.exit(main())
