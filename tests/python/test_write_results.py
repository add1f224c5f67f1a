"""write_results writes a folder under the rules of `tavis eval`'s: never into a folder another
process is writing (a running `tavis eval` holds its lock), never over results unless
overwrite=True, and an overwrite replaces only a cell tavis wrote."""

import json
import os
import subprocess
import time

import pytest

from conftest import TASK, hold_actions, make_small

# Enough episodes, one slot on one thread, that the program is still writing the cell when
# write_results tries the folder.
CLI_EPISODES = 48


@pytest.fixture(scope="module")
def ended_env():
    """An env with episodes 0..2 ended (the hold policy times them out)."""
    env = make_small(num_envs=3, cameras=[], control_ticks_per_step=3)
    env.reset(seed=0)
    while len(env.episode_records()) < 3:
        env.step(hold_actions(env))
    return env


def records(folder):
    return (folder / "episodes.jsonl").read_text().splitlines()


def wait_for_first_record(process, folder, timeout_s=120):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if (folder / "episodes.jsonl").exists() and records(folder):
            return
        assert process.poll() is None, "tavis eval ended before its first record"
        time.sleep(0.05)
    raise AssertionError("tavis eval wrote no record in time")


def test_a_folder_a_running_tavis_eval_writes_is_refused_and_keeps_its_records(ended_env, tmp_path):
    out = tmp_path / "cell"
    process = subprocess.Popen(
        [os.environ["TAVIS_CLI"], "eval", "--task", TASK, "--episodes", str(CLI_EPISODES), "--envs", "1",
         "--threads", "1", "--quiet", "--out", str(out)], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        wait_for_first_record(process, out)
        refused = f"^{out} is being written by tavis eval .*pid {process.pid}"
        with pytest.raises(ValueError, match=refused):
            ended_env.write_results(out, "hold", 1)
        with pytest.raises(ValueError, match=refused):  # overwrite does not take a folder being written
            ended_env.write_results(out, "hold", 1, overwrite=True)
        assert process.poll() is None, "the refusal must come while tavis eval still runs"
        _, stderr = process.communicate(timeout=600)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert process.returncode == 0, stderr.decode()
    lines = records(out)
    assert len(lines) == CLI_EPISODES
    assert [json.loads(line)["episode"] for line in lines] == list(range(CLI_EPISODES))
    assert json.loads((out / "summary.json").read_text())["n_episodes"] == CLI_EPISODES


def test_a_second_write_raises_unless_overwrite(ended_env, tmp_path):
    out = tmp_path / "cell"
    ended_env.write_results(out, "hold", 2)
    first = records(out)
    assert len(first) == 2
    with pytest.raises(ValueError, match=f"^out_dir {out} already holds results; give overwrite=True"):
        ended_env.write_results(out, "hold", 1, first_episode=2)
    assert records(out) == first
    ended_env.write_results(out, "hold", 1, first_episode=2, overwrite=True)
    assert [json.loads(line)["episode"] for line in records(out)] == [2]
    assert json.loads((out / "summary.json").read_text())["n_episodes"] == 1
    # The new cell was built beside the old one and swapped in: nothing is left beside it.
    assert sorted(path.name for path in tmp_path.iterdir()) == ["cell"]


def test_a_cell_of_tavis_eval_is_refused_and_replaced_only_with_overwrite(ended_env, tmp_path):
    out = tmp_path / "cell"
    subprocess.run([os.environ["TAVIS_CLI"], "eval", "--task", TASK, "--episodes", "2", "--quiet", "--out", str(out)],
                   check=True, stdout=subprocess.DEVNULL)
    cli = records(out)
    with pytest.raises(ValueError, match="already holds results"):
        ended_env.write_results(out, "hold", 1)
    assert records(out) == cli
    ended_env.write_results(out, "hold", 1, overwrite=True)
    assert not (out / "cell.json").exists()  # the old cell went as a whole
    assert [json.loads(line)["episode"] for line in records(out)] == [0]
    assert json.loads((out / "summary.json").read_text())["policy"] == "hold"


def test_overwrite_never_replaces_a_users_files(ended_env, tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    with pytest.raises(ValueError, match=f"^{out} holds files that are not a tavis evaluation cell's: notes.txt"):
        ended_env.write_results(out, "hold", 1, overwrite=True)
    with pytest.raises(ValueError, match="already holds results"):
        ended_env.write_results(out, "hold", 1)
    assert sorted(path.name for path in out.iterdir() if path.name != ".tavis_lock") == ["notes.txt"]
    assert (out / "notes.txt").read_text() == "mine"


def test_an_unusable_path_or_overwrite_of_another_type_is_refused(ended_env, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match="out_dir . is the working directory"):
        ended_env.write_results(".", "hold", 1)
    (tmp_path / "file").write_text("x")
    with pytest.raises(ValueError, match="out_dir file is a file, not a folder"):
        ended_env.write_results("file", "hold", 1)
    with pytest.raises(TypeError, match="^overwrite must be a bool, got str 'yes'$"):
        ended_env.write_results(tmp_path / "cell", "hold", 1, overwrite="yes")
    assert not (tmp_path / "cell").exists()
