"""Trains the baseline policy on a `tavis demos` dataset (docs/baselines.md).

    python3 -m tavis_baseline.train --dataset DIR --camera head|fixed --out CKPT_DIR --steps N --seed S \
        [--device cuda] [--image-size 96x96] [--time-budget-s 540] ...

All frames are decoded into memory once (uint8, moved to the device); each step gathers its batch
by indexing and augments on the device. On CUDA the forward pass runs under bf16 autocast. On the
CPU a seed gives the same weights run after run. The checkpoint (config.json, stats.json, model.pt,
training.json) is saved every --save-every steps and at the end, including when --time-budget-s
runs out (training then stops cleanly after the step in progress).
"""

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np
import torch

from . import checkpoint, train_output
from .config import ACT_OPTIONS, EXECUTED_STEPS_DEFAULT, EXECUTION_DEFAULT_WHY, HEADS, VISIONS, BaselineConfig
from .dataset import ACTION, STATE, DemoDataset
from .dataset_origin import recorded_task_and_robot
from .normalization import QUATERNION_ACTION_DIMS, mean_std
from .policy import BaselinePolicy
from .train_step import EagerStep, GraphedStep, autocast, batch_loss, can_compile


def parse_size(text):
    """'WIDTHxHEIGHT' (as `tavis demos --image-size`) -> [height, width]."""
    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--image-size {text!r} must be WIDTHxHEIGHT, e.g. 96x96") from None
    if width < 16 or height < 16:
        raise argparse.ArgumentTypeError(f"--image-size {text!r}: each side must be >= 16")
    return [height, width]


def arguments(argv):
    parser = argparse.ArgumentParser(prog="python3 -m tavis_baseline.train", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--dataset", required=True, help="a LeRobot v3.0 dataset written by `tavis demos`")
    parser.add_argument("--camera", choices=("head", "fixed"), default="head", help="protocol: OBS_HEAD or OBS_FIXED + wrists")
    parser.add_argument("--out", required=True, help="checkpoint folder (must be new or empty unless --overwrite)")
    parser.add_argument("--overwrite", action="store_true")
    parser.add_argument("--steps", type=int, default=20000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--device", default="cpu", help="cpu, cuda, cuda:1 ...")
    parser.add_argument("--image-size", type=parse_size, default=None, help="WIDTHxHEIGHT the CNN sees (default: the videos')")
    parser.add_argument("--batch-size", type=int, default=256)
    parser.add_argument("--lr", type=float, default=3e-4)
    parser.add_argument("--weight-decay", type=float, default=1e-4)
    parser.add_argument("--warmup-steps", type=int, default=500)
    parser.add_argument("--history-frames", type=int, default=2, help="frames the network sees (1: no history)")
    parser.add_argument("--history-stride", type=int, default=10, help="frames between them (10 at 20 fps: 0.5 s)")
    parser.add_argument("--chunk-size", type=int, default=20)
    parser.add_argument("--executed-steps", "--n-action-steps", dest="executed_steps", type=int,
                        default=None, metavar="K",
                        help="rows of each chunk executed per forward pass when served, stored in config.json "
                             f"(default {EXECUTED_STEPS_DEFAULT}, a queue of that many rows, or the whole chunk when it is "
                             f"shorter: {EXECUTION_DEFAULT_WHY}; 1: re-plan every step)".replace("%", "%%"))
    parser.add_argument("--temporal-ensemble", type=float, default=None, metavar="M",
                        help="serve with ACT's temporal ensembling instead: a forward pass every step, each step's "
                             "action the exp(-M * i)-weighted mean of every chunk's row for it (ACT: M = 0.01); "
                             "stored in config.json, executed steps 1")
    parser.add_argument("--shift-px", type=int, default=None,
                        help="random-shift augmentation, pixels (default 4 with --vision cnn, 0 with resnet18)")
    parser.add_argument("--vision", choices=VISIONS, default="cnn",
                        help="camera encoder: cnn (strided convs, flattened) or resnet18 (Diffusion Policy's: "
                             "GroupNorm, spatial softmax)")
    parser.add_argument("--vision-width", type=int, default=64, help="resnet18: channels of its first stage")
    parser.add_argument("--crop-ratio", type=float, default=None,
                        help="random-crop augmentation: the encoder sees this fraction of each side, a random "
                             "crop in training, the centre when served (default 1.0, no crop, with --vision cnn; "
                             "0.9 with resnet18, as LeRobot's diffusion policy)")
    parser.add_argument("--head", choices=HEADS, default="l1",
                        help="action head: l1 (regression, the control), flow (flow matching over the chunk) or "
                             "act (ACT's CVAE transformer, the --act-... sizes)")
    for name, what in ACT_OPTIONS.items():
        default = getattr(BaselineConfig, name)
        parser.add_argument(f"--{name.replace('_', '-')}", type=type(default), default=default,
                            help=f"act head: {what} (default {default})")
    parser.add_argument("--flow-steps", type=int, default=10, help="flow head: Euler steps when served (1..100)")
    parser.add_argument("--flow-width", type=int, default=256, help="flow head: channels of its temporal convs")
    parser.add_argument("--episodes", type=int, default=None, help="use only the first N episodes")
    parser.add_argument("--val-episodes", type=int, default=0, help="hold out the last K episodes and report their L1")
    parser.add_argument("--time-budget-s", type=float, default=None,
                        help="stop after this many seconds (loading included) and save the checkpoint")
    parser.add_argument("--log-every", type=int, default=100)
    parser.add_argument("--save-every", type=int, default=2000)
    parser.add_argument("--threads", type=int, default=None, help="torch CPU threads")
    parser.add_argument("--no-compile", action="store_true",
                        help="on CUDA, train eagerly instead of torch.compile + one CUDA graph per step (for comparison)")
    args = parser.parse_args(argv)
    if args.temporal_ensemble is not None and args.executed_steps not in (None, 1):
        parser.error(f"--temporal-ensemble runs a forward pass every step: --executed-steps {args.executed_steps} "
                     f"must be 1 or left out")
    if args.executed_steps is None:
        args.executed_steps = 1 if args.temporal_ensemble is not None else min(EXECUTED_STEPS_DEFAULT, args.chunk_size)
    if args.shift_px is None:
        args.shift_px = 4 if args.vision == "cnn" else 0
    if args.crop_ratio is None:
        args.crop_ratio = 1.0 if args.vision == "cnn" else 0.9
    if not 0 < args.crop_ratio <= 1:
        parser.error(f"--crop-ratio must be in (0, 1], got {args.crop_ratio}")
    if args.vision_width < 4:
        parser.error(f"--vision-width must be >= 4, got {args.vision_width}")
    if args.head == "act" and args.vision != "cnn":
        parser.error(f"--head act attends to the cnn's feature maps; --vision {args.vision} is not offered with it")
    for name in ("steps", "batch_size", "history_frames", "history_stride", "chunk_size", "executed_steps", "log_every", "save_every"):
        if getattr(args, name) < 1:
            parser.error(f"--{name.replace('_', '-')} must be >= 1, got {getattr(args, name)}")
    if args.time_budget_s is not None and args.time_budget_s <= 0:
        parser.error(f"--time-budget-s must be > 0, got {args.time_budget_s}")
    if args.executed_steps > args.chunk_size:
        parser.error(f"--executed-steps {args.executed_steps} exceeds --chunk-size {args.chunk_size}")
    if args.val_episodes < 0:
        parser.error(f"--val-episodes must be >= 0, got {args.val_episodes}")
    try:  # the head's sizes and the chunk execution, before anything is loaded or written
        BaselineConfig(chunk_size=args.chunk_size, executed_steps=args.executed_steps, head=args.head,
                       temporal_ensemble=args.temporal_ensemble, **act_sizes(args))
    except ValueError as error:
        parser.error(str(error))
    return args


def act_sizes(args):
    """The ACT head's sizes given on the command line (config.ACT_OPTIONS), as BaselineConfig fields."""
    return {name: getattr(args, name) for name in ACT_OPTIONS}


def build_policy(data, args):
    state_dim, action_dim = data.state.shape[1], data.action.shape[1]
    task, robot = recorded_task_and_robot(data.root, data.info)
    config = BaselineConfig(camera=args.camera, image_size=list(data.image_size), state_dim=state_dim,
                            action_dim=action_dim, history_frames=args.history_frames,
                            history_stride=args.history_stride, chunk_size=args.chunk_size,
                            executed_steps=args.executed_steps, shift_px=args.shift_px, head=args.head,
                            flow_steps=args.flow_steps, flow_width=args.flow_width, noise_seed=args.seed,
                            temporal_ensemble=args.temporal_ensemble, **act_sizes(args),
                            vision=args.vision, vision_width=args.vision_width, crop_ratio=args.crop_ratio,
                            task=task, robot=robot)
    quaternions = QUATERNION_ACTION_DIMS if action_dim == 19 else ()
    state_mean, state_std = mean_std(data.stats, STATE, state_dim, config.min_std, where=data.stats_path)
    action_mean, action_std = mean_std(data.stats, ACTION, action_dim, config.min_std, quaternions, where=data.stats_path)
    return BaselinePolicy(config, state_mean, state_std, action_mean, action_std)


def learning_rate(step, args):
    if step < args.warmup_steps:
        return args.lr * (step + 1) / args.warmup_steps
    progress = (step - args.warmup_steps) / max(1, args.steps - args.warmup_steps)
    return args.lr * (0.1 + 0.9 * 0.5 * (1 + math.cos(math.pi * min(1.0, progress))))


@torch.no_grad()
def validation_loss(policy, data, rows, device, batch_size):
    policy.eval()
    total, count = 0.0, 0
    for start in range(0, len(rows), batch_size):
        chunk = rows[start:start + batch_size]
        with autocast(device):
            total += float(batch_loss(policy, data, chunk, None, augment=False)) * len(chunk)
        count += len(chunk)
    policy.train()
    return total / max(count, 1)


def train(args):
    started = time.monotonic()
    deadline = started + args.time_budget_s if args.time_budget_s else None
    device = torch.device(args.device)
    if device.type == "cuda" and not torch.cuda.is_available():
        raise ValueError(f"--device {args.device}: this PyTorch sees no CUDA device")
    if args.threads:
        torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    np.random.seed(args.seed)
    train_output.prepare(args.out, args.overwrite)

    keys = BaselineConfig(camera=args.camera, state_dim=34).image_keys
    episodes = range(args.episodes) if args.episodes else None
    data = DemoDataset(args.dataset, keys, image_size=args.image_size, episodes=episodes)
    episodes_loaded = data.episodes
    if args.val_episodes >= len(episodes_loaded):
        raise ValueError(f"--val-episodes {args.val_episodes} leaves no training episode of {len(episodes_loaded)}")
    val_set = set(episodes_loaded[len(episodes_loaded) - args.val_episodes:].tolist()) if args.val_episodes else set()
    is_val = np.isin(data.row_episode, list(val_set))
    train_rows = torch.from_numpy(np.flatnonzero(~is_val))
    val_rows = torch.from_numpy(np.flatnonzero(is_val))
    load_s = time.monotonic() - started
    print(f"loaded {len(episodes_loaded)} episodes, {len(data)} frames ({len(train_rows)} train, {len(val_rows)} validation), "
          f"{len(keys)} cameras at {data.image_size[1]}x{data.image_size[0]} in {load_s:.1f} s", flush=True)
    data.to(device)
    Path(args.out).mkdir(parents=True, exist_ok=True)

    policy = build_policy(data, args).to(device).train()
    parameters = sum(p.numel() for p in policy.parameters())
    print(f"policy: {parameters / 1e6:.2f} M parameters, camera {args.camera}, vision {args.vision} on "
          f"{policy.config.crop_size[1]}x{policy.config.crop_size[0]}, history {policy.config.obs_offsets} frames, "
          f"chunk {policy.config.chunk_size} (served: {policy.config.chunk_execution}), device {device}, trained for "
          f"task {policy.config.task or '(not declared)'} on robot {policy.config.robot or '(not declared)'}", flush=True)
    generator = torch.Generator().manual_seed(args.seed)
    lr_at = lambda step: learning_rate(step, args)  # noqa: E731
    if can_compile(device) and not args.no_compile:
        print("compiling the model and capturing the training step as one CUDA graph ...", flush=True)
        stepper = GraphedStep(policy, data, train_rows, args.batch_size, lr_at, args.weight_decay, args.seed, device)
        print(f"ready in {stepper.prepare_s:.1f} s", flush=True)
    else:
        stepper = EagerStep(policy, data, train_rows, args.batch_size, lr_at, args.weight_decay, generator, device)
    log = train_output.TrainLog(args.out)  # train_log.jsonl.tmp until the first save
    summary = {"dataset": str(args.dataset), "seed": args.seed, "steps_requested": args.steps, "parameters": parameters,
               "frames": len(data), "episodes": len(episodes_loaded), "validation_episodes": sorted(val_set),
               "load_s": round(load_s, 2), "device": str(device), "batch_size": args.batch_size,
               "step_mode": stepper.mode, "prepare_s": round(stepper.prepare_s, 2)}

    def save(step, loss, stopped):
        loop_s = time.monotonic() - loop_start
        extra = dict(summary, steps_done=step, last_loss=None if math.isnan(loss) else loss, stopped=stopped,
                     wall_s=round(time.monotonic() - started, 2), steps_per_s=round(step / max(loop_s, 1e-9), 3),
                     samples_per_s=round(step * args.batch_size / max(loop_s, 1e-9), 1))
        if len(val_rows):
            extra["validation_l1"] = validation_loss(policy, data, val_rows.to(device), device, args.batch_size)
        checkpoint.save(policy, args.out, extra, staged=log.staged())
        log.saved()
        return extra

    loop_start = time.monotonic()
    window_start, window_steps = loop_start, 0
    step, loss_value, stopped = 0, float("nan"), "steps"
    while step < args.steps:
        if deadline is not None and time.monotonic() >= deadline:
            stopped = "time_budget"
            break
        stepper.run(step)
        step += 1
        window_steps += 1
        if step % args.log_every == 0 or step == args.steps:
            loss_value = stepper.window_loss()  # waits for the GPU: the rate below is of finished steps
            now = time.monotonic()
            rate = window_steps / max(now - window_start, 1e-9)
            eta = (args.steps - step) / rate
            if deadline is not None:
                eta = min(eta, max(0.0, deadline - now))
            print(f"step {step}/{args.steps} loss {loss_value:.4f} {rate:.1f} steps/s ({rate * args.batch_size:.0f} "
                  f"samples/s) ETA {eta:.0f} s", flush=True)
            log.write({"step": step, "loss": loss_value, "steps_per_s": rate, "samples_per_s": rate * args.batch_size,
                       "lr": learning_rate(step - 1, args)})
            window_start, window_steps = now, 0
        if step % args.save_every == 0 and step < args.steps:
            save(step, loss_value, "running")
    if window_steps:
        loss_value = stepper.window_loss()
    extra = save(step, loss_value, stopped)
    log.close()
    rate = extra["steps_per_s"]
    validation = f", validation L1 {extra['validation_l1']:.4f}" if "validation_l1" in extra else ""
    if step == 0:
        print("no training step ran: --time-budget-s ran out while loading", file=sys.stderr)
    print(f"saved {args.out} after {step} steps ({stopped}; {stepper.mode}, {rate:.1f} steps/s = {extra['samples_per_s']:.0f} samples/s, "
          f"{extra['wall_s']:.0f} s in all), "
          f"last loss {loss_value:.4f}{validation}", flush=True)
    return extra


def main(argv=None):
    args = arguments(argv)
    try:
        train(args)
    except (ValueError, OSError) as error:
        print(f"tavis_baseline.train: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
