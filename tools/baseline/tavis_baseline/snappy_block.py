"""Decompression of Snappy's raw block format (the body of a SNAPPY Parquet page), in pure Python.

The trainer must run wherever PyTorch runs, and neither Debian's Python nor a bare CUDA image is
guaranteed to have a snappy binding, so the ~40 lines of the format are written out here. A
dataset's Parquet is small (tens of MB for hundreds of episodes), so speed does not matter.
"""


def _varint(data, pos):
    value = shift = 0
    while True:
        if pos >= len(data):
            raise ValueError("snappy: truncated length varint")
        byte = data[pos]
        pos += 1
        value |= (byte & 0x7F) << shift
        if byte < 0x80:
            return value, pos
        shift += 7


def decompress(data):
    """The bytes `data` (a raw Snappy block) expands to; ValueError for corrupt input."""
    data = memoryview(bytes(data))
    expected, pos = _varint(data, 0)
    out = bytearray()
    end = len(data)
    while pos < end:
        tag = data[pos]
        pos += 1
        kind = tag & 3
        if kind == 0:  # literal: length-1 in the tag, or in 1-4 following bytes
            length = tag >> 2
            if length >= 60:
                extra = length - 59
                length = int.from_bytes(data[pos:pos + extra], "little")
                pos += extra
            length += 1
            if pos + length > end:
                raise ValueError("snappy: literal runs past the end of the block")
            out += data[pos:pos + length]
            pos += length
            continue
        if kind == 1:
            length = 4 + ((tag >> 2) & 7)
            offset = ((tag >> 5) << 8) | data[pos]
            pos += 1
        elif kind == 2:
            length = (tag >> 2) + 1
            offset = int.from_bytes(data[pos:pos + 2], "little")
            pos += 2
        else:
            length = (tag >> 2) + 1
            offset = int.from_bytes(data[pos:pos + 4], "little")
            pos += 4
        if offset == 0 or offset > len(out):
            raise ValueError(f"snappy: copy offset {offset} outside the {len(out)} bytes written")
        start = len(out) - offset
        if offset >= length:
            out += out[start:start + length]
        else:  # the copy overlaps what it writes: repeat the last `offset` bytes
            pattern = bytes(out[start:])
            repeats, rest = divmod(length, offset)
            out += pattern * repeats + pattern[:rest]
    if len(out) != expected:
        raise ValueError(f"snappy: block expands to {len(out)} bytes, its header says {expected}")
    return bytes(out)
