// Data page v2, which neither our writer nor DuckDB writes: a file assembled here byte by byte
// (levels outside the compressed section, no length prefixes, a null) is read the same by
// hyparquet, DuckDB and our reader.
#include <gtest/gtest.h>
#include <snappy.h>

#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "batch/dataset/parquet/parquet_reader.h"
#include "batch/dataset/parquet/parquet_schema.h"
#include "batch/dataset/parquet/rle_levels.h"
#include "batch/dataset/parquet/thrift_compact.h"
#include "tests/batch/dataset/node_parquet.h"
#include "tests/batch/dataset/parquet_fixtures.h"

namespace tavis::batch::dataset::testing {
namespace {

using Bytes = std::vector<std::uint8_t>;

void AppendInt64(std::int64_t value, Bytes& out) {
  for (int byte = 0; byte < 8; ++byte)
    out.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) >> (8 * byte)));
}

// One optional INT64 column "x" holding 5, null, 7 in a single SNAPPY data page v2.
Bytes FileWithDataPageV2() {
  Bytes definition_levels;
  parquet::AppendRleRuns({1, 0, 1}, 1, definition_levels);
  Bytes values;
  AppendInt64(5, values);
  AppendInt64(7, values);
  std::string compressed;
  snappy::Compress(reinterpret_cast<const char*>(values.data()), values.size(), &compressed);

  Bytes file{'P', 'A', 'R', '1'};
  const auto page_offset = static_cast<std::int64_t>(file.size());
  parquet::ThriftCompactWriter header(file);
  header.I32Field(1, static_cast<std::int32_t>(parquet::PageType::kDataPageV2));
  header.I32Field(2, static_cast<std::int32_t>(definition_levels.size() + values.size()));
  header.I32Field(3, static_cast<std::int32_t>(definition_levels.size() + compressed.size()));
  header.BeginStructField(8);
  header.I32Field(1, 3);  // num_values
  header.I32Field(2, 1);  // num_nulls
  header.I32Field(3, 3);  // num_rows
  header.I32Field(4, static_cast<std::int32_t>(parquet::Encoding::kPlain));
  header.I32Field(5, static_cast<std::int32_t>(definition_levels.size()));
  header.I32Field(6, 0);
  header.BoolField(7, true);
  header.EndStruct();
  header.EndStruct();
  const std::int64_t header_size = static_cast<std::int64_t>(file.size()) - page_offset;
  file.insert(file.end(), definition_levels.begin(), definition_levels.end());
  file.insert(file.end(), compressed.begin(), compressed.end());
  const std::int64_t chunk_size = static_cast<std::int64_t>(file.size()) - page_offset;
  const std::int64_t uncompressed_size =
      header_size + static_cast<std::int64_t>(definition_levels.size() + values.size());

  Bytes footer;
  parquet::ThriftCompactWriter thrift(footer);
  thrift.I32Field(1, 2);
  parquet::AppendSchemaField({parquet::ColumnSpec::Scalar("x", parquet::ValueType::kInt64)}, thrift);
  thrift.I64Field(3, 3);
  thrift.ListField(4, parquet::ThriftType::kStruct, 1);
  thrift.BeginStruct();
  thrift.ListField(1, parquet::ThriftType::kStruct, 1);
  thrift.BeginStruct();
  thrift.I64Field(2, page_offset);
  thrift.BeginStructField(3);
  thrift.I32Field(1, static_cast<std::int32_t>(parquet::PhysicalType::kInt64));
  thrift.ListField(2, parquet::ThriftType::kI32, 2);
  thrift.I32(static_cast<std::int32_t>(parquet::Encoding::kPlain));
  thrift.I32(static_cast<std::int32_t>(parquet::Encoding::kRle));
  thrift.ListField(3, parquet::ThriftType::kBinary, 1);
  thrift.Binary("x");
  thrift.I32Field(4, static_cast<std::int32_t>(parquet::Codec::kSnappy));
  thrift.I64Field(5, 3);
  thrift.I64Field(6, uncompressed_size);
  thrift.I64Field(7, chunk_size);
  thrift.I64Field(9, page_offset);
  thrift.EndStruct();
  thrift.EndStruct();
  thrift.I64Field(2, uncompressed_size);
  thrift.I64Field(3, 3);
  thrift.EndStruct();
  thrift.EndStruct();
  file.insert(file.end(), footer.begin(), footer.end());
  for (int byte = 0; byte < 4; ++byte) file.push_back(static_cast<std::uint8_t>(footer.size() >> (8 * byte)));
  file.insert(file.end(), {'P', 'A', 'R', '1'});
  return file;
}

TEST(ParquetPageV2, ReadLikeTheIndependentReaders) {
  const ScratchDir dir;
  const std::string path = dir.File("page_v2.parquet");
  const Bytes bytes = FileWithDataPageV2();
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));

  const nlohmann::json expected = nlohmann::json::array({{{"x", "5"}}, {{"x", nullptr}}, {{"x", "7"}}});
  const nlohmann::json independent = ReadWithIndependentReaders(path);
  EXPECT_EQ(independent["hyparquet"]["rows"], expected);
  EXPECT_EQ(independent["duckdb"]["rows"], expected);

  const parquet::ParquetReader reader(path);
  const parquet::ListColumn<std::int64_t> x = reader.ReadListColumn<std::int64_t>("x");
  EXPECT_EQ(x.values, (std::vector<std::int64_t>{5, 7}));
  EXPECT_EQ(x.row_lengths, (std::vector<std::size_t>{1, 0, 1}));
  try {
    reader.ReadColumn<std::int64_t>("x");
    ADD_FAILURE() << "a null read as a value";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()), path + ": column \"x\" is null in row 1");
  }
}

}  // namespace
}  // namespace tavis::batch::dataset::testing
