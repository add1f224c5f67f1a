"""A minimal Parquet column reader for the files `tavis demos` writes, in pure Python + numpy.

Why not pyarrow: Debian has none, and the trainer must not depend on it. Why not the project's C++
reader (batch/dataset/parquet): the compiled `tavis` module is built for one interpreter on one
machine, while the trainer runs on GPU machines with their own Python. What tavis writes is a
small subset of Parquet (batch/dataset/parquet/parquet_writer.h): data pages v1, PLAIN values, RLE
levels, no nulls, UNCOMPRESSED or SNAPPY. That subset takes ~150 lines to read; anything outside
it (dictionary or v2 pages, other encodings or codecs, nulls) raises ValueError naming the file
and column instead of returning wrong numbers.

    table = ParquetFile(path)
    table.column("episode_index")          # int64 array, one value per row
    table.column("action", width=19)       # float32 array of shape (rows, 19)
"""

import struct

import numpy as np

from . import snappy_block

_PHYSICAL = {1: np.dtype("<i4"), 2: np.dtype("<i8"), 4: np.dtype("<f4"), 5: np.dtype("<f8")}
_REPEATED, _OPTIONAL = 2, 1
_CODEC_NAMES = {0: "UNCOMPRESSED", 1: "SNAPPY", 2: "GZIP", 3: "LZO", 4: "BROTLI", 5: "LZ4", 6: "ZSTD", 7: "LZ4_RAW"}


class _Thrift:
    """The thrift compact protocol, read into {field id: value} dicts (enough for the footer)."""

    def __init__(self, data, pos=0):
        self.data = data
        self.pos = pos

    def _byte(self):
        byte = self.data[self.pos]
        self.pos += 1
        return byte

    def _varint(self):
        value = shift = 0
        while True:
            byte = self._byte()
            value |= (byte & 0x7F) << shift
            if byte < 0x80:
                return value
            shift += 7

    def _zigzag(self):
        n = self._varint()
        return (n >> 1) ^ -(n & 1)

    def _value(self, kind):
        if kind in (1, 2):  # a bool inside a list/set: one byte
            return self._byte() == 1
        if kind == 3:
            return struct.unpack("b", bytes([self._byte()]))[0]
        if kind in (4, 5, 6):
            return self._zigzag()
        if kind == 7:
            value = struct.unpack_from("<d", self.data, self.pos)[0]
            self.pos += 8
            return value
        if kind == 8:
            length = self._varint()
            value = bytes(self.data[self.pos:self.pos + length])
            self.pos += length
            return value
        if kind in (9, 10):
            header = self._byte()
            size = header >> 4
            if size == 15:
                size = self._varint()
            return [self._value(header & 0x0F) for _ in range(size)]
        if kind == 11:
            size = self._varint()
            if size == 0:
                return {}
            types = self._byte()
            return {self._value(types >> 4): self._value(types & 0x0F) for _ in range(size)}
        if kind == 12:
            return self.struct()
        raise ValueError(f"thrift: unknown type {kind}")

    def struct(self):
        fields = {}
        last = 0
        while True:
            header = self._byte()
            if header == 0:
                return fields
            delta = header >> 4
            field = last + delta if delta else self._zigzag()
            kind = header & 0x0F
            fields[field] = kind == 1 if kind in (1, 2) else self._value(kind)
            last = field


class ParquetFile:
    def __init__(self, path):
        self.path = str(path)
        with open(self.path, "rb") as stream:
            self._data = stream.read()
        data = self._data
        if len(data) < 12 or data[:4] != b"PAR1" or data[-4:] != b"PAR1":
            raise ValueError(f"{self.path}: not a Parquet file (no PAR1 magic)")
        footer_size = struct.unpack("<I", data[-8:-4])[0]
        if footer_size > len(data) - 12:
            raise ValueError(f"{self.path}: footer of {footer_size} bytes is larger than the file")
        meta = _Thrift(data, len(data) - 8 - footer_size).struct()
        self.num_rows = meta[3]
        self._row_groups = meta.get(4, [])
        self._leaves = self._leaf_levels(meta[2])

    @staticmethod
    def _leaf_levels(schema):
        """{top-level column name: (leaf index, physical type, max def level, max rep level)}."""
        leaves = {}
        counter = [0]

        def walk(index, top, max_def, max_rep):
            element = schema[index]
            repetition = element.get(3, 0)
            max_def += repetition in (_OPTIONAL, _REPEATED)
            max_rep += repetition == _REPEATED
            name = element[4].decode()
            top = top or name
            children = element.get(5, 0)
            index += 1
            if children == 0:
                leaves.setdefault(top, (counter[0], element.get(1), max_def, max_rep))
                counter[0] += 1
                return index
            for _ in range(children):
                index = walk(index, top, max_def, max_rep)
            return index

        index = 1
        for _ in range(schema[0].get(5, 0)):
            index = walk(index, None, 0, 0)
        return leaves

    def column_names(self):
        return list(self._leaves)

    def column(self, name, width=None):
        """Column `name`: a 1-D array, or (rows, width) for a list column of `width` items per row."""
        if name not in self._leaves:
            raise ValueError(f"{self.path} has no column {name!r} (it has {', '.join(self._leaves)})")
        leaf, physical, max_def, max_rep = self._leaves[name]
        if physical not in _PHYSICAL:
            raise ValueError(f"{self.path}: column {name!r} has physical type {physical}, which this reader does not read")
        dtype = _PHYSICAL[physical]
        parts = [self._read_chunk(group[1][leaf][3], name, dtype, max_def, max_rep) for group in self._row_groups]
        values = np.concatenate(parts) if parts else np.zeros(0, dtype)
        rows = self.num_rows
        if width is None:
            if values.size != rows:
                raise ValueError(f"{self.path}: column {name!r} holds {values.size} values for {rows} rows")
            return values
        if values.size != rows * width:
            raise ValueError(f"{self.path}: column {name!r} holds {values.size} values, not {rows} rows x {width}")
        return values.reshape(rows, width)

    def _read_chunk(self, meta, name, dtype, max_def, max_rep):
        where = f"{self.path}, column {name!r}"
        codec = meta[4]
        if codec not in (0, 1):
            raise ValueError(f"{where}: unsupported codec {_CODEC_NAMES.get(codec, codec)}")
        if 11 in meta:
            raise ValueError(f"{where}: dictionary-encoded column chunks are not read by this reader")
        remaining = meta[5]
        pos = meta[9]
        out = []
        while remaining > 0:
            reader = _Thrift(self._data, pos)
            header = reader.struct()
            body_start = reader.pos
            body = self._data[body_start:body_start + header[3]]
            pos = body_start + header[3]
            if header[1] != 0:
                raise ValueError(f"{where}: page type {header[1]} (only v1 data pages are read)")
            page = header[5]
            if page.get(2, 0) != 0:
                raise ValueError(f"{where}: value encoding {page.get(2)} (only PLAIN is read)")
            if codec == 1:
                body = snappy_block.decompress(body)
            if len(body) != header[2]:
                raise ValueError(f"{where}: page body is {len(body)} bytes, its header says {header[2]}")
            offset = 0
            for present in (max_rep > 0, max_def > 0):  # rep then def levels, each length-prefixed
                if present:
                    offset += 4 + struct.unpack_from("<I", body, offset)[0]
            count = page[1]
            values = np.frombuffer(body, dtype, count=(len(body) - offset) // dtype.itemsize, offset=offset)
            if values.size != count:  # fewer values than level entries: nulls or empty lists
                raise ValueError(f"{where}: page has {values.size} values for {count} entries (nulls are not read)")
            out.append(values)
            remaining -= count
        return np.concatenate(out) if len(out) != 1 else out[0]
