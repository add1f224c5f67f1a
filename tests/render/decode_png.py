#!/usr/bin/python3
"""Decodes a PNG file with PyAV (FFmpeg's PNG decoder, not libpng) and writes its pixels as raw
8-bit RGB rows, so that a test can compare what WritePng wrote with what another reader sees.

usage: decode_png.py PNG OUT_RGB   (prints {"width": W, "height": H, "format": F} as JSON)
"""
import json
import sys

import av

if len(sys.argv) != 3:
    sys.exit(__doc__)
with av.open(sys.argv[1]) as container:
    frame = next(container.decode(video=0))
    source_format = frame.format.name
    pixels = frame.to_ndarray(format="rgb24")
with open(sys.argv[2], "wb") as out:
    out.write(pixels.tobytes())
print(json.dumps({"width": frame.width, "height": frame.height, "format": source_format}))
