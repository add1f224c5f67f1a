// Test tables shaped like LeRobot v3.0 files (a data file, tasks.parquet, an episodes file),
// written with parquet::ParquetWriter and kept as the JSON every reader must give back: one object per row,
// column name -> value, INT64 as a decimal string, FLOAT as the double it widens to, lists as
// (nested) arrays. Also a scratch directory and our own reader's view in the same JSON.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <vector>

#include "batch/dataset/parquet/parquet_reader.h"
#include "batch/dataset/parquet/parquet_writer.h"

namespace tavis::batch::dataset::testing {

struct WrittenTable {
  std::string path;
  std::vector<parquet::ColumnSpec> columns;
  nlohmann::json rows = nlohmann::json::array();
  std::size_t row_groups = 0;
  std::vector<std::pair<std::string, std::string>> key_value_metadata;
};

// LeRobot's data file: observation.state float[34], action float[19], language_instruction,
// timestamp, frame_index, episode_index, index, task_index; three episodes (row groups) of
// different lengths.
WrittenTable WriteDataTable(const std::string& path, parquet::Codec codec);
// meta/tasks.parquet with the "pandas" key-value entry of lerobot-v3-format.md §3.3.
WrittenTable WriteTasksTable(const std::string& path, parquet::Codec codec);
// An episodes file: list<string> tasks of varying length (one empty), names with '/',
// stats as list<int64>, list<double>, list<list<list<double>>> (3,1,1), plus bool, int32 and
// list<int32>/list<bool> columns so that every value type is covered; two row groups.
WrittenTable WriteEpisodesTable(const std::string& path, parquet::Codec codec);

// Every column of `table`, read back by our parquet::ParquetReader, as rows in the JSON above. Throws
// std::logic_error when a fixed-shape column comes back with rows of another length.
nlohmann::json ReadWithOurReader(const std::string& path, const std::vector<parquet::ColumnSpec>& columns);

// Reads every column with our parquet::ParquetReader and drops the values.
void ReadEveryColumn(const std::string& path, const std::vector<parquet::ColumnSpec>& columns);

// A fresh directory under the system's temporary directory, removed with its content.
class ScratchDir {
 public:
  ScratchDir();
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  std::string File(const std::string& name) const { return path_ + "/" + name; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace tavis::batch::dataset::testing
