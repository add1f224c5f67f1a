// Reads the commanded actions of a LeRobot dataset (v3.0 or v2.1 layout) from disk: what GALT and
// other trajectory tools need, without videos or the simulator.
//
//   v3.0: DIR/data/*/*.parquet (many episodes per file), tasks in DIR/meta/episodes/*/*.parquet
//   v2.1: DIR/data/chunk-*/episode_*.parquet (one episode per file), tasks in meta/episodes.jsonl
//
// Data files are read in sorted path order, as LeRobot globs them. Every problem throws
// std::runtime_error naming the file and what is wrong: a missing or malformed meta/info.json, an
// unknown codebase_version, no data files, an `action` row that is not 19 wide, a non-finite
// action value, rows not grouped by episode in increasing order, a frame_index that is not
// 0..T-1 within its episode, an episode count that disagrees with total_episodes, a truncated or
// corrupt Parquet file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "batch/dataset/reader/dataset_info.h"

namespace tavis::batch::dataset::reader {

inline constexpr int kDatasetActionWidth = 19;  // the canonical action (reference spec 5)

struct EpisodeActions {
  std::int64_t episode_index = 0;
  std::vector<std::string> tasks;  // the episode's task strings; empty when the metadata lacks them
  std::vector<double> values;      // num_steps x kDatasetActionWidth, row-major, in frame order
  int num_steps = 0;
};

struct DatasetActions {
  DatasetInfo info;
  std::vector<EpisodeActions> episodes;  // in increasing episode_index
};

// Reads info.json, every data file's `action`, `episode_index` and `frame_index` columns, and the
// episodes' tasks when the episode metadata is present.
DatasetActions ReadDatasetActions(const std::filesystem::path& dataset_dir);

}  // namespace tavis::batch::dataset::reader
