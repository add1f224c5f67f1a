#!/usr/bin/env python3
"""Overhead of the Python module: env-steps/s of a Python loop stepping 32 envs of
clutter-pick-cube with a trivial policy and 3 cameras at 224x224, against the same work stepped
from C++ (bench/python_overhead_bench.cc). Runs the two alternately and prints the medians; the
target is the Python loop at most 10% slower (docs/python.md).

  PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py --cxx build/bench/tavis_python_overhead_bench
"""

import argparse
import json
import statistics
import subprocess
import time

import tavis

ENVS = 32


def python_steps_per_s(seconds, threads):
    env = tavis.make_vec("clutter-pick-cube", num_envs=ENVS, seed=0, cameras=("head", "left_wrist", "right_wrist"),
                         image_size=(224, 224), threads=threads)
    env.reset()
    actions = env.make_policy("hold")()  # the trivial policy: its first actions, held
    for _ in range(3):
        env.step(actions)
    steps = 0
    start = time.perf_counter()
    while time.perf_counter() - start < seconds:
        observation, rewards, terminated, truncated, infos = env.step(actions)
        steps += 1
    return ENVS * steps / (time.perf_counter() - start)


def python_side_us(repeats=2000):
    """Microseconds per step spent in Python around the C++ step (building the observation views
    and the infos): the overhead itself, which the machine's load does not hide."""
    env = tavis.make_vec("clutter-pick-cube", num_envs=ENVS, seed=0, cameras=("head", "left_wrist", "right_wrist"),
                         image_size=(224, 224))
    env.reset()
    env.step(env.make_policy("hold")())
    start = time.perf_counter()
    for _ in range(repeats):
        env._observation(), env._core.rewards(), env._core.terminated(), env._core.truncated(), env._infos()
    return 1e6 * (time.perf_counter() - start) / repeats


def cxx_steps_per_s(program, seconds):
    output = subprocess.run([program, f"--benchmark_min_time={seconds}", "--benchmark_format=json"], check=True,
                            capture_output=True, text=True).stdout
    return json.loads(output)["benchmarks"][0]["items_per_second"]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cxx", required=True, help="the tavis_python_overhead_bench program")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--seconds", type=float, default=3.0, help="timed seconds per run (at least)")
    args = parser.parse_args()
    python, cxx = [], []
    for round_index in range(args.rounds):
        cxx.append(cxx_steps_per_s(args.cxx, args.seconds))
        python.append(python_steps_per_s(args.seconds, threads=0))
        print(f"round {round_index + 1}: C++ {cxx[-1]:.1f} env-steps/s, Python {python[-1]:.1f} env-steps/s", flush=True)
    overhead_us = python_side_us()
    cxx_median, python_median = statistics.median(cxx), statistics.median(python)
    print(f"median: C++ {cxx_median:.1f}, Python {python_median:.1f} env-steps/s; "
          f"Python is {100.0 * (1.0 - python_median / cxx_median):+.1f}% slower (target <= 10%)")
    step_us = 1e6 * ENVS / cxx_median
    print(f"Python's own work per step: {overhead_us:.0f} us of a {step_us:.0f} us step "
          f"({100.0 * overhead_us / step_us:.2f}%)")


if __name__ == "__main__":
    main()
