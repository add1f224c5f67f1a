// Golden bytes of the Thrift compact protocol and of Parquet's RLE/bit-packed hybrid, from the
// format notes (lerobot-v3-format.md §6.2) and the Parquet encoding spec's examples.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "batch/dataset/parquet/rle_levels.h"
#include "batch/dataset/parquet/thrift_compact.h"

namespace tavis::batch::dataset {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes Uleb(std::uint64_t value) {
  Bytes out;
  parquet::AppendUleb128(value, out);
  return out;
}

TEST(ParquetThrift, VarintsAndZigZag) {
  EXPECT_EQ(Uleb(0), (Bytes{0x00}));
  EXPECT_EQ(Uleb(127), (Bytes{0x7f}));
  EXPECT_EQ(Uleb(128), (Bytes{0x80, 0x01}));
  EXPECT_EQ(Uleb(300), (Bytes{0xac, 0x02}));
  EXPECT_EQ(Uleb(std::numeric_limits<std::uint64_t>::max()).size(), 10U);
  EXPECT_EQ(parquet::ZigZag(0), 0U);
  EXPECT_EQ(parquet::ZigZag(-1), 1U);
  EXPECT_EQ(parquet::ZigZag(1), 2U);
  EXPECT_EQ(parquet::ZigZag(-2), 3U);
  EXPECT_EQ(parquet::ZigZag(std::numeric_limits<std::int32_t>::max()), 4294967294U);
  EXPECT_EQ(parquet::ZigZag(std::numeric_limits<std::int64_t>::min()), std::numeric_limits<std::uint64_t>::max());
}

TEST(ParquetThrift, FieldHeadersShortAndLong) {
  Bytes out;
  parquet::ThriftCompactWriter thrift(out);
  thrift.I32Field(1, 1);          // delta 1, i32: 0x15, zigzag(1) = 2
  thrift.I64Field(3, 10);         // delta 2, i64: 0x26, zigzag(10) = 20
  thrift.BoolField(4, true);      // the value is the nibble: 0x11
  thrift.BoolField(5, false);     // 0x12
  thrift.I16Field(100, -3);       // delta 95 > 15: type byte 0x04, then zigzag(100) = 200
  thrift.BinaryField(101, "hi");  // delta 1, binary: 0x18, length, bytes
  thrift.EndStruct();
  EXPECT_EQ(out, (Bytes{0x15, 0x02, 0x26, 0x14, 0x11, 0x12, 0x04, 0xc8, 0x01, 0x05, 0x18, 0x02, 'h', 'i', 0x00}));
}

TEST(ParquetThrift, NestedStructsRestartFieldIds) {
  Bytes out;
  parquet::ThriftCompactWriter thrift(out);
  thrift.I32Field(2, 7);       // 0x25 0x0e
  thrift.BeginStructField(3);  // 0x1c
  thrift.I32Field(1, 0);       // ids restart: 0x15 0x00
  thrift.BeginStructField(3);  // an empty struct member (a union's LIST): 0x2c
  thrift.EndStruct();          // 0x00
  thrift.EndStruct();          // 0x00
  thrift.I32Field(4, -1);      // delta 1 from 3: 0x15 0x01
  thrift.EndStruct();
  EXPECT_EQ(out, (Bytes{0x25, 0x0e, 0x1c, 0x15, 0x00, 0x2c, 0x00, 0x00, 0x15, 0x01, 0x00}));
}

TEST(ParquetThrift, ListHeaders) {
  Bytes out;
  parquet::ThriftCompactWriter thrift(out);
  thrift.ListField(2, parquet::ThriftType::kI32, 2);  // 0x29, size 2 << 4 | i32
  thrift.I32(0);
  thrift.I32(3);
  thrift.ListField(3, parquet::ThriftType::kBinary, 20);  // long form: 0xf8 then varint 20
  EXPECT_EQ(out, (Bytes{0x29, 0x25, 0x00, 0x06, 0x19, 0xf8, 0x14}));
}

TEST(ParquetThrift, DecoderReadsWhatTheEncoderWrote) {
  Bytes out;
  parquet::ThriftCompactWriter thrift(out);
  thrift.I32Field(1, -123456);
  thrift.I64Field(2, std::numeric_limits<std::int64_t>::min());
  thrift.BoolField(3, true);
  thrift.ListField(40, parquet::ThriftType::kBinary, 2);
  thrift.Binary("a");
  thrift.Binary("bc");
  thrift.BeginStructField(41);
  thrift.I64Field(7, 99);
  thrift.EndStruct();
  thrift.I32Field(42, 5);
  thrift.EndStruct();

  parquet::ThriftCompactReader reader(out.data(), out.size(), "test");
  std::vector<std::string> seen;
  reader.ReadStruct([&](std::int16_t id, parquet::ThriftType type) {
    switch (id) {
      case 1: EXPECT_EQ(reader.ReadI32(type), -123456); break;
      case 2: EXPECT_EQ(reader.ReadInt(type), std::numeric_limits<std::int64_t>::min()); break;
      case 3: EXPECT_TRUE(reader.ReadBool(type)); break;
      case 40: {
        parquet::ThriftType element{};
        const std::size_t size = reader.ReadListHeader(type, element);
        for (std::size_t i = 0; i < size; ++i) seen.push_back(reader.ReadBinary(element));
        break;
      }
      case 41: reader.Skip(type); break;
      case 42: EXPECT_EQ(reader.ReadI32(type), 5); break;
      default: ADD_FAILURE() << "unexpected field " << id;
    }
  });
  EXPECT_EQ(seen, (std::vector<std::string>{"a", "bc"}));
  EXPECT_EQ(reader.position(), out.size());
}

TEST(ParquetThrift, DecoderRejectsTruncatedAndOversizedData) {
  Bytes out;
  parquet::ThriftCompactWriter thrift(out);
  thrift.BinaryField(1, "hello");
  thrift.EndStruct();
  for (std::size_t cut = 0; cut < out.size(); ++cut) {
    parquet::ThriftCompactReader reader(out.data(), cut, "footer of x.parquet");
    try {
      reader.ReadStruct([&](std::int16_t, parquet::ThriftType type) { reader.Skip(type); });
      ADD_FAILURE() << "no error at cut " << cut;
    } catch (const std::runtime_error& error) {
      EXPECT_NE(std::string(error.what()).find("footer of x.parquet"), std::string::npos) << error.what();
    }
  }
  const Bytes huge_list{0x19, 0xf8, 0xff, 0xff, 0xff, 0xff, 0x0f};  // a list claiming 2^32 - 1 strings
  parquet::ThriftCompactReader reader(huge_list.data(), huge_list.size(), "x");
  EXPECT_THROW(reader.ReadStruct([&](std::int16_t, parquet::ThriftType type) { reader.Skip(type); }),
               std::runtime_error);
}

TEST(ParquetLevels, TenScalarValuesGiveTheNotesBlock) {
  Bytes out;
  parquet::AppendLevelBlock(std::vector<std::uint8_t>(10, 1), parquet::LevelBitWidth(1), out);
  EXPECT_EQ(out, (Bytes{0x02, 0x00, 0x00, 0x00, 0x14, 0x01}));
}

TEST(ParquetLevels, BitWidths) {
  EXPECT_EQ(parquet::LevelBitWidth(0), 0);
  EXPECT_EQ(parquet::LevelBitWidth(1), 1);
  EXPECT_EQ(parquet::LevelBitWidth(3), 2);
  EXPECT_EQ(parquet::LevelBitWidth(7), 3);
  EXPECT_EQ(parquet::LevelBitWidth(8), 4);
}

TEST(ParquetLevels, DecodesBitPackedAndRleRuns) {
  // The spec's example: 0..7 bit-packed with width 3, then an RLE run of five 4s.
  const Bytes encoded{0x03, 0x88, 0xc6, 0xfa, 0x0a, 0x04};
  std::vector<std::uint32_t> values;
  parquet::DecodeHybrid(encoded.data(), encoded.size(), 3, 13, 7, "test", values);
  EXPECT_EQ(values, (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 4, 4, 4, 4, 4}));
  EXPECT_THROW(parquet::DecodeHybrid(encoded.data(), encoded.size(), 3, 14, 7, "test", values), std::runtime_error);
  EXPECT_THROW(parquet::DecodeHybrid(encoded.data(), encoded.size(), 3, 13, 6, "test", values), std::runtime_error);
}

TEST(ParquetLevels, EncodedRunsDecodeBack) {
  const std::vector<std::uint8_t> levels{0, 1, 1, 1, 0, 3, 3, 2, 0, 0};
  Bytes out;
  parquet::AppendRleRuns(levels, 2, out);
  std::vector<std::uint32_t> decoded;
  parquet::DecodeHybrid(out.data(), out.size(), 2, levels.size(), 3, "test", decoded);
  EXPECT_EQ(decoded, std::vector<std::uint32_t>(levels.begin(), levels.end()));
}

}  // namespace
}  // namespace tavis::batch::dataset
