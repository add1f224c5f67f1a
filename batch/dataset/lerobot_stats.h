// A dataset's normalisation statistics per feature (lerobot-v3-format.md 4): of each episode (the
// episodes table's stats/* columns, v2.1's episodes_stats.jsonl) and of the whole dataset
// (meta/stats.json). Every numeric feature has them, the cameras too; language_instruction not.
#pragma once

#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "batch/dataset/feature_stats.h"
#include "batch/dataset/lerobot_features.h"
#include "batch/dataset/recorded_episode.h"

namespace tavis::batch::dataset {

struct DatasetStats {
  std::map<std::string, NumericStats> numeric;  // vector and bookkeeping features
  std::map<std::string, ImageStats> images;     // camera video keys

  void Merge(const DatasetStats& other);
  // feature -> {min, max, mean, std, count, q01, ..., q99}: vectors as lists, cameras as 3x1x1
  // nested lists, as stats.json holds them.
  nlohmann::json ToJson() const;
};

// The statistics of `episode`, stored as dataset episode `episode_index` whose first frame has the
// global index `first_index`.
DatasetStats EpisodeStats(const RecordedEpisode& episode, const DatasetLayout& layout, int64_t episode_index,
                          int64_t first_index);

// The names of the statistics, in the order the episodes table's stats/<feature>/<stat> columns use.
inline const std::vector<std::string> kStatNames = {"min", "max", "mean", "std", "count",
                                                    "q01", "q10", "q50",  "q90", "q99"};

// The values of one statistic of `stats` (count as a one-entry list).
std::vector<double> StatValues(const FeatureStats& stats, const std::string& stat);

}  // namespace tavis::batch::dataset
