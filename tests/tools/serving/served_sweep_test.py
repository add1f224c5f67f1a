"""Issue 46, acceptance 3: a served sweep of 4 cells (two tasks, head and fixed) against ONE
reference server, with default options (served cells run side by side), completes and writes
the same records as the same cells run one at a time.

The server is the project's own (tools/policy_server/tavis_server) serving a LeRobot-interface
policy with an observation history (tests/tools/policy_server/history_policy.py's HistoryPolicy,
n_obs_steps 2, through torch), whose actions are computed from the history it is given: the
server's action queue needs every step (replan_steps 1). Cells running side by side each number
their envs from 0, so a server that keeps per-episode state by env alone refuses the second
cell's steps ("comes after step 10; steps must grow"), and one that mixed the cells' histories
would change their records. The reference run is the same spec with --concurrent-cells 1 against
the same server.

    /usr/bin/python3 served_sweep_test.py TAVIS_BINARY SOURCE_DIR
"""

import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from tool_script_support import check, failures, passed_count, run  # noqa: E402

TAVIS, SOURCE = sys.argv[1], sys.argv[2]
TASKS = ["clutter-pick-cube", "blocked-clutter-pick-cube"]
CAMERAS = ["head", "fixed"]


def start_reference_server():
    """python3 -m tavis_server serving HistoryPolicy on a free port; returns (process, url)."""
    environment = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [os.path.join(SOURCE, "tools", "policy_server"), os.path.join(SOURCE, "tests", "tools", "policy_server")]),
        OMP_NUM_THREADS="1")
    process = subprocess.Popen(["/usr/bin/python3", "-m", "tavis_server", "--policy", "history_policy:HistoryPolicy",
                                "--policy-arg", "n_obs_steps=2", "--policy-arg", "chunk=4", "--port", "0"],
                               env=environment, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = process.stdout.readline()
    if not line.startswith("tavis_server: serving "):
        process.kill()
        sys.exit(f"the reference server did not start: {line!r} {process.stderr.read()}")
    return process, line.split(" on ")[1].strip()


def spec_text(url):
    return "\n".join([
        f"tasks: [{', '.join(TASKS)}]",
        "robots: [gr1t2]",
        "splits: [id]",
        f"cameras: [{', '.join(CAMERAS)}]",
        "seeds: [0]",
        "episodes: 1",
        "envs: 1",
        "policy:",
        "  name: openpi",
        f"  servers: [{url}]",
        "  replan_steps: 1",
        "  serving: batched",
        ""])


def records(out):
    cells = sorted(os.listdir(os.path.join(out, "cells")))
    result = {}
    for cell in cells:
        with open(os.path.join(out, "cells", cell, "episodes.jsonl")) as file:
            result[cell] = file.read()
    return result


def compare(work):
    server, url = start_reference_server()
    try:
        spec = os.path.join(work, "spec.yaml")
        with open(spec, "w") as file:
            file.write(spec_text(url))
        side_by_side, one_at_a_time = os.path.join(work, "side_by_side"), os.path.join(work, "one_at_a_time")
        run([TAVIS, "sweep", spec, "--out", side_by_side, "--quiet"])
        run([TAVIS, "sweep", spec, "--out", one_at_a_time, "--concurrent-cells", "1", "--quiet"])
        check(server.poll() is None, "the reference server is still serving")
    finally:
        server.terminate()
        _, errors = server.communicate(timeout=30)
    check("Traceback" not in errors, f"the server logged a traceback:\n{errors}")
    together, alone = records(side_by_side), records(one_at_a_time)
    check(len(together) == 4, f"4 cells, got {sorted(together)}")
    check(sorted(together) == sorted(alone), f"cells {sorted(together)} vs {sorted(alone)}")
    for cell, text in together.items():
        lines = text.splitlines()
        check(len(lines) == 1, f"{cell}: {len(lines)} records")
        check(text == alone.get(cell), f"{cell}: the records side by side differ from the cell run alone")


def main():
    work = tempfile.mkdtemp(prefix="tavis_served_sweep_")
    compare(work)
    print(f"{passed_count()} passed, {len(failures)} failed" + (f"; {work} kept" if failures else ""))
    if not failures:
        shutil.rmtree(work)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
