"""Acceptance of episode videos (issue 30): `tavis eval --videos N` films the first N episodes of a
cell as MP4s that PyAV (a decoder we did not write) decodes with the right frame count (the
episode's policy steps, then the end held one second) and size, without changing a byte of the
records; a served episode re-rendered from its saved actions (`--policy replay --episode I
--videos 1`) gives the same record and the same video, and any camera and size as PNGs; a sweep
films its cells; `--record DIR` writes the served cell's rollouts as a LeRobot dataset whose
videos PyAV decodes and whose tavis_rollouts.jsonl holds the cell's records; bad video and record
options are refused by name before anything is written.

    /usr/bin/python3 eval_videos_test.py TAVIS_BINARY SOURCE_DIR
"""

import glob
import json
import os
import shutil
import sys
import tempfile

import av

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from tool_script_support import check, failures, passed_count, run, start_replay_server  # noqa: E402

TAVIS, SOURCE = sys.argv[1], sys.argv[2]
SEED = "3"
OUTCOME_FRAMES = 20  # the end held one second at 20 fps (episode_videos.h)
# Four 320x240 tiles in two columns with 4-pixel margins, under the caption band.
FRAME_WIDTH = 2 * 320 + 3 * 4
def records(cell):
    with open(os.path.join(cell, "episodes.jsonl"), "rb") as lines:
        return [json.loads(line) for line in lines]


def decode(path):
    with av.open(path) as container:
        stream = container.streams.video[0]
        rate = stream.average_rate
        frames = [frame for frame in container.decode(video=0)]
    return frames, rate


def check_videos(cell, count, what):
    names = sorted(os.listdir(os.path.join(cell, "videos")))
    check(names == [f"episode_{i}.mp4" for i in range(count)], f"{what}: videos {names}")
    heights = set()
    for record in records(cell)[:count]:
        frames, rate = decode(os.path.join(cell, "videos", f"episode_{record['episode']}.mp4"))
        check(len(frames) == record["length_steps"] + OUTCOME_FRAMES,
              f"{what} episode {record['episode']}: {len(frames)} frames, {record['length_steps']} steps")
        check(rate == 20, f"{what}: {rate} fps")
        check(all(frame.width == FRAME_WIDTH for frame in frames), f"{what}: width {frames[0].width}")
        heights.update(frame.height for frame in frames)
        # The scene is lit and moves: the first and last frames differ.
        first, last = frames[0].to_ndarray(format="rgb24"), frames[-1].to_ndarray(format="rgb24")
        check(first.mean() > 40 and abs(first.astype(int) - last.astype(int)).mean() > 1,
              f"{what}: first frame mean {first.mean():.1f}, mean change {abs(first.astype(int) - last.astype(int)).mean():.2f}")
    check(len(heights) == 1 and min(heights) > 2 * 240, f"{what}: heights {heights}")
    return heights


def check_rollout_dataset(root, cell):
    with open(os.path.join(root, "meta", "info.json")) as text:
        info = json.load(text)
    steps = [record["length_steps"] for record in records(cell)]
    check(info["total_episodes"] == len(steps) and info["total_frames"] == sum(steps) and info["fps"] == 20,
          f"rollout dataset: {info['total_episodes']} episodes, {info['total_frames']} frames, fps {info['fps']}; steps {steps}")
    videos = sorted(glob.glob(os.path.join(root, "videos", "*", "chunk-000", "file-000.mp4")))
    check(len(videos) == 3, f"rollout dataset videos {videos}")
    for path in videos:
        frames, rate = decode(path)
        check(len(frames) == sum(steps) and frames[0].width == 320 and frames[0].height == 240 and rate == 20,
              f"{path}: {len(frames)} frames {frames[0].width}x{frames[0].height} at {rate}")
    with open(os.path.join(root, "tavis_rollouts.jsonl")) as lines:
        rollouts = [json.loads(line) for line in lines]
    check([entry.pop("episode_index") for entry in rollouts] == list(range(len(steps))), "rollout episode indices")
    check(rollouts == records(cell), "tavis_rollouts.jsonl differs from the cell's records")


def serve(actions):
    return start_replay_server(SOURCE, actions, lifetime=600)


def main():
    work = tempfile.mkdtemp(prefix="tavis_eval_videos_")
    try:
        cell = ["--task", "clutter-pick-cube", "--robot", "gr1t2", "--seed", SEED, "--quiet"]
        # 1. The expert at 20 Hz (its actions saved for replay), filmed and not.
        filmed, plain = os.path.join(work, "filmed"), os.path.join(work, "plain")
        run([TAVIS, "eval", *cell, "--episodes", "3", "--expert-hz", "20", "--videos", "2", "--out", filmed])
        run([TAVIS, "eval", *cell, "--episodes", "3", "--expert-hz", "20", "--out", plain])
        with open(os.path.join(filmed, "episodes.jsonl"), "rb") as a, open(os.path.join(plain, "episodes.jsonl"), "rb") as b:
            check(a.read() == b.read(), "episodes.jsonl differs with --videos")
        check_videos(filmed, 2, "expert cell")

        # --overwrite builds the new cell beside the old one and swaps it in at its first record:
        # the frames written before the swap move with it (PNGs), the rest follow it.
        run([TAVIS, "eval", *cell, "--episodes", "3", "--expert-hz", "20", "--videos", "1", "--video-format", "png",
             "--video-size", "64x48", "--overwrite", "--out", filmed])
        pngs = sorted(glob.glob(os.path.join(filmed, "videos", "*", "frame_*.png")))
        check(os.listdir(os.path.join(filmed, "videos")) == ["episode_0"] and
              len(pngs) == records(filmed)[0]["length_steps"] + 1,
              f"--overwrite --videos: {os.listdir(os.path.join(filmed, 'videos'))}, {len(pngs)} PNGs")
        check(not [name for name in os.listdir(work) if name.startswith(".filmed")], f"staging left behind: {os.listdir(work)}")

        # 2. A served cell (the stand-in server answers the expert's saved rows), filmed.
        server, url = serve(os.path.join(filmed, "actions"))
        served = os.path.join(work, "served")
        try:
            run([TAVIS, "eval", *cell, "--episodes", "2", "--policy", "openpi", "--server", url, "--replan-steps", "1",
                 "--videos", "2", "--record", os.path.join(work, "rollouts"), "--out", served])
        finally:
            server.kill()
            server.wait()
        check_videos(served, 2, "served cell")
        check_rollout_dataset(os.path.join(work, "rollouts"), served)

        # 3. Its episode 1 re-rendered from its CSV: the same record, the same video.
        replayed = os.path.join(work, "replayed")
        run([TAVIS, "eval", *cell, "--policy", "replay", "--actions", os.path.join(served, "actions"), "--episode", "1",
             "--videos", "1", "--out", replayed])
        check(records(replayed) == [records(served)[1]], f"replayed record {records(replayed)} != {records(served)[1]}")
        with open(os.path.join(replayed, "videos", "episode_1.mp4"), "rb") as a, \
                open(os.path.join(served, "videos", "episode_1.mp4"), "rb") as b:
            check(a.read() == b.read(), "the re-rendered video differs from the served cell's")

        # 4. Any camera at any size, as PNGs: one per policy step, then the end.
        pngs = os.path.join(work, "pngs")
        run([TAVIS, "eval", *cell, "--policy", "replay", "--actions", os.path.join(served, "actions"), "--episode", "1",
             "--videos", "1", "--video-format", "png", "--video-cameras", "right_wrist", "--video-size", "640x480",
             "--out", pngs])
        frames = sorted(glob.glob(os.path.join(pngs, "videos", "episode_1", "frame_*.png")))
        check(len(frames) == records(served)[1]["length_steps"] + 1, f"{len(frames)} PNGs")
        with av.open(frames[-1]) as image:
            frame = next(image.decode(video=0))
        check(frame.width == 640 + 2 * 4 and frame.height > 480, f"PNG {frame.width}x{frame.height}")

        # 5. The fixed protocol: the fixed camera and the wrists.
        fixed = os.path.join(work, "fixed")
        run([TAVIS, "eval", *cell, "--camera", "fixed", "--episodes", "1", "--videos", "1", "--out", fixed])
        check_videos(fixed, 1, "fixed cell")

        # 6. A sweep's `videos:` key films every cell.
        spec = os.path.join(work, "spec.yaml")
        with open(spec, "w") as text:
            text.write("tasks: [clutter-pick-cube]\nrobots: [gr1t2]\nsplits: [id]\ncameras: [head, fixed]\nseeds: [3]\n"
                       "episodes: 2\nvideos: 1\npolicy:\n  name: expert\n")
        sweep = os.path.join(work, "sweep")
        run([TAVIS, "sweep", spec, "--out", sweep, "--quiet"])
        for camera in ("head", "fixed"):
            check_videos(os.path.join(sweep, "cells", f"clutter-pick-cube_gr1t2_id_{camera}_expert_s3"), 1, f"sweep {camera}")

        # 7. --record refuses a folder with files in it, and --resume.
        result = run([TAVIS, "eval", *cell, "--episodes", "1", "--record", filmed, "--out", os.path.join(work, "r1")],
                     expect_ok=False)
        check(result.returncode != 0 and filmed in result.stderr and "already holds files" in result.stderr,
              f"--record into a full folder: exit {result.returncode}, {result.stderr.strip()}")
        result = run([TAVIS, "eval", *cell, "--episodes", "1", "--record", os.path.join(work, "r2"), "--resume", "--out", plain],
                     expect_ok=False)
        check(result.returncode != 0 and "--resume" in result.stderr and not os.path.exists(os.path.join(work, "r2")),
              f"--record --resume: exit {result.returncode}, {result.stderr.strip()}")

        # 8. Bad video options: refused by name, nothing written.
        for args, named in ((["--videos", "1", "--video-size", "101x80"], "101x80"),
                            (["--videos", "1", "--video-format", "gif"], "gif"),
                            (["--videos", "1", "--video-cameras", "belly"], "belly"),
                            (["--video-size", "320x240"], "--videos")):
            out = os.path.join(work, "refused")
            result = run([TAVIS, "eval", *cell, "--episodes", "1", *args, "--out", out], expect_ok=False)
            check(result.returncode != 0 and named in result.stderr and not os.path.exists(out),
                  f"{args}: exit {result.returncode}, {result.stderr.strip()}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"{passed_count()} checks passed, {len(failures)} failed")
    sys.exit(1 if failures else 0)


main()
