// parquet::ParquetReader: everything our writer writes comes back; files DuckDB writes (dictionaries,
// delta and byte-stream-split encodings, ZSTD) read exactly; truncated, corrupt and
// unsupported files fail with errors naming the file and the problem, never a crash.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "batch/dataset/parquet/parquet_reader.h"
#include "tests/batch/dataset/node_parquet.h"
#include "tests/batch/dataset/parquet_fixtures.h"

namespace tavis::batch::dataset::testing {
namespace {

using Bytes = std::vector<char>;

Bytes ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), {});
}

void WriteBytes(const std::string& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::vector<std::string> NamesOf(const std::vector<parquet::ColumnSpec>& columns) {
  std::vector<std::string> names;
  for (const parquet::ColumnSpec& column : columns) names.push_back(column.name);
  return names;
}

// The message of the std::runtime_error that opening and reading every column throws.
std::string ErrorReadingAll(const std::string& path, const std::vector<parquet::ColumnSpec>& columns) {
  try {
    ReadEveryColumn(path, columns);
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

class ParquetReaderRoundTrip : public ::testing::TestWithParam<parquet::Codec> {
 protected:
  ScratchDir dir_;
};

TEST_P(ParquetReaderRoundTrip, ReadsBackEveryTableTheWriterWrites) {
  for (const WrittenTable& table :
       {WriteDataTable(dir_.File("data.parquet"), GetParam()), WriteTasksTable(dir_.File("tasks.parquet"), GetParam()),
        WriteEpisodesTable(dir_.File("episodes.parquet"), GetParam())}) {
    SCOPED_TRACE(table.path);
    const parquet::ParquetReader reader(table.path);
    EXPECT_EQ(reader.num_rows(), static_cast<std::int64_t>(table.rows.size()));
    EXPECT_EQ(reader.num_row_groups(), table.row_groups);
    EXPECT_EQ(reader.column_names(), NamesOf(table.columns));
    EXPECT_EQ(reader.key_value_metadata(), table.key_value_metadata);
    EXPECT_EQ(reader.created_by(), parquet::ParquetWriterOptions{}.created_by);
    EXPECT_EQ(ReadWithOurReader(table.path, table.columns), table.rows);
  }
}

INSTANTIATE_TEST_SUITE_P(Codecs, ParquetReaderRoundTrip,
                         ::testing::Values(parquet::Codec::kUncompressed, parquet::Codec::kSnappy),
                         [](const ::testing::TestParamInfo<parquet::Codec>& param) {
                           return parquet::CodecName(param.param);
                         });

TEST(ParquetReader, TypedColumnsAndErrorsThatNameTheColumn) {
  const ScratchDir dir;
  const WrittenTable table = WriteDataTable(dir.File("data.parquet"), parquet::Codec::kSnappy);
  const parquet::ParquetReader reader(table.path);
  const std::vector<std::int64_t> frames = reader.ReadColumn<std::int64_t>("frame_index");
  ASSERT_EQ(frames.size(), 22U);
  EXPECT_EQ(frames[6], 6);
  EXPECT_EQ(frames[7], 0);  // the second episode starts
  const parquet::ListColumn<float> actions = reader.ReadListColumn<float>("action");
  EXPECT_EQ(actions.row_lengths, std::vector<std::size_t>(22, 19));
  EXPECT_EQ(reader.columns()[0].path, (std::vector<std::string>{"observation.state", "list", "element"}));
  EXPECT_EQ(reader.columns()[0].max_repetition_level, 1);
  EXPECT_EQ(reader.columns()[0].max_definition_level, 3);

  const auto message = [&](const auto& read) -> std::string {
    try {
      read();
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "no error";
  };
  EXPECT_NE(
      message([&] { reader.ReadColumn<double>("frame_index"); }).find("\"frame_index\" holds INT64, read as DOUBLE"),
      std::string::npos);
  EXPECT_NE(message([&] { reader.ReadColumn<float>("action"); }).find("\"action\" is a list column"),
            std::string::npos);
  EXPECT_NE(message([&] { reader.ReadColumn<float>("reward"); }).find(table.path + ": no column \"reward\""),
            std::string::npos);
}

// A Parquet version ("v1": PLAIN and PLAIN_DICTIONARY; "v2": RLE_DICTIONARY, delta and
// byte-stream-split encodings) and a codec, as DuckDB names them.
using DuckdbFormat = std::pair<const char*, const char*>;

class ParquetReaderDuckdbFiles : public ::testing::TestWithParam<DuckdbFormat> {};

TEST_P(ParquetReaderDuckdbFiles, ReadsEveryValueDuckdbWrote) {
  const ScratchDir dir;
  const std::string path = dir.File("duckdb.parquet");
  constexpr std::size_t kRows = 5000;
  WriteWithDuckdb(path, kRows, GetParam().first, 2048, GetParam().second);
  const parquet::ParquetReader reader(path);
  ASSERT_EQ(reader.num_rows(), static_cast<std::int64_t>(kRows));
  EXPECT_GE(reader.num_row_groups(), 2U);
  const std::vector<std::int64_t> id = reader.ReadColumn<std::int64_t>("id");
  const std::vector<std::int64_t> small = reader.ReadColumn<std::int64_t>("small");
  const std::vector<float> half = reader.ReadColumn<float>("half");
  const std::vector<double> third = reader.ReadColumn<double>("third");
  const std::vector<std::string> label = reader.ReadColumn<std::string>("label");
  const std::vector<std::string> name = reader.ReadColumn<std::string>("name");
  const parquet::ListColumn<float> vec = reader.ReadListColumn<float>("vec");
  ASSERT_EQ(vec.row_lengths.size(), kRows);
  int mismatches = 0;
  std::size_t next_item = 0;
  for (std::size_t i = 0; i < kRows; ++i) {
    const auto n = static_cast<std::int64_t>(i);
    const std::vector<float> items =
        i % 5 == 0 ? std::vector<float>{}
                   : std::vector<float>{static_cast<float>(i), static_cast<float>(i) + 0.5f, -static_cast<float>(i)};
    const std::vector<float> read_items(
        vec.values.begin() + static_cast<std::ptrdiff_t>(next_item),
        vec.values.begin() + static_cast<std::ptrdiff_t>(next_item + vec.row_lengths[i]));
    next_item += vec.row_lengths[i];
    const bool row_ok = id[i] == n * 1000003 - 5 && small[i] == n % 3 &&
                        half[i] == static_cast<float>(static_cast<double>(i) / 2.0 + 0.1) &&
                        third[i] == static_cast<double>(i) / 3.0 && label[i] == "task " + std::to_string(i % 4) &&
                        name[i] == "row-" + std::to_string(i) && read_items == items;
    if (!row_ok && ++mismatches <= 3) {
      ADD_FAILURE() << "row " << i << ": id " << id[i] << " small " << small[i] << " half " << half[i] << " third "
                    << third[i] << " label " << label[i] << " name " << name[i] << " vec items " << read_items.size();
    }
  }
  EXPECT_EQ(mismatches, 0);
}

INSTANTIATE_TEST_SUITE_P(Formats, ParquetReaderDuckdbFiles,
                         ::testing::Values(DuckdbFormat{"v1", "snappy"}, DuckdbFormat{"v2", "snappy"},
                                           DuckdbFormat{"v1", "zstd"}, DuckdbFormat{"v2", "uncompressed"}),
                         [](const ::testing::TestParamInfo<DuckdbFormat>& param) {
                           return std::string(param.param.first) + "_" + param.param.second;
                         });

TEST(ParquetReader, UnsupportedCodecIsNamedWithColumnAndFile) {
  const ScratchDir dir;
  const std::string path = dir.File("gzip.parquet");
  WriteWithDuckdb(path, 10, "v1", 0, "gzip");
  const parquet::ParquetReader reader(path);
  try {
    reader.ReadColumn<std::int64_t>("id");
    FAIL() << "GZIP read";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()), "unsupported codec GZIP in column \"id\" of " + path);
  }
}

TEST(ParquetReader, TruncatedFilesAreRejectedByName) {
  const ScratchDir dir;
  const WrittenTable table = WriteDataTable(dir.File("data.parquet"), parquet::Codec::kUncompressed);
  const Bytes bytes = ReadBytes(table.path);
  const std::string cut_path = dir.File("cut.parquet");
  for (const std::size_t cut :
       {std::size_t{0}, std::size_t{3}, std::size_t{4}, std::size_t{11}, std::size_t{100}, bytes.size() / 2,
        bytes.size() - 12, bytes.size() - 8, bytes.size() - 5, bytes.size() - 1}) {
    WriteBytes(cut_path, Bytes(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(cut)));
    const std::string error = ErrorReadingAll(cut_path, table.columns);
    EXPECT_EQ(error.rfind(cut_path + ": ", 0), 0U) << "cut at " << cut << ": " << error;
    EXPECT_TRUE(error.find("too short") != std::string::npos || error.find("bad magic at the end") != std::string::npos)
        << "cut at " << cut << ": " << error;
  }
}

TEST(ParquetReader, BadMagicFooterLengthAndMissingPagesAreNamed) {
  const ScratchDir dir;
  const WrittenTable table = WriteDataTable(dir.File("data.parquet"), parquet::Codec::kSnappy);
  const Bytes bytes = ReadBytes(table.path);
  const std::string path = dir.File("bad.parquet");

  Bytes bad_magic = bytes;
  bad_magic[0] = 'X';
  WriteBytes(path, bad_magic);
  EXPECT_EQ(ErrorReadingAll(path, table.columns), path + ": bad magic at the start (not a Parquet file)");

  Bytes long_footer = bytes;
  long_footer[long_footer.size() - 5] = '\x7f';  // the footer length's high byte
  WriteBytes(path, long_footer);
  EXPECT_NE(ErrorReadingAll(path, table.columns).find(path + ": footer length "), std::string::npos);

  // Pages removed from before the footer: the last column chunk now reaches into the footer.
  const std::size_t footer_length = static_cast<unsigned char>(bytes[bytes.size() - 8]) |
                                    static_cast<std::size_t>(static_cast<unsigned char>(bytes[bytes.size() - 7])) << 8;
  const std::size_t footer_start = bytes.size() - 8 - footer_length;
  Bytes missing_pages(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(footer_start - 40));
  missing_pages.insert(missing_pages.end(), bytes.begin() + static_cast<std::ptrdiff_t>(footer_start), bytes.end());
  WriteBytes(path, missing_pages);
  const std::string error = ErrorReadingAll(path, table.columns);
  EXPECT_EQ(error.rfind(path + ": column \"", 0), 0U) << error;
  EXPECT_NE(error.find("in row group 2: column chunk at offset"), std::string::npos) << error;
  EXPECT_NE(error.find("lies outside the data"), std::string::npos) << error;
}

// A small file with every kind of level structure (scalars, variable and nested lists), so that
// corrupting each of its bytes stays fast.
std::vector<parquet::ColumnSpec> WriteSmallTable(const std::string& path, parquet::Codec codec) {
  const std::vector<parquet::ColumnSpec> columns{
      parquet::ColumnSpec::Scalar("id", parquet::ValueType::kInt64),
      parquet::ColumnSpec::List("tags", parquet::ValueType::kString),
      parquet::ColumnSpec::List("stats/img/mean", parquet::ValueType::kDouble, {3, 1, 1}),
      parquet::ColumnSpec::Scalar("ok", parquet::ValueType::kBool),
      parquet::ColumnSpec::List("v", parquet::ValueType::kFloat, {2})};
  parquet::ParquetWriterOptions options;
  options.codec = codec;
  options.key_value_metadata = {{"k", "v"}};
  parquet::ParquetWriter writer(path, columns, options);
  for (std::size_t rows : {2, 3}) {
    parquet::RowGroupBuilder group = writer.NewRowGroup(rows);
    group.Add("id", std::vector<std::int64_t>(rows, 7));
    std::vector<std::size_t> tag_counts(rows, 1);
    tag_counts[0] = 0;
    group.AddList("tags", std::vector<std::string>(rows - 1, "tag"), tag_counts);
    group.AddList("stats/img/mean", std::vector<double>(rows * 3, 0.25));
    group.Add("ok", std::vector<bool>(rows, true));
    group.AddList("v", std::vector<float>(rows * 2, 1.5f));
    writer.WriteRowGroup(group);
  }
  writer.Close();
  return columns;
}

// Every single-byte corruption of a file either reads (a changed value) or throws a
// std::runtime_error naming the file; anything else (a crash, std::bad_alloc) fails the test.
TEST(ParquetReader, EveryCorruptedByteGivesValuesOrANamedError) {
  const ScratchDir dir;
  for (const parquet::Codec codec : {parquet::Codec::kSnappy, parquet::Codec::kUncompressed}) {
    const std::string original = dir.File("small.parquet");
    const std::vector<parquet::ColumnSpec> columns = WriteSmallTable(original, codec);
    const Bytes bytes = ReadBytes(original);
    const std::string path = dir.File("corrupt.parquet");
    int errors = 0;
    for (std::size_t at = 0; at < bytes.size(); ++at) {
      Bytes corrupt = bytes;
      corrupt[at] = static_cast<char>(corrupt[at] ^ 0x5a);
      WriteBytes(path, corrupt);
      const std::string error = ErrorReadingAll(path, columns);
      if (error.empty()) continue;
      ++errors;
      ASSERT_EQ(error.rfind(path + ": ", 0) == 0 || error.find(" of " + path) != std::string::npos, true)
          << "byte " << at << ": " << error;
    }
    EXPECT_GT(errors, static_cast<int>(bytes.size() / 4)) << parquet::CodecName(codec);
  }
}

}  // namespace
}  // namespace tavis::batch::dataset::testing
