// Test support: a LeRobot dataset (v3.0 or v2.1) as read by readers we did not write: every
// Parquet file through hyparquet and DuckDB (tests/js), the JSON metadata through nlohmann, the
// files located from info.json's path templates as LeRobot locates them.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tavis::batch::dataset::testing {

// Where one episode lives in one camera's mp4 files.
struct VideoSpan {
  std::string path;
  double from_timestamp = 0;
  double to_timestamp = 0;  // v2.1 stores none: the episode's length / fps
};

struct EpisodeEntry {
  int64_t length = 0;
  std::vector<std::string> tasks;
  int64_t from_index = 0, to_index = 0;     // v2.1: accumulated lengths
  std::map<std::string, VideoSpan> videos;  // by video key
};

struct DatasetView {
  std::string root;
  nlohmann::json info, stats;
  int fps = 0;
  std::vector<std::string> video_keys;  // info.json's video features
  std::vector<std::string> data_files;  // in sorted-path order, as LeRobot lists them
  nlohmann::json hyparquet_rows = nlohmann::json::array(),
                 duckdb_rows = nlohmann::json::array();  // every data file's rows
  std::vector<EpisodeEntry> episodes;                    // by episode_index
  std::vector<std::string> tasks;                        // by task_index
  nlohmann::json episodes_table, tasks_table;            // v3.0: read_parquet.mjs's reports of the meta tables
};

DatasetView LoadDataset(const std::string& root);

// An INT64 as the readers print it (a decimal string) or a JSON number, as int64.
int64_t Int(const nlohmann::json& value);

// root/folder/*/*.extension, sorted (LeRobot's glob of chunk folders).
std::vector<std::string> SortedFiles(const std::string& root, const std::string& folder, const std::string& extension);

}  // namespace tavis::batch::dataset::testing
