// Writes recorded episodes as a LeRobot dataset (lerobot-v3-format.md; policy-interfaces.md C).
//
// v3.0 (LeRobot's format since 0.4): data/chunk-XXX/file-XXX.parquet (many episodes per file, one
// row group each, a new file at 100 MB), videos/<key>/chunk-XXX/file-XXX.mp4 (episodes back to
// back, each starting on a keyframe, a new file at 200 MB), meta/episodes/... (one row per episode:
// offsets, video timestamps, per-episode stats), meta/tasks.parquet, meta/stats.json (with the
// quantiles) and meta/info.json.
// v2.1 (what openpi trains from): one parquet and one mp4 per camera per episode,
// meta/episodes.jsonl, meta/tasks.jsonl, meta/episodes_stats.jsonl, meta/info.json.
//
// Episodes are stored in the order Add receives them. Every data and video file is written under
// FILE.partial and renamed when complete, and the metadata is written last (info.json last of
// all), so a dataset without meta/info.json is an unfinished one and no file is ever truncated.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "batch/dataset/lerobot_features.h"
#include "batch/dataset/recorded_episode.h"

namespace tavis::batch::dataset {

class DatasetWriter {
 public:
  virtual ~DatasetWriter() = default;
  // Stores `episode` as the next dataset episode. Throws std::runtime_error naming the file on
  // an I/O failure (unwritable path, disk full).
  virtual void Add(const RecordedEpisode& episode) = 0;
  // Closes the files and writes the metadata: the dataset is complete.
  virtual void Finish() = 0;
  virtual int64_t episodes() const = 0;
  virtual int64_t frames() const = 0;
};

// A writer of `layout.version` into `root` (created; it should be empty).
std::unique_ptr<DatasetWriter> MakeDatasetWriter(const std::string& root, const DatasetLayout& layout);

}  // namespace tavis::batch::dataset
