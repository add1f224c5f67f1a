"""Issue 51, acceptance 4: the published reference checkpoint reproduces its published cell. The
bf16 checkpoint in docs/baselines/checkpoints/ is served on the CPU (`tavis_baseline.serve`, Debian's
torch) and a 16-episode slice of its published cell (the same task, robot, camera, split and seed,
episodes 0-15) is run with nothing but the server's declared contract; the slice's 95 % Wilson
interval must hold the published cell's success rate. A checkpoint that is not the published one
must not pass: the same checkpoint with its weights re-initialised (a policy that has learned
nothing) must fail the same check, and another task's checkpoint (a tiny wait-then-act one trained
here on the CPU from a 4-episode `tavis demos` recording, tests/tools/baseline/tiny_training.py)
served to the published cell's command must be refused before episode 1, naming both tasks, since
its contract declares the task it was trained for (docs/serving.md).

    /usr/bin/python3 published_checkpoint_test.py TAVIS_BINARY SOURCE_DIR
"""

import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

TESTS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [TESTS, os.path.join(TESTS, "baseline")]
from tool_script_support import check, failures, passed_count  # noqa: E402

TAVIS, SOURCE = sys.argv[1], sys.argv[2]
PACKAGES = [os.path.join(SOURCE, "tools", "baseline"), os.path.join(SOURCE, "tools", "policy_server")]
sys.path[:0] = PACKAGES  # the negative cases train and load checkpoints in-process
CHECKPOINT = os.path.join(SOURCE, "docs", "baselines", "checkpoints", "conditional-pick_gr1t2_head_flow_seed0")
PUBLISHED_CELL = os.path.join(SOURCE, "docs", "baselines", "cells", "2026-12-02-flow", "exec10", "cp_head_0_id")
SLICE = 16


def wilson(successes, n, z=1.96):
    centre = (successes + z * z / 2) / (n + z * z)
    half = z * math.sqrt(successes * (n - successes) / n + z * z / 4) / (n + z * z)
    return centre - half, centre + half


def serve(checkpoint, *args):
    environment = dict(os.environ, OMP_NUM_THREADS="2", PYTHONPATH=os.pathsep.join(PACKAGES))
    process = subprocess.Popen(["/usr/bin/python3", "-m", "tavis_baseline.serve", checkpoint, "--port", "0",
                                "--device", "cpu", *args],
                               env=environment, stdout=subprocess.PIPE, text=True)
    line = process.stdout.readline()
    if not line.startswith("tavis_server: serving "):
        process.kill()
        sys.exit(f"tavis_baseline.serve did not start: {line!r}")
    return process, line.split(" on ")[1].strip()


def evaluate_slice(checkpoint, published, out, *serve_args):
    """The published cell's command, its first SLICE episodes, against `checkpoint` served with
    `serve_args`; the finished `tavis eval`."""
    server, url = serve(checkpoint, *serve_args)
    try:
        return subprocess.run([TAVIS, "eval", "--task", published["task"], "--robot", published["robot"],
                               "--camera", published["camera"], "--split", published["split"],
                               "--seed", str(published["seed"]), "--episodes", str(SLICE), "--envs", str(SLICE),
                               "--threads", "2", "--policy", "openpi", "--server", url, "--serving", "batched",
                               "--quiet", "--out", out], capture_output=True, text=True, timeout=900)
    finally:
        server.kill()
        server.wait()


def slice_successes(checkpoint, published, out):
    """Runs the published cell's first SLICE episodes against `checkpoint` served with its queue of 10
    rows (as the published cell was); its success count."""
    result = evaluate_slice(checkpoint, published, out, "--executed-steps", "10")
    if result.returncode != 0:
        sys.exit(f"tavis eval exited {result.returncode}:\n{result.stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)["n_successful"]


def reinitialised_copy(work):
    """The checkpoint folder with every weight redrawn (same shapes, same config): not the policy."""
    import torch  # noqa: E402  (Debian's python3-torch; only the negative cases need it in-process)

    copy = os.path.join(work, "reinitialised")
    shutil.copytree(CHECKPOINT, copy)
    state = torch.load(os.path.join(copy, "model.pt"), map_location="cpu")
    generator = torch.Generator().manual_seed(0)
    redrawn = {k: (torch.randn(v.shape, generator=generator).to(v.dtype) * 0.05 if v.is_floating_point() else v)
               for k, v in state.items()}
    torch.save(redrawn, os.path.join(copy, "model.pt"))
    return copy


def other_tasks_checkpoint(work, task):
    """A tiny checkpoint of `task` on the published robot, trained here on the CPU in seconds from a
    4-episode `tavis demos` recording: its config.json says the task it was trained for."""
    os.environ["TAVIS_CLI"] = TAVIS  # for tiny_training's run_tavis
    from tavis_baseline import train  # noqa: E402
    from tiny_training import TINY, record_demos  # noqa: E402

    dataset = record_demos(os.path.join(work, task + "_demos"), task=task, robot="gr1t2")
    out = os.path.join(work, task + "_checkpoint")
    if train.main(["--dataset", str(dataset), "--out", out, *TINY]) != 0:
        sys.exit(f"training the {task} checkpoint failed")
    return out


def main():
    with open(os.path.join(PUBLISHED_CELL, "summary.json")) as f:
        published = json.load(f)
    rate = published["n_successful"] / published["n_episodes"]
    with tempfile.TemporaryDirectory() as work:
        successes = slice_successes(CHECKPOINT, published, os.path.join(work, "published"))
        low, high = wilson(successes, SLICE)
        print(f"published checkpoint: {successes}/{SLICE} [{100 * low:.1f}, {100 * high:.1f}] against the published "
              f"{published['n_successful']}/{published['n_episodes']} = {100 * rate:.1f} %")
        check(low <= rate <= high, f"the published checkpoint's slice {successes}/{SLICE} [{low:.3f}, {high:.3f}] "
                                   f"does not hold the published rate {rate:.3f}")

        other = slice_successes(reinitialised_copy(work), published, os.path.join(work, "other"))
        low, high = wilson(other, SLICE)
        print(f"re-initialised checkpoint: {other}/{SLICE} [{100 * low:.1f}, {100 * high:.1f}]")
        check(not (low <= rate <= high), f"a checkpoint that is not the published one passed: {other}/{SLICE} "
                                         f"[{low:.3f}, {high:.3f}] holds {rate:.3f}")

        other_task = "wait-then-act"
        out = os.path.join(work, "swapped")
        result = evaluate_slice(other_tasks_checkpoint(work, other_task), published, out)
        refusal = result.stderr.strip()
        print(f"{other_task} checkpoint: exit {result.returncode}: {refusal}")
        named = f"was trained for task {other_task}; this cell is {published['task']}"
        check(result.returncode != 0 and named in refusal,
              f"another task's checkpoint must be refused naming both tasks ({named!r}): exit {result.returncode}: "
              f"{refusal}")
        check(not os.path.exists(os.path.join(out, "episodes.jsonl")) and not os.path.exists(out),
              f"another task's checkpoint is refused before episode 1: {out} was written")
    print(f"{passed_count()} checks passed, {len(failures)} failed")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
