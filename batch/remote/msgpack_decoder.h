// msgpack decoding as python3-msgpack's unpackb(raw=False) with openpi's msgpack-numpy
// object_hook: a map with the bin key "__ndarray__" becomes an NdArray; one with the bin key
// "__npgeneric__" becomes its scalar "data". The same keys spelled as str leave a plain map.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "batch/remote/msgpack_value.h"

namespace tavis::batch::remote {

// Decodes exactly one value spanning the whole buffer. Every length is checked against the bytes
// left before anything is read or allocated, and nesting is limited to kMaxMsgpackDepth, so any
// input either decodes or throws MsgpackError naming what is wrong and its byte offset
// (truncation, trailing bytes, ext types, the never-used byte 0xc1, malformed msgpack-numpy
// maps). str bytes are passed through without UTF-8 validation.
Value DecodeMsgpack(const std::uint8_t* data, std::size_t size);
inline Value DecodeMsgpack(const std::vector<std::uint8_t>& bytes) { return DecodeMsgpack(bytes.data(), bytes.size()); }

inline constexpr int kMaxMsgpackDepth = 512;

}  // namespace tavis::batch::remote
