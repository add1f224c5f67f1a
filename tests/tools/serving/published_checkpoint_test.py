"""Issue 51, acceptance 4: the published reference checkpoint reproduces its published cell. The
bf16 checkpoint in docs/baselines/checkpoints/ is served on the CPU (`tavis_baseline.serve`, Debian's
torch) and a 16-episode slice of its published cell (the same task, robot, camera, split and seed,
episodes 0-15) is run with nothing but the server's declared contract; the slice's 95 % Wilson
interval must hold the published cell's success rate. A checkpoint that is not the published one
must fail the same check: another task's is not published yet, so the negative case serves the
same checkpoint with its weights re-initialised (a policy that has learned nothing), which a check
that could not fail would pass.

    /usr/bin/python3 published_checkpoint_test.py TAVIS_BINARY SOURCE_DIR
"""

import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from tool_script_support import check, failures, passed_count  # noqa: E402

TAVIS, SOURCE = sys.argv[1], sys.argv[2]
CHECKPOINT = os.path.join(SOURCE, "docs", "baselines", "checkpoints", "conditional-pick_gr1t2_head_flow_seed0")
PUBLISHED_CELL = os.path.join(SOURCE, "docs", "baselines", "cells", "2026-12-02-flow", "exec10", "cp_head_0_id")
SLICE = 16


def wilson(successes, n, z=1.96):
    centre = (successes + z * z / 2) / (n + z * z)
    half = z * math.sqrt(successes * (n - successes) / n + z * z / 4) / (n + z * z)
    return centre - half, centre + half


def serve(checkpoint):
    environment = dict(os.environ, OMP_NUM_THREADS="2",
                       PYTHONPATH=os.pathsep.join(os.path.join(SOURCE, "tools", p) for p in ("baseline", "policy_server")))
    process = subprocess.Popen(["/usr/bin/python3", "-m", "tavis_baseline.serve", checkpoint, "--port", "0",
                                "--device", "cpu", "--executed-steps", "10"],
                               env=environment, stdout=subprocess.PIPE, text=True)
    line = process.stdout.readline()
    if not line.startswith("tavis_server: serving "):
        process.kill()
        sys.exit(f"tavis_baseline.serve did not start: {line!r}")
    return process, line.split(" on ")[1].strip()


def slice_successes(checkpoint, published, out):
    """Runs the published cell's first SLICE episodes against `checkpoint`; its success count."""
    server, url = serve(checkpoint)
    try:
        result = subprocess.run([TAVIS, "eval", "--task", published["task"], "--robot", published["robot"],
                                 "--camera", published["camera"], "--split", published["split"],
                                 "--seed", str(published["seed"]), "--episodes", str(SLICE), "--envs", str(SLICE),
                                 "--threads", "2", "--policy", "openpi", "--server", url, "--serving", "batched",
                                 "--quiet", "--out", out], capture_output=True, text=True, timeout=900)
    finally:
        server.kill()
        server.wait()
    if result.returncode != 0:
        sys.exit(f"tavis eval exited {result.returncode}:\n{result.stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)["n_successful"]


def reinitialised_copy(work):
    """The checkpoint folder with every weight redrawn (same shapes, same config): not the policy."""
    sys.path[:0] = [os.path.join(SOURCE, "tools", "baseline"), os.path.join(SOURCE, "tools", "policy_server")]
    import torch  # noqa: E402  (Debian's python3-torch; only this case needs it in-process)

    copy = os.path.join(work, "reinitialised")
    shutil.copytree(CHECKPOINT, copy)
    state = torch.load(os.path.join(copy, "model.pt"), map_location="cpu")
    generator = torch.Generator().manual_seed(0)
    redrawn = {k: (torch.randn(v.shape, generator=generator).to(v.dtype) * 0.05 if v.is_floating_point() else v)
               for k, v in state.items()}
    torch.save(redrawn, os.path.join(copy, "model.pt"))
    return copy


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
    print(f"{passed_count()} checks passed, {len(failures)} failed")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
