// A LeRobot dataset's meta/info.json (the keys trajectory readers need) and where its data and
// episode-metadata files are, per codebase version (lerobot-v3-format.md sections 1-2).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace tavis::batch::dataset::reader {

enum class DatasetVersion {
  kV30,  // "v3.0": data/*/*.parquet holding many episodes each
  kV21,  // "v2.1": data/chunk-*/episode_*.parquet, one episode each
};

struct DatasetInfo {
  std::string codebase_version;  // as written, "v3.0" or "v2.1"
  DatasetVersion version = DatasetVersion::kV30;
  double fps = 0.0;                       // frames per second of the data rows
  std::optional<std::string> robot_type;  // null in info.json (as TAVIS writes it) -> nullopt
  std::int64_t total_episodes = 0;
};

// The frame rates of a recording (and of `tavis galt --fps`): an info.json fps outside them is a
// damaged or mistaken file, not a recording (a reader that uses the rate refuses it).
inline constexpr double kMinDatasetFps = 1.0;
inline constexpr double kMaxDatasetFps = 1000.0;

// Parses DIR/meta/info.json. Throws std::runtime_error naming the file when it is missing, is not
// JSON, has an unknown codebase_version, or lacks a positive fps or a non-negative
// total_episodes.
DatasetInfo ReadDatasetInfo(const std::filesystem::path& dataset_dir);

// The *.parquet files whose name starts with `file_prefix`, in the directories under `root` whose
// name starts with `dir_prefix` (the glob ROOT/DIR_PREFIX*/FILE_PREFIX*.parquet), sorted by path as
// LeRobot sorts its globs; empty when `root` is not a directory.
std::vector<std::filesystem::path> ParquetFilesUnder(const std::filesystem::path& root, const std::string& dir_prefix,
                                                     const std::string& file_prefix);

// The data Parquet files in the order LeRobot reads them (sorted paths); throws naming the
// directory when there are none.
std::vector<std::filesystem::path> DataFiles(const std::filesystem::path& dataset_dir, DatasetVersion version);

}  // namespace tavis::batch::dataset::reader
