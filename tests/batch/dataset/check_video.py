"""An independent reader of our mp4 files: Debian's PyAV 10 (python3-av), run with /usr/bin/python3.

Usage: check_video.py VIDEO FPS [FROM_TIMESTAMP FRAME_INDEX OUT_RGB_PATH]...

Prints JSON describing the first video stream (decoder, pix_fmt, size, rates, stream duration,
the pts in seconds of every decoded frame, the keyframe flag of every packet). Each query triple
replays LeRobot's PyAV lookup (video_utils.py, tolerance 1e-4 s, float32 timestamps): seek
backward to the keyframe at or before from_timestamp + frame_index / fps, decode forward to the
frame within the tolerance, and write it as raw rgb24 bytes to OUT_RGB_PATH. A query that finds
no frame is reported with "found": false (LeRobot would raise).
"""

import json
import sys

import av
import numpy as np

TOLERANCE_S = 1e-4


def describe(path):
    with av.open(path) as container:
        stream = container.streams.video[0]
        time_base = stream.time_base
        packets = [packet for packet in container.demux(stream) if packet.size > 0]
        keyframe_flags = [bool(packet.is_keyframe) for packet in packets]
        packet_pts_s = [float(packet.pts * time_base) for packet in packets]
    with av.open(path) as container:
        stream = container.streams.video[0]
        frame_pts_s = [float(frame.pts * time_base) for frame in container.decode(stream)]
        context = stream.codec_context
        return {
            "decoder": context.name,
            "pix_fmt": context.pix_fmt,
            "width": context.width,
            "height": context.height,
            "average_rate": str(stream.average_rate),
            "guessed_rate": str(stream.guessed_rate),
            "base_rate": str(stream.base_rate),
            "duration_s": float(stream.duration * time_base),
            "frame_count": len(frame_pts_s),
            "frame_pts_s": frame_pts_s,
            "packet_pts_s": packet_pts_s,
            "keyframes": keyframe_flags,
        }


def lookup(path, query_s, out_path):
    """LeRobot's decode_video_frames_pyav for one timestamp."""
    with av.open(path) as container:
        stream = container.streams.video[0]
        time_base = stream.time_base
        container.seek(int(query_s / time_base), backward=True, any_frame=False, stream=stream)
        decoded = 0
        first_pts_s = None
        for frame in container.decode(stream):
            pts_s = float(frame.pts * time_base)
            if first_pts_s is None:
                first_pts_s = pts_s
            decoded += 1
            if abs(pts_s - query_s) <= TOLERANCE_S:
                with open(out_path, "wb") as out:
                    out.write(frame.to_ndarray(format="rgb24").tobytes())
                return {"query_s": query_s, "found": True, "pts_s": pts_s,
                        "seek_landed_s": first_pts_s, "decoded": decoded}
            if pts_s > query_s + TOLERANCE_S:
                break
        return {"query_s": query_s, "found": False, "seek_landed_s": first_pts_s, "decoded": decoded}


def main():
    path, fps = sys.argv[1], int(sys.argv[2])
    queries = sys.argv[3:]
    report = describe(path)
    report["lookups"] = []
    for i in range(0, len(queries), 3):
        from_timestamp = float(queries[i])
        # LeRobot stores timestamp = frame_index / fps as float32.
        timestamp = float(np.float32(int(queries[i + 1]) / fps))
        report["lookups"].append(lookup(path, from_timestamp + timestamp, queries[i + 2]))
    print(json.dumps(report))


if __name__ == "__main__":
    main()
