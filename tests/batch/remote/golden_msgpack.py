"""Prints "NAME HEX" lines: python3-msgpack's encoding, with openpi's msgpack-numpy hook, of the
values msgpack_golden_test.cc builds in C++ (policy-interfaces.md section A1 vectors, every
length and integer boundary, observation and reply shapes). Run with /usr/bin/python3."""

import numpy as np

from openpi_msgpack_numpy import packb


def pattern(shape, modulus=251):
    return (np.arange(int(np.prod(shape))) % modulus).astype(np.uint8).reshape(shape)


CASES = {
    "f32_pair": np.array([1.0, 2.0], dtype=np.float32),
    "image_224": pattern((224, 224, 3)),
    "empty_map": {},
    "mixed_list": [np.float64(1), 3, -1, 300, True, None],
    "npgeneric_f32": np.float32(0.5),
    "zero_d_f8": np.array(2.5),
    "empty_rows_f4": np.zeros((0, 3), dtype=np.float32),
    "int64_array": np.array([1, -2], dtype=np.int64),
    "int_edges": [0, 127, 128, 255, 256, 65535, 65536, 2**32 - 1, 2**32, 2**63 - 1, 2**64 - 1,
                  -1, -32, -33, -128, -129, -32768, -32769, -2**31, -2**31 - 1, -2**63],
    "doubles": [0.0, -0.0, 1.5, 1e300, float("inf")],
    "strings": ["", "a" * 31, "b" * 32, "c" * 255, "d" * 256, "e" * 65536, "h\u00e9llo"],
    "binaries": [b"", b"\x00" * 255, b"\x01" * 256, b"\x02" * 65536],
    "containers": [[None] * 15, [None] * 16, [None] * 65536,
                   {str(i): i for i in range(15)}, {str(i): i for i in range(16)}],
    "str_keys_stay_a_map": {"__ndarray__": True, "data": b"\x07", "dtype": "|u1", "shape": [1]},
    "libero_observation": {
        "observation/image": pattern((8, 6, 3)),
        "observation/wrist_image": pattern((8, 6, 3), 13),
        "observation/state": np.array([0.5, -1.25, 2.0, 0.0, 1.0, -3.5, 0.04, 0.04], dtype=np.float32),
        "prompt": "pick up the red cube",
    },
    "aloha_observation": {
        "state": np.arange(14, dtype=np.float32) / 4,
        "images": {"cam_high": pattern((3, 4, 4))},
        "prompt": "fold",
    },
    "reply_f8": {
        "actions": np.arange(70, dtype=np.float64).reshape(10, 7) / 8,
        "policy_timing": {"infer_ms": 12.5},
        "server_timing": {"infer_ms": 13.25, "prev_total_ms": 20.0},
    },
}

SINGLE_FLOAT_CASES = {"single_floats": [1.5, -0.25]}

if __name__ == "__main__":
    for name, value in CASES.items():
        print(name, packb(value).hex())
    for name, value in SINGLE_FLOAT_CASES.items():
        print(name, packb(value, use_single_float=True).hex())
