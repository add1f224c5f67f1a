// Test support: what LeRobot needs of any dataset, checked on a DatasetView with gtest
// expectations: the data rows' columns, widths and bookkeeping, the per-episode metadata, the
// stats.json entries, and every mp4 as PyAV reads it with LeRobot's lookup.
#pragma once

#include <map>
#include <string>
#include <tuple>

#include "tests/batch/dataset/lerobot_dataset_view.h"
#include "tests/batch/dataset/synthetic_frames.h"

namespace tavis::batch::dataset::testing {

// Columns = info.json's non-video features, vector widths = their shapes, hyparquet and DuckDB
// agree on every row, index 0..N-1 in file order, each episode a run of frame_index 0..len-1 with
// timestamp frame_index / fps as float32 and a task_index naming one of the episode's tasks.
void ExpectDataRowsAsLeRobotReadsThem(const DatasetView& view);

// stats.json: the ten statistics of every non-string feature, with LeRobot's shapes.
void ExpectStatsJsonComplete(const DatasetView& view);

// (video key, episode, frame_index) -> the frame LeRobot's PyAV lookup decodes.
using LookedUpFrames = std::map<std::tuple<std::string, int64_t, int>, RgbFrame>;

// Every mp4: frames, rate, pix_fmt and size; a keyframe where each episode starts; each episode's
// from_timestamp the previous one's to_timestamp (0 first in a file), the stream duration the last
// one's; LeRobot's lookup finds the first, middle and last frame of every episode (returned).
LookedUpFrames ExpectVideosAsLeRobotReadsThem(const DatasetView& view, const std::string& scratch_dir);

}  // namespace tavis::batch::dataset::testing
