"""What the Python tests of the `tavis` program share: counted checks, running the program, and
the stand-in policy server (tests/batch/remote/policy_server.py) replaying saved actions.

A test script puts tests/tools on sys.path and imports these; it ends with
`sys.exit(1 if failures else 0)` after printing `passed_count()`.
"""

import os
import socket
import subprocess
import sys
import time
import urllib.request

failures = []
_passed = [0]


def check(condition, message):
    """Counts a check; a failed one is printed at once and kept in `failures`."""
    _passed[0] += 1 if condition else 0
    if not condition:
        failures.append(message)
        print("FAIL:", message, flush=True)


def passed_count():
    return _passed[0]


def run(args, expect_ok=True, **kwargs):
    """Runs a command (10 minutes at most); one that fails ends the test with its output."""
    result = subprocess.run(args, capture_output=True, text=True, timeout=600, **kwargs)
    if expect_ok and result.returncode != 0:
        sys.exit(f"{' '.join(args)} exited {result.returncode}:\n{result.stdout}\n{result.stderr}")
    return result


def free_port():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def start_replay_server(source_dir, replay, record_dir=None, lifetime=900):
    """Starts policy_server.py answering each request with the saved action row of its (episode,
    step) from `replay` (a folder of episode_<i>.csv or .csv.gz), saving every request under
    `record_dir` if given; returns (process, ws:// address) once its /healthz answers."""
    return start_policy_server(source_dir, ["--replay-actions", replay], record_dir, lifetime)


def start_policy_server(source_dir, options, record_dir=None, lifetime=900):
    """Starts policy_server.py (horizon 1, 19 action entries) with further `options`, saving every
    request under `record_dir` if given; returns (process, ws:// address) once its /healthz answers."""
    server = os.path.join(source_dir, "tests", "batch", "remote", "policy_server.py")
    port = free_port()
    command = ["/usr/bin/python3", server, "--port", str(port), "--horizon", "1", "--action-dim", "19",
               "--lifetime", str(lifetime)] + list(options)
    if record_dir is not None:
        command += ["--record-dir", record_dir]
    process = subprocess.Popen(command, cwd=os.path.dirname(server))
    deadline = time.time() + 30
    while time.time() < deadline:
        try:
            urllib.request.urlopen(f"http://127.0.0.1:{port}/healthz", timeout=1)
            return process, f"ws://127.0.0.1:{port}"
        except OSError:
            time.sleep(0.1)
    process.kill()
    sys.exit("policy_server.py did not become ready")
