"""Serving throughput: a served cell against the same cell replayed without a server.

A policy server that takes --sleep-ms (default 30) per forward pass whatever its batch size (one
pass at a time, as on one GPU) serves a 96-episode clutter-pick-cube GR1T2 cell with the default
observation (head + both wrists at 320x240) and --envs 16. Its actions are the scripted expert's at
20 Hz (`tavis eval --policy expert --expert-hz 20` saves them), so the served episodes are real
ones. The same cell then replays the served actions with no server (`--policy replay --actions
DIR/actions`, the same cameras rendered). Runs alternate (served, replay, served, ...) and the
medians are compared; the records of every run must agree.

    /usr/bin/python3 bench/serving_throughput.py build/tavis [--runs 3] [--serving batched ...]

Prints each run, then per mode: requests, envs per request, mean batch size, the time split
(waiting for replies vs the rest) and the ratio served / replay. Writes --out/summary.json.
"""

import argparse
import json
import os
import shutil
import socket
import statistics
import subprocess
import sys
import time
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
SERVER = os.path.join(HERE, "..", "tests", "batch", "remote", "policy_server.py")
CAMERAS = "head,left_wrist,right_wrist"


def free_port():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def run(args):
    start = time.monotonic()
    result = subprocess.run(args, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"{' '.join(args)} exited {result.returncode}:\n{result.stdout}\n{result.stderr}")
    return time.monotonic() - start


def summary(out):
    with open(os.path.join(out, "summary.json")) as file:
        return json.load(file)


def records(out):
    with open(os.path.join(out, "episodes.jsonl")) as file:
        return [(line["episode"], line["success"], line["end"], line["length_control_ticks"])
                for line in map(json.loads, file)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("tavis")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--episodes", type=int, default=96)
    parser.add_argument("--envs", type=int, default=16)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--sleep-ms", type=float, default=30.0)
    parser.add_argument("--horizon", type=int, default=10, help="chunk rows per reply")
    parser.add_argument("--serving", nargs="+", default=["batched"], choices=["serial", "per-env", "batched"])
    parser.add_argument("--out", default="/tmp/tavis_serving_bench")
    args = parser.parse_args()
    shutil.rmtree(args.out, ignore_errors=True)
    os.makedirs(args.out)
    common = ["--task", "clutter-pick-cube", "--robot", "gr1t2", "--episodes", str(args.episodes), "--seed", "0",
              "--quiet"] + (["--threads", str(args.threads)] if args.threads else [])
    expert = os.path.join(args.out, "expert")
    run([args.tavis, "eval", "--policy", "expert", "--expert-hz", "20", "--out", expert] + common)

    port = free_port()
    server = subprocess.Popen(["/usr/bin/python3", SERVER, "--port", str(port), "--batched", "--horizon", str(args.horizon),
                               "--action-dim", "19", "--sleep-ms", str(args.sleep_ms), "--lifetime", "86400",
                               "--replay-actions", os.path.join(expert, "actions")], cwd=os.path.dirname(SERVER))
    try:
        for _ in range(300):
            try:
                urllib.request.urlopen(f"http://127.0.0.1:{port}/healthz", timeout=1)
                break
            except OSError:
                time.sleep(0.1)
        served_args = ["--policy", "openpi", "--server", f"ws://127.0.0.1:{port}", "--envs", str(args.envs)]
        times = {mode: [] for mode in args.serving + ["replay"]}
        details = {}
        reference = None
        for attempt in range(args.runs):
            for mode in args.serving:
                out = os.path.join(args.out, f"served_{mode}_{attempt}")
                times[mode].append(run([args.tavis, "eval", "--serving", mode, "--out", out] + served_args + common))
                details[mode] = summary(out)
                reference = reference or records(out)
                if records(out) != reference:
                    sys.exit(f"{out}: records differ from the first served run")
                print(f"run {attempt} {mode}: {times[mode][-1]:.1f} s", flush=True)
            out = os.path.join(args.out, f"replay_{attempt}")
            served_actions = os.path.join(args.out, f"served_{args.serving[0]}_0", "actions")
            times["replay"].append(run([args.tavis, "eval", "--policy", "replay", "--actions", served_actions,
                                        "--render-cameras", CAMERAS, "--image-size", "320x240", "--envs", str(args.envs),
                                        "--out", out] + common))
            if records(out) != reference:
                sys.exit(f"{out}: the replay's records differ from the served cell's")
            print(f"run {attempt} replay: {times['replay'][-1]:.1f} s", flush=True)
    finally:
        server.terminate()
        server.wait(timeout=10)

    replay = statistics.median(times["replay"])
    result = {"runs": args.runs, "episodes": args.episodes, "envs": args.envs, "sleep_ms": args.sleep_ms,
              "horizon": args.horizon, "replay_median_s": replay, "successes": sum(r[1] for r in reference), "modes": {}}
    print(f"\nreplay (no server): median {replay:.1f} s of {times['replay']}")
    for mode in args.serving:
        median = statistics.median(times[mode])
        requests = details[mode]["requests"]
        result["modes"][mode] = {"median_s": median, "times_s": times[mode], "ratio_to_replay": median / replay,
                                 "requests": requests["count"], "env_requests": requests["env_requests"],
                                 "mean_batch_size": requests["mean_batch_size"], "policy_ticks": requests["policy_ticks"],
                                 "wait_s": requests["wait_s"], "rest_s": details[mode]["wall_s"] - requests["wait_s"]}
        entry = result["modes"][mode]
        print(f"{mode}: median {median:.1f} s of {times[mode]}, {median / replay:.2f}x the replay; "
              f"{entry['requests']} requests for {entry['env_requests']} env requests (mean batch {entry['mean_batch_size']:.1f}); "
              f"last run: {entry['wait_s']:.1f} s waiting for replies, {entry['rest_s']:.1f} s the rest")
    with open(os.path.join(args.out, "summary.json"), "w") as file:
        json.dump(result, file, indent=2)


if __name__ == "__main__":
    main()
