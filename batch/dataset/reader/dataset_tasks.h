// The task strings of each episode, from a LeRobot dataset's episode metadata:
// v3.0 meta/episodes/*/*.parquet (columns episode_index, tasks list<string>),
// v2.1 meta/episodes.jsonl (one {"episode_index", "tasks", ...} object per line).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "batch/dataset/reader/dataset_info.h"

namespace tavis::batch::dataset::reader {

// episode_index -> tasks. Empty when the dataset has no episode metadata (it is optional for
// reading actions); throws std::runtime_error naming the file when metadata exists but is broken.
std::map<std::int64_t, std::vector<std::string>> ReadEpisodeTasks(const std::filesystem::path& dataset_dir,
                                                                  DatasetVersion version);

}  // namespace tavis::batch::dataset::reader
