// Decoding of the values in a Parquet data page (after its levels), for the encodings pyarrow
// and DuckDB write other than dictionaries: PLAIN, DELTA_BINARY_PACKED (INT32/INT64),
// DELTA_LENGTH_BYTE_ARRAY (BYTE_ARRAY), BYTE_STREAM_SPLIT (INT32/INT64/FLOAT/DOUBLE) and RLE
// (BOOLEAN). Dictionary indices are decoded by the reader with DecodeHybrid.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "batch/dataset/parquet/parquet_format.h"

namespace tavis::batch::dataset::parquet {

// Appends `count` values of type T (bool, std::int32_t, std::int64_t, float, double,
// std::string) decoded from [data, data + size) to `out`. Throws std::runtime_error starting
// with `context` for an encoding T does not support or data that ends early or is malformed.
template <typename T>
void DecodeValues(Encoding encoding, const std::uint8_t* data, std::size_t size, std::size_t count,
                  const std::string& context, std::vector<T>& out);

}  // namespace tavis::batch::dataset::parquet
