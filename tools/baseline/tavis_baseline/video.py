"""Decoding a dataset's mp4 files into uint8 RGB frames at the training resolution.

PyAV (Debian's python3-av here) when it is importable, else OpenCV (common on GPU machines):
both decode the H.264 that `tavis demos` writes by default. Frames are resized by the decoder's
scaler only when the requested size differs from the video's.
"""


def available_backends():
    """The decoders importable here, in the order of preference."""
    names = []
    for name, module in (("pyav", "av"), ("opencv", "cv2")):
        try:
            __import__(module)
        except ImportError:
            continue
        names.append(name)
    return names


def decode_into(path, fps, frame_rows, out, backend=None):
    """Decodes `path` and writes its frame k into out[frame_rows[k]] for every k with frame_rows[k] >= 0.

    frame_rows: int64 array over the file's frames (the dataset row of each, -1 for none);
    out: the (rows, height, width, 3) uint8 array of every frame of the camera, filled in place;
    backend: "pyav", "opencv" or None (the first of available_backends()).
    """
    size = out.shape[1:3]
    if backend is None:
        backends = available_backends()
        if not backends:
            raise ValueError(f"{path}: no video decoder: install PyAV (python3-av) or OpenCV (python3-opencv)")
        backend = backends[0]
    if backend == "pyav":
        count = _decode_pyav(path, fps, frame_rows, size, out)
    elif backend == "opencv":
        count = _decode_opencv(path, frame_rows, size, out)
    else:
        raise ValueError(f"unknown video backend {backend!r} (pyav or opencv)")
    if count < frame_rows.size:
        raise ValueError(f"{path}: holds {count} frames, the episodes table needs {frame_rows.size}")


def _store(out, frame_rows, k, rgb):
    if k < frame_rows.size and frame_rows[k] >= 0:
        out[frame_rows[k]] = rgb


def _decode_pyav(path, fps, frame_rows, size, out):
    import av

    height, width = size
    count = 0
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        stream.thread_type = "AUTO"
        for frame in container.decode(stream):
            # The frame's place in the file from its timestamp (pts k/fps), as LeRobot looks it up.
            k = int(round(float(frame.pts * stream.time_base) * fps)) if frame.pts is not None else count
            if frame.width == width and frame.height == height:
                rgb = frame.to_ndarray(format="rgb24")
            else:
                rgb = frame.to_ndarray(format="rgb24", width=width, height=height)
            _store(out, frame_rows, k, rgb)
            count += 1
    return count


def _decode_opencv(path, frame_rows, size, out):
    import cv2

    height, width = size
    capture = cv2.VideoCapture(str(path))
    if not capture.isOpened():
        raise ValueError(f"{path}: OpenCV cannot open it")
    count = 0
    while True:
        ok, bgr = capture.read()
        if not ok:
            break
        if bgr.shape[:2] != (height, width):
            bgr = cv2.resize(bgr, (width, height), interpolation=cv2.INTER_AREA)
        _store(out, frame_rows, count, bgr[:, :, ::-1])
        count += 1
    capture.release()
    return count
