"""Issue 51, acceptance 2: a served cell whose server declares a 96x96, two-camera, history-11
contract (tavis_server --contract, observation_contract in its metadata frame) gets exactly that,
checked in the stateful stand-in's request log, with no --image-size, --keys, --match-dataset or
--replan-steps; a contradicting option is refused before episode 1 naming both values, as is a
cell of another task or robot than the contract says the policy was trained for; a server that
declares nothing keeps today's defaults (320x240, every camera) and its cell's records.

    /usr/bin/python3 declared_contract_test.py TAVIS_BINARY SOURCE_DIR
"""

import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from tool_script_support import check, failures, passed_count  # noqa: E402

TAVIS, SOURCE = sys.argv[1], sys.argv[2]
HEAD, WRIST, STATE = "observation.images.OBS_HEAD", "observation.images.OBS_WRIST_LEFT", "observation.state"
CONTRACT = {"cameras": {"head": HEAD, "left_wrist": WRIST}, "image_width": 96, "image_height": 96,
            "state": {"key": STATE, "size": 34}, "task": "clutter-pick-cube", "robot": "gr1t2"}


def start_server(work, name, contract):
    record = os.path.join(work, name + ".json")
    command = ["/usr/bin/python3", "-m", "tavis_server", "--policy", "stateful", "--history", "11",
               "--record", record, "--port", "0"]
    if contract is not None:
        path = os.path.join(work, name + "_contract.json")
        with open(path, "w") as f:
            json.dump(contract, f)
        command += ["--contract", path]
    process = subprocess.Popen(command, env=dict(os.environ, PYTHONPATH=os.path.join(SOURCE, "tools", "policy_server")),
                               stdout=subprocess.PIPE, text=True)
    line = process.stdout.readline()
    if not line.startswith("tavis_server: serving "):
        process.kill()
        sys.exit(f"tavis_server did not start: {line!r}")
    return process, line.split(" on ")[1].strip(), record


def evaluate(url, out, *extra, task="clutter-pick-cube", robot="gr1t2"):
    return subprocess.run([TAVIS, "eval", "--task", task, "--robot", robot, "--episodes", "1", "--envs", "1",
                           "--policy", "openpi", "--server", url, "--out", out, "--quiet", *extra],
                          capture_output=True, text=True, timeout=900)


def main():
    with tempfile.TemporaryDirectory() as work:
        server, url, record = start_server(work, "declared", CONTRACT)
        try:
            result = evaluate(url, os.path.join(work, "adopted"))
            check(result.returncode == 0, f"the cell adopting the contract failed: {result.stderr}")
            with open(record) as f:
                log = json.load(f)
            expected = {HEAD: {"shape": [96, 96, 3], "dtype": "|u1"}, WRIST: {"shape": [96, 96, 3], "dtype": "|u1"},
                        STATE: {"shape": [34], "dtype": "<f4"}}
            check(log["layouts"] == [expected], f"requests sent {log['layouts']}, expected {expected}")
            steps = log["episodes"][0]["steps"]
            check(steps == list(range(len(steps))) and len(steps) > 11,
                  f"history 11 needs every step asked (executed_steps 1): got steps {steps[:20]}...")
            with open(os.path.join(work, "adopted", "summary.json")) as f:
                summary = json.load(f)
            check("observation_contract" in summary["server_metadata"][0], "summary.json keeps the metadata frame")
            trained_for = summary["provenance"]["policy"].get("trained_for")
            check(trained_for == [{"task": "clutter-pick-cube", "robot": "gr1t2"}],
                  f"provenance records the task and robot the policy was trained for: {trained_for}")
            for what, given, declared in (("task", "wait-then-act", "clutter-pick-cube"), ("robot", "reachy2", "gr1t2")):
                out = os.path.join(work, "other_" + what)
                result = evaluate(url, out, **{what: given})
                named = f"was trained for {what} {declared}; this cell"
                check(result.returncode == 1 and named in result.stderr and given in result.stderr,
                      f"a cell of {what} {given} must be refused naming both: exit {result.returncode}: "
                      f"{result.stderr}")
                check(not os.path.exists(os.path.join(out, "episodes.jsonl")), f"{what}: refused before episode 1")
            for flag, value, named in (("--image-size", "224x224", "96x96"), ("--replan-steps", "5", "executed_steps 1"),
                                       ("--keys", "libero", "OBS_HEAD")):
                out = os.path.join(work, "refused" + flag)
                result = evaluate(url, out, flag, value)
                check(result.returncode != 0 and flag in result.stderr and value in result.stderr and named in result.stderr,
                      f"{flag} {value} must be refused naming both values: exit {result.returncode}: {result.stderr}")
                check(not os.path.exists(os.path.join(out, "episodes.jsonl")), f"{flag}: refused before episode 1")
        finally:
            server.terminate()
            server.wait()
        server, url, record = start_server(work, "plain", None)
        try:
            result = evaluate(url, os.path.join(work, "plain"), "--replan-steps", "1")
            check(result.returncode == 0, f"a server that declares nothing must still work: {result.stderr}")
            with open(record) as f:
                layouts = json.load(f)["layouts"]
            check(len(layouts) == 1 and layouts[0][HEAD]["shape"] == [240, 320, 3] and len(layouts[0]) == 4,
                  f"a plain server gets today's layout (320x240, three cameras): {layouts}")
            with open(os.path.join(work, "plain", "summary.json")) as f:
                policy = json.load(f)["provenance"]["policy"]
            check("trained_for" not in policy, f"a server that declares nothing adds nothing to the record: {policy}")
        finally:
            server.terminate()
            server.wait()
    print(f"{passed_count()} checks passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
