#include "batch/action_csv.h"
#include "tests/support/thrown_message.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace tavis::batch {
namespace {

std::string Row(double first, double rest = 0.0) {
  std::string row = std::to_string(first);
  for (int column = 1; column < 19; ++column) row += "," + std::to_string(rest);
  return row + "\n";
}

ActionTrajectory Parse(const std::string& text) {
  std::istringstream in(text);
  return ParseActionCsv(in, "episode.csv");
}

// The message of the error that parsing `text` throws.
std::string ErrorOf(const std::string& text) {
  return testing::ThrownMessage<std::runtime_error>([&text] { Parse(text); }, "no error");
}

TEST(ActionCsv, ReadsRowsWithOptionalHeaderAndBlankLines) {
  std::string header = "left_x";
  for (int column = 1; column < 19; ++column) header += ",c" + std::to_string(column);
  const ActionTrajectory trajectory = Parse(header + "\r\n" + Row(1.5, -1) + "\n" + " +2.5e-1 , 3" + Row(0).substr(17));
  EXPECT_EQ(trajectory.num_steps, 2);
  EXPECT_EQ(trajectory.num_columns, 19);
  EXPECT_EQ(trajectory.view().at(0, 0), 1.5);
  EXPECT_EQ(trajectory.view().at(0, 18), -1.0);
  EXPECT_EQ(trajectory.view().at(1, 0), 0.25);
  EXPECT_EQ(trajectory.view().at(1, 1), 3.0);
}

TEST(ActionCsv, ParsesLikePythonFloat) {
  // 7 significant digits as in the conformance vectors; correctly rounded.
  const ActionTrajectory trajectory = Parse("0.2644762" + Row(0).substr(8));
  EXPECT_EQ(trajectory.values[0], 0.2644762);
}

TEST(ActionCsv, MalformedInputNamesFileAndLine) {
  EXPECT_EQ(ErrorOf(Row(1) + "1,2,3\n"), "episode.csv:2: expected 19 comma-separated values, found 3");
  EXPECT_EQ(ErrorOf(Row(1) + Row(2) + "x" + Row(0).substr(8)), "episode.csv:3: column 1: not a number: 'x'");
  EXPECT_EQ(ErrorOf(Row(1) + "nan" + Row(0).substr(8)),
            "episode.csv:2: column 1: non-finite or out-of-range value 'nan'");
  EXPECT_EQ(ErrorOf("inf" + Row(0).substr(8)), "episode.csv:1: column 1: non-finite or out-of-range value 'inf'");
  EXPECT_EQ(ErrorOf("1e999" + Row(0).substr(8)), "episode.csv:1: column 1: non-finite or out-of-range value '1e999'");
  EXPECT_EQ(ErrorOf(Row(1) + "1,,2" + Row(0).substr(8)), "episode.csv:2: expected 19 comma-separated values, found 21");
  EXPECT_EQ(ErrorOf("0.5.1" + Row(0).substr(8)), "episode.csv:1: column 1: not a number: '0.5.1'");
  EXPECT_EQ(ErrorOf(""), "episode.csv: no data rows");
  EXPECT_EQ(ErrorOf("\n\n"), "episode.csv: no data rows");
}

TEST(ActionCsv, HeaderOnlyCountsAsEmptyAndLaterHeadersAreErrors) {
  std::string header = "a";
  for (int column = 1; column < 19; ++column) header += ",b";
  EXPECT_EQ(ErrorOf(header + "\n"), "episode.csv: no data rows");
  EXPECT_EQ(ErrorOf(Row(1) + header + "\n"), "episode.csv:2: column 1: not a number: 'a'");
}

TEST(ActionCsv, MissingFileIsAnError) {
  try {
    ReadActionCsv("/nonexistent/episode.csv");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/episode.csv: no such file");
  }
}

// Spreadsheet programs start a UTF-8 CSV with a byte order mark: before, the first number was
// refused as "not a number: '0'" with the mark invisible in the message.
TEST(ActionCsv, ByteOrderMarkIsSkipped) {
  const std::string rows = Row(0.25, -1) + Row(2);
  const ActionTrajectory with_mark = Parse("\xEF\xBB\xBF" + rows);
  const ActionTrajectory plain = Parse(rows);
  EXPECT_EQ(with_mark.num_steps, 2);
  EXPECT_EQ(with_mark.values, plain.values);
  std::string header = "left_x";
  for (int column = 1; column < 19; ++column) header += ",c" + std::to_string(column);
  EXPECT_EQ(Parse("\xEF\xBB\xBF" + header + "\n" + rows).values, plain.values)
      << "a header after the mark is still a header";
  EXPECT_EQ(ErrorOf(Row(1) + "\xEF\xBB\xBF" + Row(1)),
            "episode.csv:2: column 1: not a number: '\xEF\xBB\xBF"
            "1.000000'")
      << "only the file's start may hold the mark";
}

// Before: /dev/zero was read as one endless line until the stream failed with "read error".
TEST(ActionCsv, DeviceOrFolderIsNamedNotRead) {
  for (const auto& [path, what] :
       {std::pair<std::string, std::string>{"/dev/zero", "is a character device, not a regular file"},
        {std::filesystem::temp_directory_path().string(), "is a directory, not a file"}}) {
    try {
      ReadActionCsv(path);
      FAIL() << path << " was read";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), path + ": " + what);
    }
  }
}

TEST(ActionCsv, WrittenActionsReadBackBitExactly) {
  std::vector<kinematics::Action> rows(3);
  for (std::size_t row = 0; row < rows.size(); ++row) {
    for (std::size_t column = 0; column < rows[row].size(); ++column) {
      rows[row][column] = std::nextafter(0.1 * static_cast<double>(column + 1), 1.0) / static_cast<double>(row + 3);
    }
  }
  rows[1][4] = -1.0 / 3.0;
  rows[2][0] = 1.2345678901234567e-300;
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "tavis_action_csv_test_roundtrip.csv";
  WriteActionCsv(path, rows);
  const ActionTrajectory read = ReadActionCsv(path);
  std::filesystem::remove(path);
  ASSERT_EQ(read.num_steps, 3);
  ASSERT_EQ(read.num_columns, 19);
  for (std::size_t row = 0; row < rows.size(); ++row) {
    for (std::size_t column = 0; column < rows[row].size(); ++column) {
      EXPECT_EQ(read.values[row * 19 + column], rows[row][column]) << "row " << row << " column " << column;
    }
  }
}

// A cell's actions are saved gzip-compressed: they read back bit-exactly, the same actions give
// the same bytes (no time stamp in the stream), and the file is a gzip stream that gzip reads.
TEST(ActionCsv, CompressedActionsReadBackBitExactlyAndAreTheSameBytesEachTime) {
  std::vector<kinematics::Action> rows(50);
  for (std::size_t row = 0; row < rows.size(); ++row) {
    for (std::size_t column = 0; column < rows[row].size(); ++column)
      rows[row][column] = std::sin(0.37 * static_cast<double>(row * 19 + column)) / 3.0;
  }
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "tavis_action_csv_test_gzip";
  std::filesystem::create_directories(dir);
  WriteActionCsv(dir / "plain.csv", rows);
  WriteActionCsv(dir / "a.csv.gz", rows, ActionFileFormat::kGzip);
  WriteActionCsv(dir / "b.csv.gz", rows, ActionFileFormat::kGzip);
  const auto bytes = [](const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::string compressed = bytes(dir / "a.csv.gz");
  EXPECT_EQ(compressed, bytes(dir / "b.csv.gz"));
  ASSERT_GE(compressed.size(), 2u);
  EXPECT_EQ(static_cast<unsigned char>(compressed[0]), 0x1f);  // the gzip magic
  EXPECT_EQ(static_cast<unsigned char>(compressed[1]), 0x8b);
  EXPECT_LT(compressed.size() * 2, bytes(dir / "plain.csv").size());
  const ActionTrajectory read = ReadActionCsv(dir / "a.csv.gz");
  const ActionTrajectory plain = ReadActionCsv(dir / "plain.csv");
  ASSERT_EQ(read.num_steps, 50);
  EXPECT_EQ(read.values, plain.values);
  for (std::size_t row = 0; row < rows.size(); ++row) {
    for (std::size_t column = 0; column < rows[row].size(); ++column)
      ASSERT_EQ(read.values[row * 19 + column], rows[row][column]) << "row " << row << " column " << column;
  }
  // gzip itself reads it as the plain CSV: another reader than ours.
  const std::string command =
      "gzip -dc '" + (dir / "a.csv.gz").string() + "' > '" + (dir / "gunzipped.csv").string() + "'";
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(bytes(dir / "gunzipped.csv"), bytes(dir / "plain.csv"));
  // A cut stream is named, not read as fewer rows.
  std::ofstream(dir / "cut.csv.gz", std::ios::binary) << compressed.substr(0, compressed.size() / 2);
  const std::string error =
      testing::ThrownMessage<std::runtime_error>([&dir] { ReadActionCsv(dir / "cut.csv.gz"); }, "no error");
  EXPECT_EQ(error.rfind((dir / "cut.csv.gz").string() + ": damaged gzip data: ", 0), 0u) << error;
  std::filesystem::remove_all(dir);
}

// Episode i's actions in a folder: the plain CSV of older cells first, else the compressed one.
TEST(ActionCsv, EpisodeActionsAreFoundPlainOrCompressed) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "tavis_action_csv_test_find";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  EXPECT_EQ(EpisodeActionsName(7), "episode_7.csv.gz");
  EXPECT_TRUE(FindEpisodeActions(dir, 7).empty());
  WriteActionCsv(dir / "episode_7.csv.gz", {kinematics::Action{}}, ActionFileFormat::kGzip);
  EXPECT_EQ(FindEpisodeActions(dir, 7), dir / "episode_7.csv.gz");
  WriteActionCsv(dir / "episode_7.csv", {kinematics::Action{}});
  EXPECT_EQ(FindEpisodeActions(dir, 7), dir / "episode_7.csv");
  EXPECT_TRUE(FindEpisodeActions(dir, 8).empty());
  std::filesystem::remove_all(dir);
}

TEST(ActionCsv, UnwritableFileIsNamed) {
  try {
    WriteActionCsv("/nonexistent/episode.csv", {kinematics::Action{}});
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/episode.csv: cannot write");
  }
}

}  // namespace
}  // namespace tavis::batch
