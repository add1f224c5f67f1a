#include "batch/dataset/parquet/rle_levels.h"

#include <algorithm>
#include <stdexcept>

#include "batch/dataset/parquet/thrift_compact.h"

namespace tavis::batch::dataset::parquet {

int LevelBitWidth(std::uint32_t max_level) {
  int width = 0;
  while (max_level != 0) {
    ++width;
    max_level >>= 1;
  }
  return width;
}

void AppendRleRuns(const std::vector<std::uint8_t>& levels, int bit_width, std::vector<std::uint8_t>& out) {
  const int value_bytes = (bit_width + 7) / 8;
  for (std::size_t start = 0; start < levels.size();) {
    std::size_t end = start + 1;
    while (end < levels.size() && levels[end] == levels[start]) ++end;
    AppendUleb128(static_cast<std::uint64_t>(end - start) << 1, out);
    for (int byte = 0; byte < value_bytes; ++byte) out.push_back(byte == 0 ? levels[start] : 0);
    start = end;
  }
}

void AppendLevelBlock(const std::vector<std::uint8_t>& levels, int bit_width, std::vector<std::uint8_t>& out) {
  const std::size_t length_at = out.size();
  out.resize(out.size() + 4);
  AppendRleRuns(levels, bit_width, out);
  const std::size_t length = out.size() - length_at - 4;
  for (int byte = 0; byte < 4; ++byte) out[length_at + byte] = static_cast<std::uint8_t>(length >> (8 * byte));
}

std::uint32_t LoadUint32Le(const std::uint8_t* bytes) {
  return static_cast<std::uint32_t>(bytes[0]) | static_cast<std::uint32_t>(bytes[1]) << 8 |
         static_cast<std::uint32_t>(bytes[2]) << 16 | static_cast<std::uint32_t>(bytes[3]) << 24;
}

void DecodeHybrid(const std::uint8_t* data, std::size_t size, int bit_width, std::size_t count, std::uint32_t max_value,
                  const std::string& context, std::vector<std::uint32_t>& out) {
  if (bit_width < 0 || bit_width > 32) throw std::runtime_error(context + ": bit width " + std::to_string(bit_width));
  out.clear();
  out.reserve(count);
  std::size_t position = 0;
  const auto fail = [&](const std::string& what) {
    throw std::runtime_error(context + ": " + what + " after " + std::to_string(out.size()) + " of " +
                             std::to_string(count) + " values");
  };
  const auto check = [&](std::uint32_t value) {
    if (value > max_value) fail("value " + std::to_string(value) + " above the maximum " + std::to_string(max_value));
  };
  while (out.size() < count) {
    std::uint64_t header = 0;
    if (!ReadUleb128(data, size, position, header)) fail("run header past the end of the encoded data");
    const std::size_t wanted = count - out.size();
    if ((header & 1) == 0) {
      const std::uint64_t run = header >> 1;
      const int value_bytes = (bit_width + 7) / 8;
      if (size - position < static_cast<std::size_t>(value_bytes)) fail("RLE run value past the end");
      std::uint32_t value = 0;
      for (int byte = 0; byte < value_bytes; ++byte)
        value |= static_cast<std::uint32_t>(data[position++]) << (8 * byte);
      check(value);
      if (run == 0) fail("empty RLE run");
      out.insert(out.end(), static_cast<std::size_t>(std::min<std::uint64_t>(run, wanted)), value);
    } else {
      // Groups of 8 values, bit-packed least significant bit first; a last group may be padding.
      const std::uint64_t groups = header >> 1;
      // Every run yields at least one value, so the loop ends; the cap keeps the products exact.
      if (groups == 0 || groups > (std::uint64_t{1} << 56))
        fail("bit-packed run of " + std::to_string(groups) + " groups");
      const std::uint64_t values = groups * 8;
      const std::uint64_t bytes = groups * static_cast<std::uint64_t>(bit_width);
      if (bytes > size - position) fail("bit-packed run past the end");
      const std::uint8_t* packed = data + position;
      const std::size_t take = static_cast<std::size_t>(std::min<std::uint64_t>(values, wanted));
      for (std::size_t i = 0; i < take; ++i) {
        std::uint64_t value = 0;
        const std::size_t first_bit = i * static_cast<std::size_t>(bit_width);
        for (int bit = 0; bit < bit_width; ++bit) {
          const std::size_t at = first_bit + static_cast<std::size_t>(bit);
          value |= static_cast<std::uint64_t>((packed[at / 8] >> (at % 8)) & 1) << bit;
        }
        check(static_cast<std::uint32_t>(value));
        out.push_back(static_cast<std::uint32_t>(value));
      }
      position += static_cast<std::size_t>(bytes);
    }
  }
}

}  // namespace tavis::batch::dataset::parquet
