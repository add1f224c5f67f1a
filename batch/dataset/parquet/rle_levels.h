// Parquet's RLE/bit-packed hybrid encoding of repetition and definition levels (and of
// dictionary indices): the writer emits RLE runs only, the reader accepts both kinds of run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tavis::batch::dataset::parquet {

// Bits needed to store `max_level` (0 for 0).
int LevelBitWidth(std::uint32_t max_level);

// Appends `levels` as RLE runs of `bit_width` bits, without a length prefix.
void AppendRleRuns(const std::vector<std::uint8_t>& levels, int bit_width, std::vector<std::uint8_t>& out);

// Appends the level block of a data page v1: a uint32 little-endian byte length, then the runs.
void AppendLevelBlock(const std::vector<std::uint8_t>& levels, int bit_width, std::vector<std::uint8_t>& out);

// The uint32 little-endian at `bytes` (the length before a level block, a string, a footer).
std::uint32_t LoadUint32Le(const std::uint8_t* bytes);

// Decodes exactly `count` values of `bit_width` bits (at most 32) from [data, data + size) into
// `out`. Throws std::runtime_error starting with `context` when the runs end early or a value
// exceeds `max_value`.
void DecodeHybrid(const std::uint8_t* data, std::size_t size, int bit_width, std::size_t count, std::uint32_t max_value,
                  const std::string& context, std::vector<std::uint32_t>& out);

}  // namespace tavis::batch::dataset::parquet
