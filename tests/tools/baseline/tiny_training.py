"""How the baseline's tests make a dataset and a checkpoint on the CPU in seconds: a `tavis demos`
recording of a few episodes at a small image size (at 64x48 H.264 alone costs the head camera about
30 dB, hence 96x72), and the training options of a tiny checkpoint. conftest.py's shared dataset
and the published checkpoint's test (tests/tools/serving/published_checkpoint_test.py, which
trains another task's checkpoint) both make theirs so. The tavis program is the one TAVIS_CLI names
(ctest sets it)."""

import json
import os
import subprocess
from pathlib import Path

SEED = 3
EPISODES = 4
WIDTH, HEIGHT = 96, 72
FPS = 20
CONTROL_HZ = 60
# A checkpoint trained in two steps of batch 8 on 32x24 images: it serves, it has not learned.
TINY = ["--batch-size", "8", "--image-size", "32x24", "--threads", "2", "--warmup-steps", "1", "--chunk-size", "8",
        "--history-stride", "2", "--steps", "2"]


def tavis_cli():
    path = os.environ.get("TAVIS_CLI")
    if not path or not os.path.exists(path):
        raise RuntimeError("TAVIS_CLI must name the built tavis program (ctest sets it)")
    return path


def run_tavis(*args):
    result = subprocess.run([tavis_cli(), *args], capture_output=True, text=True, timeout=300)
    if result.returncode != 0:
        raise RuntimeError(f"tavis {' '.join(args)} failed ({result.returncode}):\n{result.stderr[-2000:]}")
    return result.stdout


def record_demos(out, task="clutter-pick-cube", robot="gr1t2"):
    """`tavis demos` of EPISODES episodes of `task` on `robot` into `out`; the dataset's folder.
    Dataset episode i is scene episode i of SEED: an attempt that failed (which would be skipped)
    is an error."""
    out = Path(out)
    run_tavis("demos", "--task", task, "--robot", robot, "--episodes", str(EPISODES), "--fps", str(FPS),
              "--image-size", f"{WIDTH}x{HEIGHT}", "--seed", str(SEED), "--threads", "2", "--quiet", "--out", str(out))
    report = json.loads((out / "tavis_demos.json").read_text())
    if report["tasks"][0]["attempts"] != EPISODES:
        raise RuntimeError(f"{task}: an attempt of the first {EPISODES} failed: {report}")
    return out
