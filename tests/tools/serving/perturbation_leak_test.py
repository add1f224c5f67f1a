"""The out-of-distribution leak check (issue 49, acceptance 4): under every level of every axis in
configs/perturbations/, the request a served policy receives carries nothing that names or encodes
the level, except what its axis declares: the language axis changes the prompt, by design; every
other axis changes only what the cameras see.

A stand-in server (tests/batch/remote/policy_server.py) saves every request and answers a NaN
action (--nan-entry 0), so each episode ends invalid_action on its first request and a cell costs
one request per episode. The base cell and one cell per level run the same episodes; each level's
first requests must equal the base cell's key for key (the same keys, dtypes and shapes; every
value but the images byte for byte: the state, the prompt, the episode index and step and any
other metadata), the prompt (and the "task" key carrying the same text) excepted for the language
axis, whose prompt must still name neither its axis nor its level. Where a level's request differs, the failure names the level and the key.

    /usr/bin/python3 perturbation_leak_test.py TAVIS_BINARY SOURCE_DIR
"""

import glob
import os
import shutil
import sys
import tempfile

import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from tool_script_support import check, failures, passed_count, run, start_policy_server  # noqa: E402

TAVIS, SOURCE = (os.path.abspath(path) for path in sys.argv[1:3])
TASK, EPISODES = "clutter-pick-cube", 2
# The axis whose levels change the prompt, by design (docs/perturbations.md); no other axis may.
PROMPT_AXES = {"language"}
# The keys that carry the instruction: the prompt, and the tavis layout's LeRobot-style "task" (the
# same text).
PROMPT_KEYS = {"prompt", "task"}


def levels():
    """[(axis, level)] for every level of every axis file, in file order."""
    found = []
    for path in sorted(glob.glob(os.path.join(SOURCE, "configs", "perturbations", "*.yaml"))):
        with open(path) as file:
            axis = yaml.safe_load(file)
        found += [(axis["axis"], level["name"]) for level in axis["levels"]]
    return found


def first_requests(work, name, perturb):
    """Each episode's first request as the server decoded it: {episode: {key: array}}."""
    record_dir = os.path.join(work, name + "_requests")
    process, address = start_policy_server(SOURCE, ["--nan-entry", "0"], record_dir)
    try:
        command = [TAVIS, "eval", "--task", TASK, "--episodes", str(EPISODES), "--envs", str(EPISODES), "--policy",
                   "openpi", "--server", address, "--out", os.path.join(work, name), "--quiet", "--threads", "2"]
        for choice in perturb:
            command += ["--perturb", choice]
        run(command)
    finally:
        process.terminate()
        process.wait(timeout=10)
    requests = {}
    for episode in range(EPISODES):
        with np.load(os.path.join(record_dir, f"e{episode}_s0.npz")) as saved:
            requests[episode] = {key: saved[key] for key in saved.files}
    return requests


def is_image(value):
    return value.dtype == np.uint8 and value.ndim == 3


def main():
    work = tempfile.mkdtemp(prefix="tavis_leak_")
    all_levels = levels()
    check(len(all_levels) >= 30 and len({axis for axis, _ in all_levels}) >= 7,
          f"the axes of configs/perturbations/ are read: {all_levels}")
    base = first_requests(work, "base", [])
    check(any(is_image(value) for value in base[0].values()), "the base request carries the cameras' images")
    check("prompt" in base[0] and str(base[0]["prompt"]), f"the base request carries a prompt: {sorted(base[0])}")
    for axis, level in all_levels:
        name = f"{axis}.{level}"
        perturbed = first_requests(work, name, [f"{axis}:{level}"])
        for episode in range(EPISODES):
            was, now = base[episode], perturbed[episode]
            check(sorted(now) == sorted(was), f"{name} episode {episode}: keys {sorted(now)} against {sorted(was)}")
            for key in sorted(set(was) & set(now)):
                if key in PROMPT_KEYS and axis in PROMPT_AXES:
                    prompt = str(now[key]).lower()
                    check(now[key].dtype.kind == "U" and now[key].shape == () and axis not in prompt
                          and level not in prompt,
                          f"{name} episode {episode}: {key} {prompt!r} is a text naming neither its axis nor its level")
                elif (now[key].dtype, now[key].shape) != (was[key].dtype, was[key].shape):
                    check(False, f"{name} episode {episode}: {key} is {now[key].dtype} {now[key].shape}, "
                                 f"the base's {was[key].dtype} {was[key].shape}")
                elif is_image(was[key]):
                    continue  # what the cameras see is what a visual axis perturbs
                else:
                    check(np.array_equal(now[key], was[key]) and now[key].tobytes() == was[key].tobytes(),
                          f"{name} episode {episode}: {key} differs from the base's: {now[key]!r} against "
                          f"{was[key]!r}")
        if axis in PROMPT_AXES:
            changed = any(str(perturbed[e]["prompt"]) != str(base[e]["prompt"]) for e in range(EPISODES))
            check(changed, f"{name}: the language axis changes the prompt (else this check proves nothing)")
    shutil.rmtree(work, ignore_errors=True)
    print(f"{passed_count()} checks passed over {len(all_levels)} levels, {len(failures)} failed")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
