"""Snappy raw-block decoding on hand-made blocks (real SNAPPY pages are covered by the Parquet test)."""

import pytest

from tavis_baseline.snappy_block import decompress


def test_literal_then_overlapping_copy():
    # 13 bytes: literal "abc" (tag (3-1)<<2), then a 1-byte-offset copy of length 10 at offset 3,
    # which overlaps what it writes (tag 1 | (10-4)<<2).
    block = bytes([13, 0x08]) + b"abc" + bytes([0x01 | (6 << 2), 3])
    assert decompress(block) == b"abcabcabcabca"


def test_two_byte_offset_copy():
    literal = b"0123456789"
    block = bytes([14, (10 - 1) << 2]) + literal + bytes([0x02 | ((4 - 1) << 2), 10, 0])
    assert decompress(block) == literal + b"0123"


@pytest.mark.parametrize("block, message", [
    (bytes([5, 0x08]) + b"abc", "header says 5"),
    (bytes([4, 0x01 | (0 << 2), 9]), "offset 9"),
    (bytes([9, 0x20]) + b"ab", "past the end"),
])
def test_corrupt_blocks_are_refused(block, message):
    with pytest.raises(ValueError, match=message):
        decompress(block)
