// Compression of Parquet page bodies: UNCOMPRESSED and SNAPPY (the raw block format of Debian's
// libsnappy) both ways, and ZSTD to read. Other codecs are rejected with their name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "batch/dataset/parquet/parquet_format.h"

namespace tavis::batch::dataset::parquet {

// Appends `body` compressed with `codec` to `out`. Throws std::invalid_argument for a codec
// other than UNCOMPRESSED or SNAPPY.
void AppendCompressed(Codec codec, const std::vector<std::uint8_t>& body, std::vector<std::uint8_t>& out);

// Decompresses [data, data + size) into `out`, which must come out exactly `uncompressed_size`
// bytes. Throws std::runtime_error starting with `context` for an unsupported codec, corrupt data
// or a size mismatch; the output is bounded by what `size` bytes can expand to.
void Decompress(Codec codec, const std::uint8_t* data, std::size_t size, std::size_t uncompressed_size,
                const std::string& context, std::vector<std::uint8_t>& out);

}  // namespace tavis::batch::dataset::parquet
