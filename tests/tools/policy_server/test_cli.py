"""python3 -m tavis_server as the C++ tests and users start it: the stand-ins (echo, sleep,
stateful), a MODULE:FACTORY policy, and bad command lines."""

import json
import os
import subprocess
import sys
import zlib

import numpy as np
import pytest

from conftest import SERVER_PACKAGE_DIR, batched, connect, get, observation, run

HERE = os.path.dirname(os.path.abspath(__file__))


def ask_all(url, requests):
    async def session():
        async with connect(url) as client:
            return client.metadata, [await client.ask(request) for request in requests]
    return run(session())


def assert_valid_actions(actions):
    """What the tavis client executes (kinematics/action_check.h), and grippers in [-1, 1]."""
    assert np.isfinite(actions).all()
    assert (np.abs(actions[..., [0, 1, 2, 7, 8, 9]]) <= 10).all()
    for quaternion in (slice(3, 7), slice(10, 14)):
        np.testing.assert_allclose(np.linalg.norm(actions[..., quaternion], axis=-1), 1.0, rtol=1e-6)
    assert (np.abs(actions[..., 17:19]) <= 1).all()


def test_echo_encodes_what_it_received(cli_server):
    server = cli_server("--policy", "echo", "--chunk", "3")
    assert server.ready_line == f"tavis_server: serving echo on ws://127.0.0.1:{server.port}"
    assert get(server.port, "/healthz") == (200, b"OK\n")
    requests = [observation(2, 41, 0, prompt="stack the blocks"), observation(2, 41, 1),
                batched([observation(0, 7, 0), observation(5, 9, 0)])]
    metadata, replies = ask_all(server.url, requests)
    assert metadata["policy"] == "echo" and metadata["action_horizon"] == 3 and metadata["batched_requests"] is True
    first = replies[0]["actions"]
    assert first.shape == (3, 19) and first.dtype == np.float32
    assert_valid_actions(first)
    assert np.round(first[:, :3] * 1000).tolist() == [[2, 41, 0]] * 3
    np.testing.assert_allclose(first[:, 14], [0, 1e-3, 2e-3], atol=1e-7)
    assert first[0, 15] == 1.0 and replies[1]["actions"][0, 15] == 0.0
    state_crc = zlib.crc32(requests[0]["observation.state"].tobytes())
    image_sum = sum(int(requests[0][key].sum()) for key in requests[0] if key.startswith("observation.images."))
    assert round(first[0, 7] * 1000) == state_crc % 10000
    assert round(first[0, 8] * 1000) == image_sum % 10000
    assert round(first[0, 9] * 1000) == len("stack the blocks")
    together = replies[2]["actions"]
    assert together.shape == (2, 3, 19)
    assert_valid_actions(together)
    assert np.round(together[:, 0, :3] * 1000).tolist() == [[0, 7, 0], [5, 9, 0]]
    assert server.stop() == 0


@pytest.mark.parametrize("device", [[], ["--device", "cpu"]], ids=["direct", "as-a-checkpoint"])
def test_sleep_answers_its_row_once_per_forward_pass(cli_server, device):
    row = "0.3,0.1,0.9,0,1,0,0,0.3,-0.1,0.9,1,0,0,0,0,0.2,0,0.5,-0.5"
    server = cli_server("--policy", "sleep", "--sleep-ms", "400", "--chunk", "4", "--action-row", row, *device)
    metadata, replies = ask_all(server.url, [observation(0, 0, 0), batched([observation(env, 0, 0) for env in
                                                                            range(1, 6)])])
    assert metadata["action_horizon"] == 4 and metadata["sleep_ms"] == 400
    assert metadata.get("device") == ("cpu" if device else None)  # torch input tensors only under --device
    expected = np.array([float(value) for value in row.split(",")], dtype=np.float32)
    assert replies[0]["actions"].shape == (4, 19)
    assert (replies[0]["actions"] == expected).all()
    assert replies[1]["actions"].shape == (5, 4, 19) and (replies[1]["actions"] == expected).all()
    # One forward pass sleeps 400 ms whatever the batch size: five envs cost one sleep, not five.
    assert 400 <= replies[0]["server_timing"]["infer_ms"]
    assert 400 <= replies[1]["server_timing"]["infer_ms"] < 1600
    assert server.stop() == 0


def test_stateful_check_records_steps_per_env_and_episode(cli_server, tmp_path):
    record = tmp_path / "steps.json"
    server = cli_server("--policy", "stateful", "--chunk", "2", "--record", str(record))
    requests = [batched([observation(0, 0, 0), observation(1, 1, 0)]), batched([observation(0, 0, 1), observation(1, 1, 1)]),
                observation(0, 2, 0), observation(1, 1, 5)]
    metadata, replies = ask_all(server.url, requests)
    assert metadata["policy"] == "stateful"
    assert replies[1]["received"] == [{"connection": 0, "env_index": 0, "episode_index": 0, "steps": [0, 1], "is_first": [True, False]},
                                      {"connection": 0, "env_index": 1, "episode_index": 1, "steps": [0, 1], "is_first": [True, False]}]
    assert replies[3]["received"] == {"connection": 0, "env_index": 1, "episode_index": 1, "steps": [0, 1, 5],
                                      "is_first": [True, False, False]}
    assert replies[3]["actions"].shape == (2, 19)
    assert_valid_actions(replies[3]["actions"])
    assert server.stop() == 0
    written = json.loads(record.read_text())
    assert written["episodes"] == [
        {"connection": 0, "env_index": 0, "episode_index": 0, "steps": [0, 1], "is_first": [True, False]},
        {"connection": 0, "env_index": 0, "episode_index": 2, "steps": [0], "is_first": [True]},
        {"connection": 0, "env_index": 1, "episode_index": 1, "steps": [0, 1, 5], "is_first": [True, False, False]}]
    assert written["requests"] == [[0, 1], [0, 1], [0], [1]]


def test_stateful_check_with_a_history_demands_every_step(cli_server):
    server = cli_server("--policy", "stateful", "--history", "2")

    async def session():
        async with connect(server.url) as client:
            await client.ask(observation(0, 0, 0))
            with pytest.raises(AssertionError, match="skips from step 0"):
                await client.ask(observation(0, 0, 2))

    run(session())


def test_a_factory_policy_is_served(cli_server):
    server = cli_server("--policy", "history_policy:HistoryPolicy", "--policy-arg", "n_obs_steps=2",
                        "--policy-arg", "chunk=3", "--action-queue", "off", pythonpath=[HERE])
    metadata, replies = ask_all(server.url, [observation(0, 3, 0), observation(0, 3, 1)])
    assert metadata["policy"] == "history_policy:HistoryPolicy"
    assert metadata["n_obs_steps"] == 2 and metadata["action_horizon"] == 3 and metadata["device"] == "cpu"
    assert metadata["action_queue"] is False
    assert np.round(replies[1]["actions"][0, :3] * 1000).tolist() == [0, 1, 3]  # a forward pass at step 1


def test_a_history_policy_queues_n_action_steps_by_default(cli_server):
    server = cli_server("--policy", "history_policy:DiffusionLikePolicy", "--n-action-steps", "2", pythonpath=[HERE])
    metadata, replies = ask_all(server.url, [observation(0, 3, step) for step in range(4)])
    assert metadata["action_queue"] is True and metadata["n_action_steps"] == 2 and metadata["action_horizon"] == 1
    # (newest history step, horizon row, forward pass) per step: passes at steps 0 and 2 only.
    assert [tuple(np.round(reply["actions"][0, [1, 14, 15]] * 1000).astype(int).tolist()) for reply in replies] == [
        (0, 1, 1), (0, 2, 1), (2, 1, 2), (2, 2, 2)]


@pytest.mark.parametrize("args, message", [
    (["--policy", "nonsense"], "--policy 'nonsense' is neither a stand-in (echo, sleep, stateful) nor MODULE:FACTORY"),
    (["--policy", "json:no_such_factory"], "module json has no callable no_such_factory"),
    (["--policy", "no_such_module_here:make"], "No module named 'no_such_module_here'"),
    (["--policy", "sleep", "--action-row", "1,2,3"], "has 3 fields; a tavis action has 19"),
    (["--policy", "stateful", "--action-row", ",".join(["0"] * 19)], "an arm quaternion has norm 0"),
    (["--policy", "echo", "--chunk", "0"], "echo: --chunk 0 must be at least 1"),
    (["--policy", "history_policy:HistoryPolicy", "--policy-arg", "chunk"], "--policy-arg 'chunk' is not KEY=VALUE"),
    (["--policy", "echo", "--action-queue", "on"],
     "--action-queue/--n-action-steps apply to LeRobot-interface policies, not to the echo stand-in served directly"),
    (["--policy", "history_policy:HistoryPolicy", "--n-action-steps", "0"], "n_action_steps 0 must be an integer"),
])
def test_bad_command_lines_exit_2_naming_the_value(args, message):
    environment = dict(os.environ, PYTHONPATH=os.pathsep.join([SERVER_PACKAGE_DIR, HERE]))
    result = subprocess.run([sys.executable, "-m", "tavis_server", "--port", "0", *args], env=environment,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert message in result.stderr
    assert result.stdout == ""


def test_a_port_in_use_exits_1(cli_server):
    server = cli_server("--policy", "echo")
    environment = dict(os.environ, PYTHONPATH=SERVER_PACKAGE_DIR)
    result = subprocess.run([sys.executable, "-m", "tavis_server", "--policy", "echo", "--port", str(server.port)],
                            env=environment, capture_output=True, text=True, timeout=60)
    assert result.returncode == 1
    assert f"cannot listen on 127.0.0.1:{server.port}" in result.stderr
