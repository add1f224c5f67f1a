"""The contract the server declares in its metadata frame (tavis_server/contract.py, docs/serving.md
"The contract a server declares"): the policy's fields checked, the served ones from how it serves."""

import json

import pytest

from tavis_server.contract import CONTRACT_KEY, complete_contract
from tavis_server.server import PolicyServer
from tavis_server.standins import StatefulCheckPolicy

DECLARED = {"cameras": {"head": "observation.images.OBS_HEAD", "left_wrist": "observation.images.OBS_WRIST_LEFT"},
            "image_width": 96, "image_height": 96, "state": {"key": "observation.state", "size": 34}}


def test_the_server_adds_history_chunk_and_executed_steps():
    served = StatefulCheckPolicy(chunk=1, history=11)
    served.metadata = {**served.metadata, CONTRACT_KEY: DECLARED}
    contract = PolicyServer(served).metadata[CONTRACT_KEY]
    assert contract == {"version": 1, **DECLARED, "n_obs_steps": 11, "chunk_length": 1, "executed_steps": 1}


def test_the_task_and_robot_trained_for_are_sent_as_declared():
    declared = {**DECLARED, "task": "conditional-pick", "robot": "gr1t2"}
    contract = complete_contract(declared, chunk_length=1, n_obs_steps=11, consecutive_steps=True)
    assert (contract["task"], contract["robot"]) == ("conditional-pick", "gr1t2")
    # Which names exist is the client's to know: a well-formed name of no task is sent.
    assert complete_contract({**DECLARED, "task": "no-such-task"}, 1, 11, True)["task"] == "no-such-task"
    assert "task" not in complete_contract(DECLARED, 1, 11, True)


def test_without_a_history_the_client_executes_the_whole_reply():
    assert complete_contract(DECLARED, chunk_length=8, n_obs_steps=1, consecutive_steps=False)["executed_steps"] == 8


def test_a_plain_policy_declares_nothing():
    assert CONTRACT_KEY not in PolicyServer(StatefulCheckPolicy()).metadata


@pytest.mark.parametrize("change, message", [
    ({"image_width": "96"}, "image_width must be an int"),
    ({"image_width": 4}, "image_width must be an int from 8"),
    ({"cameras": {"nose": "x"}}, "unknown camera 'nose'"),
    ({"cameras": {"head": "step"}}, "cameras.head must be a key"),
    ({"cameras": {"head": "observation.state"}}, "two of the request's keys are the same"),
    ({"state": {"key": "observation.state"}}, "state must be"),
    ({"checkpoint_sha256": "ABC"}, "checkpoint_sha256 must be 64 lower-case hex digits"),
    ({"n_obs_steps": 2}, "n_obs_steps is declared 2, but the server serves 11"),
    ({"colour": "red"}, "unknown fields"),
    ({"task": "Conditional Pick"}, "task must be a tavis name"),
    ({"task": "c" * 65}, "task must be a tavis name"),
    ({"task": ""}, "task must be a tavis name"),
    ({"task": "-pick"}, "task must be a tavis name"),
    ({"robot": 7}, "robot must be a tavis name"),
    ({"robot": "gr1t2\n"}, "robot must be a tavis name"),
])
def test_a_malformed_declaration_is_refused_naming_the_field(change, message):
    with pytest.raises(ValueError, match=message):
        complete_contract({**DECLARED, **change}, chunk_length=1, n_obs_steps=11, consecutive_steps=True)


def test_the_cli_sends_a_contract_file(tmp_path):
    from tavis_server import cli
    path = tmp_path / "contract.json"
    path.write_text(json.dumps(DECLARED))
    options = cli.parser().parse_args(["--policy", "stateful", "--history", "11", "--contract", str(path)])
    served = cli.build_served_policy(options)
    served.metadata = {**served.metadata, CONTRACT_KEY: cli._read_contract(options.contract)}
    assert PolicyServer(served).metadata[CONTRACT_KEY]["n_obs_steps"] == 11
    path.write_text("{not json")
    with pytest.raises(ValueError, match="--contract"):
        cli._read_contract(str(path))
