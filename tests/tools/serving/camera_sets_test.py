"""Camera sets (batch/camera_protocol.h) as a served policy receives them.

1. wrists-only on blocked-clutter-pick-cube is today's head protocol there: the task already
   blacks the head image, so every served request (images, state, prompt) and every record is the
   same byte for byte.
2. On clutter-pick-cube, whose head camera is not black, wrists-only sends an all-zero head image
   where head sends a real one, and the same wrist images; head-only sends all-zero wrist images
   and the same head image. The cells pair: the same episodes under every set.

policy_server.py answers, by (episode, step), the actions `tavis eval --policy expert --expert-hz
20` chose, so the head moves as the expert moves it; it saves every request it receives.

    /usr/bin/python3 camera_sets_test.py TAVIS_BINARY SOURCE_DIR
"""

import glob
import json
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from tool_script_support import check, failures, passed_count, run, start_replay_server  # noqa: E402

TAVIS, SOURCE = sys.argv[1], sys.argv[2]
ROBOT, SEED, EPISODES = "gr1t2", "2", "2"
HEAD, LEFT, RIGHT = "observation.images.OBS_HEAD", "observation.images.OBS_WRIST_LEFT", "observation.images.OBS_WRIST_RIGHT"
def served_cell(task, camera, replay, work):
    record_dir, out = os.path.join(work, f"{task}_{camera}_requests"), os.path.join(work, f"{task}_{camera}")
    server, address = start_replay_server(SOURCE, replay, record_dir)
    try:
        run([TAVIS, "eval", "--task", task, "--robot", ROBOT, "--seed", SEED, "--episodes", EPISODES, "--envs", "2",
             "--policy", "openpi", "--server", address, "--camera", camera, "--out", out, "--quiet"])
    finally:
        server.terminate()
        server.wait()
    requests = {}
    for path in sorted(glob.glob(os.path.join(record_dir, "*.npz"))):
        with np.load(path) as saved:
            requests[os.path.basename(path)] = {key: saved[key] for key in saved.files}
    with open(os.path.join(out, "episodes.jsonl")) as file:
        records = file.read()
    with open(os.path.join(out, "summary.json")) as file:
        summary = json.load(file)
    return requests, records, summary


def expert_actions(task, work):
    out = os.path.join(work, f"{task}_expert")
    run([TAVIS, "eval", "--task", task, "--robot", ROBOT, "--seed", SEED, "--episodes", EPISODES, "--envs", "2",
         "--policy", "expert", "--expert-hz", "20", "--out", out, "--quiet"])
    return os.path.join(out, "actions")


def same_requests(a, b, keys=None):
    if a.keys() != b.keys():
        return False
    for name in a:
        for key in (keys if keys is not None else a[name].keys() | b[name].keys()):
            if key not in a[name] or key not in b[name] or not np.array_equal(a[name][key], b[name][key]):
                return False
    return True


def main():
    with tempfile.TemporaryDirectory() as work:
        # 1. blocked-clutter-pick-cube: wrists-only == head.
        task = "blocked-clutter-pick-cube"
        replay = expert_actions(task, work)
        head, head_records, head_summary = served_cell(task, "head", replay, work)
        wrists, wrists_records, wrists_summary = served_cell(task, "wrists-only", replay, work)
        check(len(head) > 100, f"{task}: the head cell sent {len(head)} requests")
        check(all(not request[HEAD].any() for request in head.values()), f"{task}: the task blacks the head image")
        check(any(request[LEFT].any() for request in head.values()), f"{task}: the wrist images are not black")
        check(same_requests(head, wrists), f"{task}: wrists-only sends exactly what head sends")
        check(wrists_records == head_records, f"{task}: wrists-only records equal head's")
        check(wrists_summary["camera"] == "wrists-only" and head_summary["camera"] == "head", "summary.json names the set")
        check(wrists_summary["galt"] == head_summary["galt"], "wrists-only computes GALT as head does")
        check(json.loads(head_records.splitlines()[0])["success"], f"{task}: the replayed expert succeeds")

        # 2. clutter-pick-cube: the sets black what they say, and only that.
        task = "clutter-pick-cube"
        replay = expert_actions(task, work)
        head, head_records, _ = served_cell(task, "head", replay, work)
        wrists, wrists_records, _ = served_cell(task, "wrists-only", replay, work)
        head_only, head_only_records, _ = served_cell(task, "head-only", replay, work)
        check(all(request[HEAD].any() for request in head.values()), f"{task}: head sends a real head image")
        check(all(not request[HEAD].any() for request in wrists.values()), f"{task}: wrists-only sends a black head image")
        check(same_requests(head, wrists, [LEFT, RIGHT, "observation.state", "prompt"]),
              f"{task}: wrists-only sends head's wrist images and state")
        check(all(not request[LEFT].any() and not request[RIGHT].any() for request in head_only.values()),
              f"{task}: head-only sends black wrist images")
        check(same_requests(head, head_only, [HEAD, "observation.state"]), f"{task}: head-only sends head's head image")
        # The replayed actions do not read images, so every set's records are head's: the cells pair.
        check(wrists_records == head_records and head_only_records == head_records, f"{task}: the sets' episodes pair with head's")

    print(f"{passed_count()} checks passed, {len(failures)} failed")
    sys.exit(1 if failures else 0)


main()
