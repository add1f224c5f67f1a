"""A rendered expert cell recorded with `tavis eval --record` gives the same records and the same
dataset, byte for byte (parquet tables, mp4 files, tavis_rollouts.jsonl), whether its slots run
per slot on 1 or 2 threads (each slot's frames rendered and encoded on its own thread) or
lock-step (`--videos` needs the common tick); the frames are real images: PyAV, a decoder we did
not write, decodes one per policy step of every episode, lit and changing.

    /usr/bin/python3 record_schedules_test.py TAVIS_BINARY
"""

import glob
import json
import os
import shutil
import sys
import tempfile

import av

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from tool_script_support import check, failures, passed_count, run  # noqa: E402

TAVIS = sys.argv[1]


def files(root):
    """Every file of a dataset by its relative path (the output lock and marker left out)."""
    found = {}
    for path in glob.glob(os.path.join(root, "**", "*"), recursive=True):
        name = os.path.relpath(path, root)
        if os.path.isfile(path) and not os.path.basename(name).startswith(".tavis"):
            with open(path, "rb") as data:
                found[name] = data.read()
    return found


def main():
    work = tempfile.mkdtemp(prefix="tavis_record_schedules_")
    try:
        cell = ["eval", "--task", "clutter-pick-cube", "--robot", "gr1t2", "--seed", "2", "--episodes", "3",
                "--render-cameras", "head,left_wrist", "--image-size", "64x48", "--record-cameras",
                "head,left_wrist", "--record-size", "64x48", "--quiet"]
        runs = {"per_slot_1": ["--threads", "1"], "per_slot_2": ["--threads", "2", "--envs", "2"],
                "lock_step_2": ["--threads", "2", "--videos", "1", "--video-size", "64x48"],
                "lock_step_1": ["--threads", "1", "--videos", "1", "--video-size", "64x48"]}
        for name, args in runs.items():
            run([TAVIS, *cell, *args, "--record", os.path.join(work, name + "_dataset"),
                 "--out", os.path.join(work, name)])
        with open(os.path.join(work, "per_slot_1", "episodes.jsonl"), "rb") as text:
            reference_records = text.read()
        records = [json.loads(line) for line in reference_records.splitlines()]
        check(len(records) == 3 and all(record["success"] for record in records), f"records {records}")
        reference = files(os.path.join(work, "per_slot_1_dataset"))
        videos = sorted(name for name in reference if name.endswith(".mp4"))
        check(len(videos) == 2 and any(name.endswith(".parquet") for name in reference), f"dataset files {sorted(reference)}")
        for name in runs:
            if name == "per_slot_1":
                continue
            with open(os.path.join(work, name, "episodes.jsonl"), "rb") as text:
                check(text.read() == reference_records, f"{name}: episodes.jsonl differs from per_slot_1's")
            other = files(os.path.join(work, name + "_dataset"))
            check(sorted(other) == sorted(reference), f"{name}: files {sorted(other)}")
            for path, data in reference.items():
                check(other.get(path) == data, f"{name}: {path} differs from per_slot_1's")
        steps = sum(record["length_steps"] for record in records)
        for video in videos:
            with av.open(os.path.join(work, "per_slot_1_dataset", video)) as container:
                frames = [frame.to_ndarray(format="rgb24") for frame in container.decode(video=0)]
            check(len(frames) == steps, f"{video}: {len(frames)} frames for {steps} policy steps")
            change = max(abs(frame.astype(int) - frames[0].astype(int)).mean() for frame in frames)
            check(frames[0].mean() > 20 and change > 1,
                  f"{video}: first frame mean {frames[0].mean():.1f}, largest mean change from it {change:.2f}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"{passed_count()} checks passed, {len(failures)} failed")
    sys.exit(1 if failures else 0)


main()
