"""A Python rollout of the scripted expert writes the episodes.jsonl that `tavis eval` writes for
the same cell, compared with the real program's output."""

import json
import os
import subprocess

import tavis
from conftest import TASK

EPISODES = 16
SEED = 7
# Differ by design: timing, the thread count, the env slots, the control ticks (the Python
# loop keeps refilling slots after the 16th episode has started) and the provenance (machine, times).
RUN_DEPENDENT = {"wall_s", "threads", "control_ticks", "control_ticks_per_s", "envs", "render", "provenance"}


def run_cli(out):
    subprocess.run([os.environ["TAVIS_CLI"], "eval", "--task", TASK, "--episodes", str(EPISODES), "--envs", "4",
                    "--seed", str(SEED), "--threads", "2", "--quiet", "--out", str(out)], check=True,
                    stdout=subprocess.DEVNULL)


def run_python(out, episodes=EPISODES, num_envs=3, seed=SEED, **options):
    env = tavis.make_vec(TASK, num_envs=num_envs, seed=seed, cameras=[], control_ticks_per_step=1, threads=2,
                         **options)
    expert = env.make_policy("expert")
    env.reset(seed=0)
    while sum(record["episode"] < episodes for record in env.episode_records()) < episodes:
        env.step(expert())
    env.write_results(out, "expert", episodes)
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


def test_an_episode_the_expert_gives_up_ends_as_tavis_eval_ends_it(tmp_path):
    # Episode 75 of this cell is one the expert gives up on, well before the 20 s time-out.
    cell = ["--task", "clutter-pick-cube", "--robot", "reachy2", "--split", "ood-init-pose"]
    subprocess.run([os.environ["TAVIS_CLI"], "eval", *cell, "--episode", "75", "--threads", "2", "--quiet",
                    "--out", str(tmp_path / "cli")], check=True, stdout=subprocess.DEVNULL)
    cli = [json.loads(line) for line in (tmp_path / "cli" / "episodes.jsonl").read_text().splitlines()]
    assert len(cli) == 1 and cli[0]["episode"] == 75
    assert cli[0]["end"] == "gave_up" and not cli[0]["success"]
    assert cli[0]["length_control_ticks"] < 1200

    env = tavis.make_vec("clutter-pick-cube", robot="reachy2", split="ood-init-pose", cameras=[],
                         control_ticks_per_step=1, autoreset=False, threads=2)
    expert = env.make_policy("expert")
    env.reset(seed=75)
    for _ in range(env.call("_max_episode_steps")[0]):
        _, _, terminated, truncated, infos = env.step(expert())
        if terminated[0] or truncated[0]:
            break
    assert terminated[0] and not truncated[0]
    assert infos["final_info"]["end"][0] == "gave_up"
    assert json.dumps(env.episode_records()[0]) == json.dumps(cli[0])


def test_a_fixed_camera_ood_init_pose_rollout_reproduces_tavis_eval(tmp_path):
    # The camera protocol's rule (neck actions and state zeroed) and the ood-init-pose warm-up in
    # each reset, on the Python env's loop and on tavis eval's.
    subprocess.run([os.environ["TAVIS_CLI"], "eval", "--task", TASK, "--split", "ood-init-pose", "--camera", "fixed",
                    "--episodes", "4", "--envs", "2", "--seed", "3", "--threads", "2", "--quiet", "--out",
                    str(tmp_path / "cli")], check=True, stdout=subprocess.DEVNULL)
    run_python(tmp_path / "python", episodes=4, num_envs=2, seed=3, split="ood-init-pose", camera="fixed")
    cli = (tmp_path / "cli" / "episodes.jsonl").read_text()
    assert len(cli.splitlines()) == 4
    assert (tmp_path / "python" / "episodes.jsonl").read_text() == cli
