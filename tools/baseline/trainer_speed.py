"""The trainer's two CUDA paths side by side on one dataset: N steps eager (--no-compile) and N
steps compiled (torch.compile + one CUDA graph per step), one after the other in this process,
with the same seed and settings. Prints steps/s and samples/s of each (the median of the logged
windows after the first, and the whole loop's) and checks that each lowered its loss and that the
two end at similar losses (they draw different random numbers, so not the same ones).

    PYTHONPATH=tools/baseline:tools/policy_server python3 tools/baseline/trainer_speed.py --dataset DS --steps 600 \\
        [--device cuda] [--batch-size 256] [--camera head] [--image-size 96x96] [--keep DIR]

DS: a `tavis demos` dataset (docs/baselines.md). Exit status 0 when both runs lowered the loss,
the compiled run really ran compiled, and their last losses are within a factor of 1.5; 1
otherwise (the reason is printed)."""

import argparse
import json
import statistics
import sys
import tempfile
from pathlib import Path

from tavis_baseline import train

MODES = (("eager", ["--no-compile"]), ("compiled", []))


def run(mode_args, args, out):
    argv = ["--dataset", args.dataset, "--out", str(out), "--steps", str(args.steps), "--device", args.device,
            "--batch-size", str(args.batch_size), "--camera", args.camera, "--seed", "0",
            "--log-every", str(max(1, args.steps // 6)), "--save-every", str(args.steps + 1), *mode_args]
    if args.image_size:
        argv += ["--image-size", args.image_size]
    if train.main(argv) != 0:
        raise SystemExit(f"trainer_speed: the training into {out} failed (above)")
    summary = json.loads((out / "training.json").read_text())
    log = [json.loads(line) for line in (out / "train_log.jsonl").read_text().splitlines()]
    windows = [entry["steps_per_s"] for entry in log[1:]] or [log[0]["steps_per_s"]]
    return {"mode": summary["step_mode"], "prepare_s": summary["prepare_s"],
            "steps_per_s": statistics.median(windows), "loop_steps_per_s": summary["steps_per_s"],
            "samples_per_s": statistics.median(windows) * args.batch_size,
            "first_loss": log[0]["loss"], "last_loss": log[-1]["loss"]}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dataset", required=True)
    parser.add_argument("--steps", type=int, default=600)
    parser.add_argument("--device", default="cuda")
    parser.add_argument("--batch-size", type=int, default=256)
    parser.add_argument("--camera", default="head", choices=("head", "fixed"))
    parser.add_argument("--image-size", default=None, help="WIDTHxHEIGHT (default: the videos')")
    parser.add_argument("--keep", default=None, help="a folder to keep the two checkpoints in (default: a temporary one)")
    args = parser.parse_args(argv)
    if args.steps < 12:
        parser.error("--steps must be at least 12 (six logged windows)")
    with tempfile.TemporaryDirectory(prefix="trainer_speed_") as temporary:
        folder = Path(args.keep or temporary)
        results = {name: run(mode_args, args, folder / name) for name, mode_args in MODES}
    problems = []
    print(f"\n{'path':<10} {'step mode':<24} {'prepare s':>9} {'steps/s':>9} {'samples/s':>10} {'loop steps/s':>12} "
          f"{'first loss':>10} {'last loss':>10}")
    for name, result in results.items():
        print(f"{name:<10} {result['mode']:<24} {result['prepare_s']:>9.1f} {result['steps_per_s']:>9.1f} "
              f"{result['samples_per_s']:>10.0f} {result['loop_steps_per_s']:>12.1f} {result['first_loss']:>10.4f} "
              f"{result['last_loss']:>10.4f}")
        if not result["last_loss"] < result["first_loss"]:
            problems.append(f"{name}: the loss did not fall ({result['first_loss']:.4f} -> {result['last_loss']:.4f})")
    eager, compiled = results["eager"], results["compiled"]
    if compiled["mode"] == eager["mode"]:
        problems.append(f"the compiled run ran {compiled['mode']!r} (needs CUDA and PyTorch 2.x)")
    ratio = compiled["last_loss"] / eager["last_loss"]
    if not 1 / 1.5 <= ratio <= 1.5:
        problems.append(f"the last losses differ by a factor {ratio:.2f} (eager {eager['last_loss']:.4f}, "
                        f"compiled {compiled['last_loss']:.4f})")
    print(f"\ncompiled / eager: {compiled['steps_per_s'] / eager['steps_per_s']:.2f}x steps/s; "
          f"last losses {eager['last_loss']:.4f} eager, {compiled['last_loss']:.4f} compiled")
    for problem in problems:
        print(f"trainer_speed: {problem}", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
