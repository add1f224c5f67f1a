"""tavis_baseline.serve: a checkpoint is served with the chunk execution its config holds (a queue
of 10 rows by default, a queue of k rows, or re-planning every step), over the real websocket server, and the metadata it
sends (what `tavis eval` copies into summary.json) says which. Each reply is compared with the
policy's own forward pass over the same observation history, computed here."""

import asyncio
import collections
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import torch
import websockets

from conftest import run_tavis
from tiny_training import TINY
from tavis_baseline import checkpoint, train

REPO = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(REPO / "tests" / "batch" / "remote"))
# Where tavis_baseline and the tavis_server it serves through live.
PACKAGES = os.pathsep.join([str(REPO / "tools" / "baseline"), str(REPO / "tools" / "policy_server")])
from openpi_msgpack_numpy import packb, unpackb  # noqa: E402  (a msgpack-numpy we did not serve with)

HEIGHT, WIDTH = 24, 32
STEPS = 8


@pytest.fixture(scope="module")
def checkpoints(demo_dataset, tmp_path_factory):
    folder = tmp_path_factory.mktemp("served")
    made = {}
    for name, extra in (("default", []), ("queue4", ["--executed-steps", "4"]), ("replan", ["--executed-steps", "1"])):
        made[name] = folder / name
        assert train.main(["--dataset", str(demo_dataset), "--out", str(made[name]), *TINY, *extra]) == 0
    return made


class Server:
    """python3 -m tavis_baseline.serve CKPT --port 0 ARGS, waited for by its ready line."""

    def __init__(self, ckpt, *args):
        environment = dict(os.environ, PYTHONPATH=PACKAGES)
        self.process = subprocess.Popen([sys.executable, "-m", "tavis_baseline.serve", str(ckpt), "--port", "0", *args],
                                        env=environment, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = self.process.stdout.readline()
        if " on ws://" not in line:
            self.process.kill()
            raise AssertionError(f"no ready line: {line!r} {self.process.communicate()[1]}")
        self.url = line.split(" on ")[1].strip()

    def stop(self):
        self.process.terminate()
        _, stderr = self.process.communicate(timeout=30)
        return stderr


def observation(step, rng):
    request = {f"observation.images.{camera}": rng.integers(0, 256, (HEIGHT, WIDTH, 3), dtype=np.uint8)
               for camera in ("OBS_HEAD", "OBS_WRIST_LEFT", "OBS_WRIST_RIGHT")}
    request["observation.state"] = rng.standard_normal(34).astype(np.float32)
    request.update(prompt="pick the cube", task="pick the cube", env_index=0, episode_index=0, step=step,
                   is_first=step == 0)
    return request


async def ask_steps(url, requests):
    async with websockets.connect(url, compression=None, max_size=None) as websocket:
        metadata = unpackb(await websocket.recv())
        replies = []
        for request in requests:
            await websocket.send(packb(request))
            reply = await websocket.recv()
            assert not isinstance(reply, str), reply
            replies.append(np.asarray(unpackb(reply)["actions"]))
        return metadata, replies


def serve_steps(ckpt, *args):
    rng = np.random.default_rng(7)
    requests = [observation(step, rng) for step in range(STEPS)]
    server = Server(ckpt, *args)
    try:
        metadata, replies = asyncio.run(asyncio.wait_for(ask_steps(server.url, requests), 120))
    finally:
        stderr = server.stop()
    return requests, metadata, replies, stderr


def own_chunks(ckpt, requests):
    """The policy's chunk at each step, over the history tavis_server keeps (the first observation
    repeated before an episode's start), computed here without the server."""
    policy = checkpoint.load(ckpt)
    history = collections.deque(maxlen=policy.config.n_obs_steps)
    chunks = []
    for request in requests:
        arrays = {key: value for key, value in request.items() if isinstance(value, np.ndarray)}
        if not history:
            history.extend([arrays] * policy.config.n_obs_steps)
        else:
            history.append(arrays)
        batch = {}
        for key in arrays:
            stacked = torch.from_numpy(np.stack([entry[key] for entry in history]))[None]
            batch[key] = stacked.movedim(-1, -3).float() / 255 if key.startswith("observation.images.") else stacked
        config = policy.config
        config.n_action_steps = config.chunk_size  # every row, to look up the queued ones
        chunks.append(policy.predict_action_chunk(batch)[0].numpy())
    return chunks


def test_the_default_checkpoint_queues_its_whole_chunk_when_shorter_than_10_rows(checkpoints):
    # The default is a queue of 10 rows (config.EXECUTION_DEFAULT_WHY), cut to these tiny chunks' 8.
    assert json.loads((checkpoints["default"] / "config.json").read_text())["executed_steps"] == 8
    requests, metadata, replies, _ = serve_steps(checkpoints["default"])
    assert metadata["executed_steps"] == 8 and metadata["action_queue"] is True and metadata["n_action_steps"] == 8
    assert metadata["chunk_execution"].startswith("queue of 8 rows")
    chunks = own_chunks(checkpoints["default"], requests)
    for step, reply in enumerate(replies):
        np.testing.assert_allclose(reply[0], chunks[0][step], atol=1e-5, err_msg=f"step {step}")


def test_a_replanning_checkpoint_replans_every_step(checkpoints):
    assert json.loads((checkpoints["replan"] / "config.json").read_text())["executed_steps"] == 1
    requests, metadata, replies, _ = serve_steps(checkpoints["replan"])
    assert metadata["executed_steps"] == 1 and metadata["action_queue"] is False
    assert metadata["n_action_steps"] == 1 and metadata["action_horizon"] == 1
    assert metadata["chunk_execution"].startswith("re-plan every step")
    chunks = own_chunks(checkpoints["replan"], requests)
    # One forward pass per step asked: every reply is one row, the first of that step's own chunk.
    for step, reply in enumerate(replies):
        assert reply.shape == (1, 19)
        np.testing.assert_allclose(reply[0], chunks[step][0], atol=1e-5, err_msg=f"step {step}")
    # ... which a queued row would not be (the comparison tells the two apart).
    assert not np.allclose(replies[1][0], chunks[0][1], atol=1e-5)


@pytest.mark.parametrize("name,args", [("queue4", ()), ("default", ("--executed-steps", "4"))])
def test_a_queue_of_4_rows_runs_one_forward_pass_every_4_steps(checkpoints, name, args):
    requests, metadata, replies, _ = serve_steps(checkpoints[name], *args)
    assert metadata["executed_steps"] == 4 and metadata["action_queue"] is True and metadata["n_action_steps"] == 4
    assert metadata["chunk_execution"].startswith("queue of 4 rows")
    chunks = own_chunks(checkpoints[name], requests)
    for step, reply in enumerate(replies):
        planned = step - step % 4  # the step of the forward pass whose row this is
        np.testing.assert_allclose(reply[0], chunks[planned][step - planned], atol=1e-5, err_msg=f"step {step}")


def test_an_old_checkpoint_is_served_with_its_queue_as_before_and_says_so(checkpoints, tmp_path):
    old = tmp_path / "old"
    old.mkdir()
    for path in checkpoints["queue4"].iterdir():
        (old / path.name).write_bytes(path.read_bytes())
    config = json.loads((old / "config.json").read_text())
    config["n_action_steps"] = config.pop("executed_steps")  # as written before the setting
    del config["task"], config["robot"]  # ... and before the task and robot it was trained for
    (old / "config.json").write_text(json.dumps(config))
    _, metadata, _, stderr = serve_steps(old)
    assert metadata["executed_steps"] == 4 and metadata["action_queue"] is True and metadata["n_action_steps"] == 4
    assert not {"task", "robot"} & set(metadata["observation_contract"]), "an old checkpoint declares neither"
    assert "predates the executed_steps setting" in stderr and "n_action_steps 4 rows" in stderr


def test_bad_executed_steps_are_refused(checkpoints):
    environment = dict(os.environ, PYTHONPATH=PACKAGES)
    result = subprocess.run([sys.executable, "-m", "tavis_baseline.serve", str(checkpoints["default"]), "--port", "0",
                             "--executed-steps", "9"], env=environment, capture_output=True, text=True, timeout=60)
    assert result.returncode == 2 and "chunks of 8 rows" in result.stderr


def test_tavis_eval_records_how_the_chunks_ran(checkpoints, tmp_path):
    server = Server(checkpoints["replan"])
    try:
        run_tavis("eval", "--task", "clutter-pick-cube", "--robot", "gr1t2", "--seed", "3", "--episodes", "2",
                  "--envs", "2", "--policy", "openpi", "--server", server.url, "--replan-steps", "1",
                  "--image-size", f"{WIDTH}x{HEIGHT}", "--quiet", "--out", str(tmp_path / "cell"))
    finally:
        server.stop()
    summary = json.loads((tmp_path / "cell" / "summary.json").read_text())
    [metadata] = summary["server_metadata"]
    assert metadata["executed_steps"] == 1 and metadata["action_queue"] is False and metadata["n_action_steps"] == 1
    assert metadata["chunk_execution"].startswith("re-plan every step")
    assert len((tmp_path / "cell" / "episodes.jsonl").read_text().splitlines()) == 2
