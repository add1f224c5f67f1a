// Files our parquet::ParquetWriter makes, read back by readers we did not write (hyparquet and DuckDB,
// tests/js/read_parquet.mjs): the schema, row and row-group counts, key-value metadata and every
// value must be what was written (floats exactly), UNCOMPRESSED and SNAPPY alike.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/batch/dataset/node_parquet.h"
#include "tests/batch/dataset/parquet_fixtures.h"

namespace tavis::batch::dataset::testing {
namespace {

using nlohmann::json;

// A count printed as a number by one reader and as a BigInt string by another.
std::string CountText(const json& count) { return count.is_string() ? count.get<std::string>() : count.dump(); }

// One schema element as both readers print it: name, physical type, repetition, converted type.
struct ExpectedElement {
  std::string name;
  std::string type;            // empty for a group
  std::string converted_type;  // empty for none
};

std::vector<ExpectedElement> ExpectedSchema(const std::vector<parquet::ColumnSpec>& columns) {
  std::vector<ExpectedElement> elements;
  for (const parquet::ColumnSpec& column : columns) {
    for (int level = 0; level < column.list_depth(); ++level) {
      elements.push_back({level == 0 ? column.name : "element", "", "LIST"});
      elements.push_back({"list", "", ""});
    }
    elements.push_back({column.is_list ? "element" : column.name,
                        parquet::PhysicalTypeName(parquet::PhysicalTypeOf(column.type)),
                        column.type == parquet::ValueType::kString ? "UTF8" : ""});
  }
  return elements;
}

std::string TextOrEmpty(const json& object, const char* key) {
  return object.contains(key) && object[key].is_string() ? object[key].get<std::string>() : "";
}

void ExpectSchema(const std::string& reader, const json& schema, const WrittenTable& table) {
  const std::vector<ExpectedElement> expected = ExpectedSchema(table.columns);
  ASSERT_EQ(schema.size(), expected.size() + 1) << reader << " schema: " << schema.dump();
  EXPECT_EQ(CountText(schema[0]["num_children"]), std::to_string(table.columns.size())) << reader;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const json& element = schema[i + 1];
    const ExpectedElement& want = expected[i];
    EXPECT_EQ(TextOrEmpty(element, "name"), want.name) << reader << " element " << i + 1;
    EXPECT_EQ(TextOrEmpty(element, "type"), want.type) << reader << " element " << want.name;
    EXPECT_EQ(TextOrEmpty(element, "converted_type"), want.converted_type) << reader << " element " << want.name;
    const std::string repetition = TextOrEmpty(element, "repetition_type");
    EXPECT_EQ(repetition, want.name == "list" ? "REPEATED" : "OPTIONAL") << reader << " element " << want.name;
  }
}

void ExpectRows(const std::string& reader, const json& rows, const WrittenTable& table) {
  ASSERT_EQ(rows.size(), table.rows.size()) << reader;
  int mismatches = 0;
  for (std::size_t row = 0; row < rows.size(); ++row) {
    EXPECT_EQ(rows[row].size(), table.columns.size()) << reader << " row " << row << ": " << rows[row].dump();
    for (const parquet::ColumnSpec& column : table.columns) {
      const json& actual = rows[row].contains(column.name) ? rows[row][column.name] : json();
      const json& expected = table.rows[row][column.name];
      if (actual != expected && ++mismatches <= 5) {
        ADD_FAILURE() << reader << " row " << row << " column " << column.name << ": read " << actual.dump()
                      << ", wrote " << expected.dump();
      }
    }
  }
  EXPECT_EQ(mismatches, 0) << reader << ": values differ from what was written";
}

void ExpectKeyValueMetadata(const std::string& reader, const json& entries, const WrittenTable& table) {
  ASSERT_EQ(entries.size(), table.key_value_metadata.size()) << reader << ": " << entries.dump();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    EXPECT_EQ(entries[i]["key"], table.key_value_metadata[i].first) << reader;
    EXPECT_EQ(entries[i]["value"], table.key_value_metadata[i].second) << reader;
  }
}

void ExpectBothReadersSeeTheTable(const WrittenTable& table, parquet::Codec codec) {
  const json output = ReadWithIndependentReaders(table.path);
  for (const char* reader : {"hyparquet", "duckdb"}) {
    SCOPED_TRACE(std::string(reader) + " reading " + table.path);
    const json& seen = output.at(reader);
    EXPECT_EQ(CountText(seen["num_rows"]), std::to_string(table.rows.size()));
    EXPECT_EQ(CountText(seen["num_row_groups"]), std::to_string(table.row_groups));
    ExpectSchema(reader, seen["schema"], table);
    ExpectKeyValueMetadata(reader, seen["key_value_metadata"], table);
    ExpectRows(reader, seen["rows"], table);
  }
  EXPECT_EQ(output["duckdb"]["codecs"], json::array({parquet::CodecName(codec)}));
  // hyparquet reports the STRING and LIST logical types as written.
  for (const json& element : output["hyparquet"]["schema"]) {
    const std::string converted = TextOrEmpty(element, "converted_type");
    if (converted == "UTF8") {
      EXPECT_EQ(element["logical_type"]["type"], "STRING") << element.dump();
    } else if (converted == "LIST") {
      EXPECT_EQ(element["logical_type"]["type"], "LIST") << element.dump();
    }
  }
}

class ParquetIndependentReaders : public ::testing::TestWithParam<parquet::Codec> {
 protected:
  ScratchDir dir_;
};

TEST_P(ParquetIndependentReaders, ReadTheLeRobotDataFile) {
  ExpectBothReadersSeeTheTable(WriteDataTable(dir_.File("file-000.parquet"), GetParam()), GetParam());
}

TEST_P(ParquetIndependentReaders, ReadTasksWithThePandasMetadata) {
  ExpectBothReadersSeeTheTable(WriteTasksTable(dir_.File("tasks.parquet"), GetParam()), GetParam());
}

TEST_P(ParquetIndependentReaders, ReadTheEpisodesFileWithNestedListsAndSlashNames) {
  ExpectBothReadersSeeTheTable(WriteEpisodesTable(dir_.File("episodes.parquet"), GetParam()), GetParam());
}

INSTANTIATE_TEST_SUITE_P(Codecs, ParquetIndependentReaders,
                         ::testing::Values(parquet::Codec::kUncompressed, parquet::Codec::kSnappy),
                         [](const ::testing::TestParamInfo<parquet::Codec>& param) {
                           return parquet::CodecName(param.param);
                         });

}  // namespace
}  // namespace tavis::batch::dataset::testing
