// msgpack encoding with the choices of python3-msgpack >= 1.0 (use_bin_type=True), so that our
// bytes equal Python's: every integer, str, bin, array and map in its shortest form, float64 as
// 0xcb and float32 as 0xca, and NdArray as openpi's msgpack-numpy map whose keys are bin.
#pragma once

#include <cstdint>
#include <vector>

#include "batch/remote/msgpack_value.h"

namespace tavis::batch::remote {

std::vector<std::uint8_t> EncodeMsgpack(const Value& value);

// Appends the encoding of `value` to `out`. Throws std::invalid_argument for an NdArray whose
// data size does not match its dtype and shape, or a container of 2^32 or more entries.
void AppendMsgpack(const Value& value, std::vector<std::uint8_t>& out);

}  // namespace tavis::batch::remote
