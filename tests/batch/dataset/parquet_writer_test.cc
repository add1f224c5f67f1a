// parquet::ParquetWriter: byte-identical output for identical input, the file appears under its name only
// at Close, I/O failures name the path and the system's reason, and schema and row-group mistakes
// throw std::invalid_argument naming the column.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "batch/dataset/parquet/parquet_writer.h"
#include "tests/batch/dataset/parquet_fixtures.h"

namespace tavis::batch::dataset::testing {
namespace {

std::vector<char> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), {});
}

// The message of the exception of type E that `run` throws, or "" if none.
template <typename E, typename Run>
std::string ErrorOf(const Run& run) {
  try {
    run();
  } catch (const E& error) {
    return error.what();
  }
  return "";
}

const std::vector<parquet::ColumnSpec> kColumns{parquet::ColumnSpec::Scalar("frame_index", parquet::ValueType::kInt64),
                                                parquet::ColumnSpec::List("action", parquet::ValueType::kFloat, {3}),
                                                parquet::ColumnSpec::List("tasks", parquet::ValueType::kString)};

void FillRows(parquet::RowGroupBuilder& rows, std::size_t count) {
  rows.Add("frame_index", std::vector<std::int64_t>(count, 1));
  rows.AddList("action", std::vector<float>(count * 3, 0.5f));
  rows.AddList("tasks", std::vector<std::string>(count, "t"), std::vector<std::size_t>(count, 1));
}

TEST(ParquetWriter, SameInputGivesByteIdenticalFiles) {
  const ScratchDir dir;
  for (const parquet::Codec codec : {parquet::Codec::kUncompressed, parquet::Codec::kSnappy}) {
    const std::string name = parquet::CodecName(codec);
    WriteEpisodesTable(dir.File(name + "-a.parquet"), codec);
    WriteEpisodesTable(dir.File(name + "-b.parquet"), codec);
    const std::vector<char> first = ReadBytes(dir.File(name + "-a.parquet"));
    EXPECT_GT(first.size(), 1000U);
    EXPECT_TRUE(first == ReadBytes(dir.File(name + "-b.parquet"))) << name;
  }
  EXPECT_LT(std::filesystem::file_size(dir.File("SNAPPY-a.parquet")),
            std::filesystem::file_size(dir.File("UNCOMPRESSED-a.parquet")));
}

TEST(ParquetWriter, FileAppearsUnderItsNameOnlyAtClose) {
  const ScratchDir dir;
  const std::string path = dir.File("data.parquet");
  parquet::ParquetWriter writer(path, kColumns);
  EXPECT_EQ(writer.bytes_written(), 4U);  // the magic
  parquet::RowGroupBuilder rows = writer.NewRowGroup(5);
  FillRows(rows, 5);
  writer.WriteRowGroup(rows);
  const std::uint64_t after_one = writer.bytes_written();
  rows.Reset(2);
  FillRows(rows, 2);
  writer.WriteRowGroup(rows);
  EXPECT_GT(writer.bytes_written(), after_one);
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_EQ(std::filesystem::file_size(path + ".partial"), writer.bytes_written());
  writer.Close();
  EXPECT_FALSE(std::filesystem::exists(path + ".partial"));
  EXPECT_EQ(std::filesystem::file_size(path), writer.bytes_written());
  EXPECT_EQ(writer.num_rows(), 7);
  EXPECT_THROW(writer.Close(), std::logic_error);
}

TEST(ParquetWriter, DestroyedWithoutCloseLeavesNoFile) {
  const ScratchDir dir;
  const std::string path = dir.File("data.parquet");
  {
    parquet::ParquetWriter writer(path, kColumns);
    parquet::RowGroupBuilder rows = writer.NewRowGroup(1);
    FillRows(rows, 1);
    writer.WriteRowGroup(rows);
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(ParquetWriter, UnwritablePathsAreNamedWithTheReason) {
  const ScratchDir dir;
  const std::string missing = dir.File("no/such/dir/data.parquet");
  EXPECT_EQ(ErrorOf<std::runtime_error>([&] { parquet::ParquetWriter(missing, kColumns); }),
            "cannot create Parquet file " + missing + ".partial: No such file or directory");
  const std::string blocked = dir.File("blocked.parquet");
  std::filesystem::create_directory(blocked + ".partial");
  EXPECT_EQ(ErrorOf<std::runtime_error>([&] { parquet::ParquetWriter(blocked, kColumns); }),
            "cannot create Parquet file " + blocked + ".partial: Is a directory");
}

TEST(ParquetWriter, FullDiskIsNamedAndLeavesNoFile) {
  const ScratchDir dir;
  const std::string path = dir.File("data.parquet");
  ASSERT_EQ(::symlink("/dev/full", (path + ".partial").c_str()), 0);  // writes through it fail with ENOSPC
  EXPECT_EQ(ErrorOf<std::runtime_error>([&] { parquet::ParquetWriter(path, kColumns); }),
            "cannot write Parquet file " + path + ".partial: No space left on device");
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// A write that fails midway (the file size limit, as a full disk would) stops the writer.
TEST(ParquetWriter, FailedRowGroupWriteIsNamedAndStopsTheWriter) {
  const ScratchDir dir;
  const std::string path = dir.File("data.parquet");
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit limited = saved;
  limited.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
  std::string error;
  {
    parquet::ParquetWriterOptions options;
    options.codec = parquet::Codec::kUncompressed;
    parquet::ParquetWriter writer(path, kColumns, options);
    parquet::RowGroupBuilder rows = writer.NewRowGroup(1000);
    FillRows(rows, 1000);
    error = ErrorOf<std::runtime_error>([&] { writer.WriteRowGroup(rows); });
    EXPECT_NE(ErrorOf<std::runtime_error>([&] { writer.Close(); }).find("after a failed write"), std::string::npos);
  }
  ::setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_EQ(error, "cannot write Parquet file " + path + ".partial: File too large");
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(ParquetWriter, SchemaMistakesNameTheColumn) {
  const ScratchDir dir;
  const auto error_for = [&](std::vector<parquet::ColumnSpec> columns) {
    return ErrorOf<std::invalid_argument>([&] { parquet::ParquetWriter(dir.File("x.parquet"), columns); });
  };
  const parquet::ColumnSpec ok = parquet::ColumnSpec::Scalar("ok", parquet::ValueType::kInt64);
  EXPECT_EQ(error_for({ok, ok}), "Parquet column \"ok\" declared twice");
  EXPECT_EQ(error_for({parquet::ColumnSpec::Scalar("", parquet::ValueType::kInt64)}),
            "Parquet column with an empty name");
  for (const char* name : {"stats//mean", "/stats", "stats/"}) {
    EXPECT_EQ(error_for({parquet::ColumnSpec::Scalar(name, parquet::ValueType::kInt64)}),
              "Parquet column \"" + std::string(name) + "\": empty part between '/' separators");
  }
  EXPECT_EQ(error_for({parquet::ColumnSpec::Scalar("tab\there", parquet::ValueType::kInt64)}),
            "Parquet column \"tab\there\": control character in the name");
  EXPECT_EQ(error_for({parquet::ColumnSpec::List("img", parquet::ValueType::kDouble, {3, 0, 1})}),
            "Parquet column \"img\": shape with a 0 axis");
  EXPECT_EQ(error_for({}), "a Parquet schema needs at least one column");
  EXPECT_EQ(error_for({parquet::ColumnSpec::Scalar("data/chunk_index", parquet::ValueType::kInt64),
                       parquet::ColumnSpec::List("stats/observation.images.head/mean", parquet::ValueType::kDouble,
                                                 {3, 1, 1})}),
            "");
  parquet::ParquetWriterOptions zstd;
  zstd.codec = parquet::Codec::kZstd;
  EXPECT_NE(ErrorOf<std::invalid_argument>([&] {
              parquet::ParquetWriter(dir.File("z.parquet"), kColumns, zstd);
            }).find("unsupported codec ZSTD"),
            std::string::npos);
}

TEST(ParquetWriter, RowGroupMistakesNameTheColumn) {
  const ScratchDir dir;
  parquet::ParquetWriter writer(dir.File("x.parquet"), kColumns);
  parquet::RowGroupBuilder rows = writer.NewRowGroup(2);
  const auto error_of = [](const auto& run) { return ErrorOf<std::invalid_argument>(run); };
  EXPECT_EQ(error_of([&] { rows.Add("frame_index", std::vector<std::int64_t>(3)); }),
            "Parquet column \"frame_index\": 3 values for 2 rows of 1 (expected 2)");
  EXPECT_EQ(error_of([&] { rows.Add("frame_index", std::vector<std::int32_t>(2)); }),
            "Parquet column \"frame_index\": declared int64, given int32 values");
  EXPECT_EQ(error_of([&] { rows.Add("action", std::vector<float>(6)); }),
            "Parquet column \"action\": is a list column");
  EXPECT_EQ(error_of([&] { rows.AddList("action", std::vector<float>(5)); }),
            "Parquet column \"action\": 5 values for 2 rows of 3 (expected 6)");
  EXPECT_EQ(error_of([&] {
              rows.AddList("action", std::vector<float>(6), {3, 3});
            }),
            "Parquet column \"action\": has a fixed shape; row lengths are not taken");
  EXPECT_EQ(error_of([&] { rows.AddList("tasks", std::vector<std::string>(2)); }),
            "Parquet column \"tasks\": 0 row lengths for 2 rows (a list without a shape needs one length per row)");
  EXPECT_EQ(error_of([&] {
              rows.AddList("tasks", std::vector<std::string>(2), {1, 2});
            }),
            "Parquet column \"tasks\": 2 values where the row lengths add up to 3");
  EXPECT_EQ(error_of([&] { rows.Add("reward", std::vector<float>(2)); }),
            "Parquet column \"reward\": not in the schema");
  rows.Add("frame_index", std::vector<std::int64_t>{0, 1});
  EXPECT_EQ(error_of([&] {
              rows.Add("frame_index", std::vector<std::int64_t>{0, 1});
            }),
            "Parquet column \"frame_index\": filled twice in one row group");
  EXPECT_EQ(error_of([&] { writer.WriteRowGroup(rows); }),
            "Parquet column \"action\": not filled in the row group for " + dir.File("x.parquet"));
  EXPECT_EQ(error_of([&] { writer.NewRowGroup(0); }), "a Parquet row group needs at least one row");
  parquet::ParquetWriter other(dir.File("y.parquet"), kColumns);
  parquet::RowGroupBuilder foreign = other.NewRowGroup(1);
  FillRows(foreign, 1);
  EXPECT_EQ(error_of([&] { writer.WriteRowGroup(foreign); }),
            "row group from another Parquet writer given to " + dir.File("x.parquet"));
}

}  // namespace
}  // namespace tavis::batch::dataset::testing
