"""A Python rollout of the scripted expert writes the episodes.jsonl that `tavis eval` writes for
the same cell, compared with the real program's output."""

import json
import os
import subprocess

import tavis
from conftest import TASK

EPISODES = 16
SEED = 7
# Differ by design: timing, the thread count, the env slots, and the control ticks (the Python
# loop keeps refilling slots after the 16th episode has started).
RUN_DEPENDENT = {"wall_s", "threads", "control_ticks", "control_ticks_per_s", "envs", "render"}


def run_cli(out):
    subprocess.run([os.environ["TAVIS_CLI"], "eval", "--task", TASK, "--episodes", str(EPISODES), "--envs", "4",
                    "--seed", str(SEED), "--threads", "2", "--quiet", "--out", str(out)], check=True,
                    stdout=subprocess.DEVNULL)


def run_python(out):
    env = tavis.make_vec(TASK, num_envs=3, seed=SEED, cameras=[], control_ticks_per_step=1, threads=2)
    expert = env.make_policy("expert")
    env.reset(seed=0)
    while sum(record["episode"] < EPISODES for record in env.episode_records()) < EPISODES:
        env.step(expert())
    env.write_results(out, "expert", EPISODES)
    return env


def test_expert_rollout_reproduces_tavis_eval(tmp_path):
    run_cli(tmp_path / "cli")
    env = run_python(tmp_path / "python")
    cli = (tmp_path / "cli" / "episodes.jsonl").read_text()
    python = (tmp_path / "python" / "episodes.jsonl").read_text()
    assert len(cli.splitlines()) == EPISODES
    assert python == cli
    assert [json.dumps(record) for record in env.episode_records()[:EPISODES]] == \
        [json.dumps(json.loads(line)) for line in cli.splitlines()]
    summary_cli = json.loads((tmp_path / "cli" / "summary.json").read_text())
    summary_python = json.loads((tmp_path / "python" / "summary.json").read_text())
    assert summary_cli.keys() == summary_python.keys()
    for key in summary_cli.keys() - RUN_DEPENDENT:
        assert summary_python[key] == summary_cli[key], key
    assert summary_python["n_successful"] > 0
