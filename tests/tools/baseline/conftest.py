"""Fixtures of the baseline's tests: one small dataset made by `tavis demos` (4 episodes of
clutter-pick-cube on GR1T2 at 96x72 and 20 fps; at 64x48 H.264 alone costs the head camera about 30 dB), shared by the whole session, and a way to run the
tavis program. ctest passes TAVIS_CLI (the program) and TAVIS_JS_DIR (the npm Parquet readers)."""

import json
import os
import subprocess

import pytest

SEED = 3
EPISODES = 4
WIDTH, HEIGHT = 96, 72
FPS = 20
CONTROL_HZ = 60


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


@pytest.fixture(scope="session")
def demo_dataset(tmp_path_factory):
    out = tmp_path_factory.mktemp("demos") / "dataset"
    run_tavis("demos", "--task", "clutter-pick-cube", "--robot", "gr1t2", "--episodes", str(EPISODES), "--fps", str(FPS),
              "--image-size", f"{WIDTH}x{HEIGHT}", "--seed", str(SEED), "--threads", "2", "--quiet", "--out", str(out))
    report = json.loads((out / "tavis_demos.json").read_text())
    # Dataset episode i is scene episode i of the seed only if no attempt failed (failures are skipped).
    assert report["tasks"][0]["attempts"] == EPISODES, report
    return out
