"""openpi's msgpack-numpy wire format (numpy arrays as maps with msgpack *bin* keys), on Debian's
python3-msgpack. Written from the format's description; the tests decode it with the test
directory's independent copy (tests/batch/remote/openpi_msgpack_numpy.py).

Decoding is the server's first contact with a peer's bytes, so it trusts nothing: an array is
built only from a dtype on a short list of numeric and bool types (by their exact `dtype.str`,
so no peer-chosen string reaches numpy's dtype parser), a shape of at most MAX_RANK non-negative
ints, and a bin whose length is exactly the shape's bytes. An object dtype would otherwise make
numpy read the peer's bytes as object pointers (a crash, or worse, once torch touches the batch);
a structured, string, datetime or complex dtype is nothing a policy reads. Anything else raises
ValueError naming the bad value."""

import math

import msgpack
import numpy as np

# Native (little-endian here) numeric and bool dtypes, by the `dtype.str` openpi's encoder and the
# tavis client send ("<f4", "|u1", "|b1", ...). Complex is left out: no policy input is complex.
ACCEPTED_DTYPES = {np.dtype(name).str: np.dtype(name) for name in (
    "bool", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
    "float16", "float32", "float64")}
MAX_RANK = 32  # numpy's own limit (NPY_MAXDIMS in numpy 1.x)


def _encode(obj):
    if isinstance(obj, (np.ndarray, np.generic)) and obj.dtype.kind in ("V", "O", "c"):
        raise ValueError(f"cannot send numpy dtype {obj.dtype} over msgpack-numpy")
    if isinstance(obj, np.ndarray):
        array = np.ascontiguousarray(obj)
        return {b"__ndarray__": True, b"data": array.tobytes(), b"dtype": array.dtype.str, b"shape": array.shape}
    if isinstance(obj, np.generic):
        return {b"__npgeneric__": True, b"data": obj.item(), b"dtype": obj.dtype.str}
    return obj


def _accepted_dtype(text, what):
    if not isinstance(text, str) or text not in ACCEPTED_DTYPES:
        raise ValueError(f"{what} dtype {text!r} is not accepted; only {', '.join(ACCEPTED_DTYPES)}")
    return ACCEPTED_DTYPES[text]


def _shape(value):
    if not isinstance(value, (list, tuple)) or len(value) > MAX_RANK or not all(
            isinstance(size, int) and not isinstance(size, bool) and size >= 0 for size in value):
        raise ValueError(f"ndarray shape {value!r} is not a list of at most {MAX_RANK} non-negative ints")
    return tuple(value)


def _decode_ndarray(obj):
    dtype = _accepted_dtype(obj.get(b"dtype"), "ndarray")
    shape = _shape(obj.get(b"shape"))
    data = obj.get(b"data")
    if not isinstance(data, bytes):
        raise ValueError(f"ndarray data is a {type(data).__name__}, not a msgpack bin")
    expected = math.prod(shape) * dtype.itemsize  # Python ints: no overflow for absurd shapes
    if len(data) != expected:
        raise ValueError(f"ndarray of dtype {dtype.str} and shape {list(shape)} needs {expected} bytes of data, "
                         f"got {len(data)}")
    if dtype.kind == "b" and data.translate(None, b"\x00\x01"):
        raise ValueError("bool ndarray holds a byte other than 0 or 1")
    return np.frombuffer(data, dtype=dtype).reshape(shape)


def _decode_generic(obj):
    dtype = _accepted_dtype(obj.get(b"dtype"), "npgeneric")
    data = obj.get(b"data")
    if dtype.kind == "b":
        valid = isinstance(data, bool)
    elif dtype.kind in "iu":
        info = np.iinfo(dtype)
        valid = isinstance(data, int) and not isinstance(data, bool) and info.min <= data <= info.max
    else:
        valid = isinstance(data, (int, float)) and not isinstance(data, bool)
    if not valid:
        raise ValueError(f"npgeneric of dtype {dtype.str} cannot hold {data!r}")
    return dtype.type(data)


def _decode(obj):
    if b"__ndarray__" in obj:
        return _decode_ndarray(obj)
    if b"__npgeneric__" in obj:
        return _decode_generic(obj)
    return obj


def packb(obj):
    return msgpack.packb(obj, default=_encode)


def unpackb(data):
    return msgpack.unpackb(data, object_hook=_decode)
