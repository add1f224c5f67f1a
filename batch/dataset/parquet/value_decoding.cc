#include "batch/dataset/parquet/value_decoding.h"

#include <cstring>
#include <stdexcept>
#include <type_traits>

#include "batch/dataset/parquet/parquet_schema.h"
#include "batch/dataset/parquet/rle_levels.h"
#include "batch/dataset/parquet/thrift_compact.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "PLAIN values are read as little-endian bytes");

namespace tavis::batch::dataset::parquet {
namespace {

[[noreturn]] void Fail(const std::string& context, const std::string& what) {
  throw std::runtime_error(context + ": " + what);
}

// A bounded cursor for the variable-length parts of the delta encodings.
struct Cursor {
  const std::uint8_t* data;
  std::size_t size;
  std::size_t position;
  const std::string& context;

  std::uint64_t Uleb128() {
    std::uint64_t value = 0;
    if (!ReadUleb128(data, size, position, value)) Fail(context, "varint past the end of the values");
    return value;
  }
  std::int64_t ZigZag() { return UnZigZag(Uleb128()); }
};

template <typename T>
void DecodePlainFixed(const std::uint8_t* data, std::size_t size, std::size_t count, const std::string& context,
                      std::vector<T>& out) {
  if (count > size / sizeof(T)) {
    Fail(context, std::to_string(count) + " PLAIN values need more than the " + std::to_string(size) + " bytes left");
  }
  if (count == 0) return;  // memcpy from or to a null pointer is undefined even for 0 bytes
  const std::size_t start = out.size();
  out.resize(start + count);
  std::memcpy(out.data() + start, data, count * sizeof(T));
}

// BYTE_STREAM_SPLIT: byte b of value i is at data[b * count + i].
template <typename T>
void DecodeByteStreamSplit(const std::uint8_t* data, std::size_t size, std::size_t count, const std::string& context,
                           std::vector<T>& out) {
  if (count > size / sizeof(T)) Fail(context, std::to_string(count) + " BYTE_STREAM_SPLIT values past the end");
  std::uint8_t bytes[sizeof(T)];
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t b = 0; b < sizeof(T); ++b) bytes[b] = data[b * count + i];
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    out.push_back(value);
  }
}

// DELTA_BINARY_PACKED: a header (block size, miniblocks per block, total count, first value),
// then blocks of a zigzag minimum delta, one bit width per miniblock, and the bit-packed
// deltas. Returns the bytes consumed.
template <typename Integer>
std::size_t DecodeDeltaBinaryPacked(const std::uint8_t* data, std::size_t size, std::size_t count,
                                    const std::string& context, std::vector<Integer>& out) {
  Cursor cursor{data, size, 0, context};
  const std::uint64_t block_size = cursor.Uleb128();
  const std::uint64_t miniblocks = cursor.Uleb128();
  const std::uint64_t total = cursor.Uleb128();
  std::uint64_t value = static_cast<std::uint64_t>(cursor.ZigZag());
  // Writers use blocks of 128 values or a few times that; the cap keeps the sizes below exact.
  constexpr std::uint64_t kMaxBlockSize = std::uint64_t{1} << 20;
  if (block_size == 0 || block_size > kMaxBlockSize || block_size % 128 != 0 || miniblocks == 0 ||
      block_size % miniblocks != 0 || (block_size / miniblocks) % 32 != 0) {
    Fail(context, "DELTA_BINARY_PACKED block of " + std::to_string(block_size) + " values in " +
                      std::to_string(miniblocks) + " miniblocks");
  }
  // Equal counts also bound the loop below, as `count` is bounded by the caller.
  if (total != count) {
    Fail(context,
         "DELTA_BINARY_PACKED holds " + std::to_string(total) + " values, " + std::to_string(count) + " expected");
  }
  const std::uint64_t per_miniblock = block_size / miniblocks;
  if (total == 0) return cursor.position;
  out.push_back(static_cast<Integer>(value));
  std::uint64_t left = total - 1;
  while (left > 0) {
    const std::uint64_t min_delta = static_cast<std::uint64_t>(cursor.ZigZag());
    if (miniblocks > size - cursor.position) Fail(context, "DELTA_BINARY_PACKED bit widths past the end");
    const std::uint8_t* widths = data + cursor.position;
    cursor.position += static_cast<std::size_t>(miniblocks);
    for (std::uint64_t m = 0; m < miniblocks && left > 0; ++m) {
      const int width = widths[m];
      if (width > 64) Fail(context, "DELTA_BINARY_PACKED bit width " + std::to_string(width));
      const std::uint64_t bytes = per_miniblock * static_cast<std::uint64_t>(width) / 8;
      if (bytes > size - cursor.position) Fail(context, "DELTA_BINARY_PACKED miniblock past the end");
      const std::uint8_t* packed = data + cursor.position;
      for (std::uint64_t i = 0; i < per_miniblock && left > 0; ++i, --left) {
        std::uint64_t delta = 0;
        for (int bit = 0; bit < width; ++bit) {
          const std::uint64_t at = i * static_cast<std::uint64_t>(width) + static_cast<std::uint64_t>(bit);
          delta |= static_cast<std::uint64_t>((packed[at / 8] >> (at % 8)) & 1) << bit;
        }
        value += min_delta + delta;  // wraps as the encoder's arithmetic does
        out.push_back(static_cast<Integer>(value));
      }
      cursor.position += static_cast<std::size_t>(bytes);
    }
  }
  return cursor.position;
}

void DecodeStrings(Encoding encoding, const std::uint8_t* data, std::size_t size, std::size_t count,
                   const std::string& context, std::vector<std::string>& out) {
  if (encoding == Encoding::kDeltaLengthByteArray) {
    std::vector<std::int32_t> lengths;
    std::size_t position = DecodeDeltaBinaryPacked(data, size, count, context, lengths);
    for (const std::int32_t length : lengths) {
      if (length < 0 || static_cast<std::size_t>(length) > size - position) Fail(context, "string past the end");
      out.emplace_back(reinterpret_cast<const char*>(data + position), static_cast<std::size_t>(length));
      position += static_cast<std::size_t>(length);
    }
    return;
  }
  if (encoding != Encoding::kPlain) Fail(context, "unsupported encoding " + EncodingName(encoding) + " for BYTE_ARRAY");
  if (count > size / 4) Fail(context, std::to_string(count) + " PLAIN strings past the end");
  std::size_t position = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (size - position < 4) Fail(context, "string length past the end");
    const std::uint32_t length = LoadUint32Le(data + position);
    position += 4;
    if (length > size - position) Fail(context, "string of " + std::to_string(length) + " bytes past the end");
    out.emplace_back(reinterpret_cast<const char*>(data + position), length);
    position += length;
  }
}

void DecodeBooleans(Encoding encoding, const std::uint8_t* data, std::size_t size, std::size_t count,
                    const std::string& context, std::vector<bool>& out) {
  if (encoding == Encoding::kRle) {
    // A uint32 length, then the RLE/bit-packed hybrid of width 1.
    if (size < 4 || LoadUint32Le(data) > size - 4) Fail(context, "RLE booleans past the end");
    std::vector<std::uint32_t> bits;
    DecodeHybrid(data + 4, LoadUint32Le(data), 1, count, 1, context, bits);
    for (const std::uint32_t bit : bits) out.push_back(bit != 0);
    return;
  }
  if (encoding != Encoding::kPlain) Fail(context, "unsupported encoding " + EncodingName(encoding) + " for BOOLEAN");
  if ((count + 7) / 8 > size) Fail(context, std::to_string(count) + " PLAIN booleans past the end");
  for (std::size_t i = 0; i < count; ++i) out.push_back(((data[i / 8] >> (i % 8)) & 1) != 0);
}

}  // namespace

template <typename T>
void DecodeValues(Encoding encoding, const std::uint8_t* data, std::size_t size, std::size_t count,
                  const std::string& context, std::vector<T>& out) {
  if constexpr (std::is_same_v<T, bool>) {
    DecodeBooleans(encoding, data, size, count, context, out);
  } else if constexpr (std::is_same_v<T, std::string>) {
    DecodeStrings(encoding, data, size, count, context, out);
  } else {
    switch (encoding) {
      case Encoding::kPlain: return DecodePlainFixed(data, size, count, context, out);
      case Encoding::kByteStreamSplit: return DecodeByteStreamSplit(data, size, count, context, out);
      case Encoding::kDeltaBinaryPacked:
        if constexpr (std::is_integral_v<T>) {
          DecodeDeltaBinaryPacked(data, size, count, context, out);
          return;
        }
        break;
      default: break;
    }
    Fail(context, "unsupported encoding " + EncodingName(encoding));
  }
}

#define TAVIS_PARQUET_INSTANTIATE(T)                                                                         \
  template void DecodeValues<T>(Encoding, const std::uint8_t*, std::size_t, std::size_t, const std::string&, \
                                std::vector<T>&);
TAVIS_PARQUET_FOR_EACH_VALUE_TYPE(TAVIS_PARQUET_INSTANTIATE)
#undef TAVIS_PARQUET_INSTANTIATE

}  // namespace tavis::batch::dataset::parquet
