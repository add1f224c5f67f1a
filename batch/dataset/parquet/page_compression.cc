#include "batch/dataset/parquet/page_compression.h"

#include <snappy.h>
#include <zstd.h>

#include <stdexcept>

namespace tavis::batch::dataset::parquet {
namespace {

// The largest expansion of a snappy block: a 3-byte copy element yields at most 64 bytes.
constexpr std::size_t kSnappyMaxRatio = 22;
// Zstandard has no such small bound (a page of one repeated value shrinks thousands of times),
// so a page may claim this many times its compressed size, plus a fixed allowance.
constexpr std::size_t kZstdMaxRatio = 1024;
constexpr std::size_t kZstdAllowance = std::size_t{64} << 20;

}  // namespace

void AppendCompressed(Codec codec, const std::vector<std::uint8_t>& body, std::vector<std::uint8_t>& out) {
  if (codec == Codec::kUncompressed) {
    out.insert(out.end(), body.begin(), body.end());
    return;
  }
  if (codec != Codec::kSnappy) throw std::invalid_argument("cannot write Parquet pages with codec " + CodecName(codec));
  const std::size_t start = out.size();
  out.resize(start + snappy::MaxCompressedLength(body.size()));
  std::size_t compressed_size = 0;
  snappy::RawCompress(reinterpret_cast<const char*>(body.data()), body.size(),
                      reinterpret_cast<char*>(out.data() + start), &compressed_size);
  out.resize(start + compressed_size);
}

void Decompress(Codec codec, const std::uint8_t* data, std::size_t size, std::size_t uncompressed_size,
                const std::string& context, std::vector<std::uint8_t>& out) {
  const auto mismatch = [&](std::size_t actual) {
    return std::runtime_error(context + ": page body is " + std::to_string(actual) +
                              " bytes uncompressed, its header says " + std::to_string(uncompressed_size));
  };
  switch (codec) {
    case Codec::kUncompressed:
      if (size != uncompressed_size) throw mismatch(size);
      out.assign(data, data + size);
      return;
    case Codec::kSnappy: {
      const char* compressed = reinterpret_cast<const char*>(data);
      std::size_t length = 0;
      if (!snappy::GetUncompressedLength(compressed, size, &length)) {
        throw std::runtime_error(context + ": corrupt snappy block header");
      }
      if (length != uncompressed_size) throw mismatch(length);
      if (length > size * kSnappyMaxRatio + 64) {
        throw std::runtime_error(context + ": snappy block of " + std::to_string(size) + " bytes claims " +
                                 std::to_string(length) + " bytes");
      }
      out.resize(length);
      if (!snappy::RawUncompress(compressed, size, reinterpret_cast<char*>(out.data()))) {
        throw std::runtime_error(context + ": corrupt snappy data");
      }
      return;
    }
    case Codec::kZstd: {
      if (uncompressed_size > size * kZstdMaxRatio + kZstdAllowance) {
        throw std::runtime_error(context + ": zstd frame of " + std::to_string(size) + " bytes claims " +
                                 std::to_string(uncompressed_size) + " bytes");
      }
      out.resize(uncompressed_size);
      const std::size_t length = ZSTD_decompress(out.data(), out.size(), data, size);
      if (ZSTD_isError(length) != 0) {
        throw std::runtime_error(context + ": corrupt zstd data: " + ZSTD_getErrorName(length));
      }
      if (length != uncompressed_size) throw mismatch(length);
      return;
    }
    default: throw std::runtime_error(context + ": unsupported codec " + CodecName(codec));
  }
}

}  // namespace tavis::batch::dataset::parquet
