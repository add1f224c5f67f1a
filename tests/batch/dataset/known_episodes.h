// Test support: three hand-built episodes with values a test can recompute (no simulator), as
// the dataset writers receive them: two tasks (task_index 0, 1, 0), lengths 7, 12 and 5, two
// cameras at 64x48 whose frames are SyntheticFrames encoded at the layout's fps.
#pragma once

#include <string>
#include <vector>

#include "batch/dataset/lerobot_features.h"
#include "batch/dataset/recorded_episode.h"
#include "tests/batch/dataset/synthetic_frames.h"

namespace tavis::batch::dataset::testing {

inline const std::vector<int> kKnownLengths = {7, 12, 5};
inline const std::vector<int> kKnownTaskIndex = {0, 1, 0};
constexpr int kKnownFps = 30;
constexpr int kKnownStateSize = 5;

struct KnownDataset {
  DatasetLayout layout;
  std::vector<RecordedEpisode> episodes;
  std::vector<std::vector<std::vector<RgbFrame>>> frames;  // [episode][camera][frame], as encoded
};

// Not a power-of-two fraction, so a float32 stored as a double or a decimal would show.
float KnownValue(int feature, int episode, int frame, int dim);

// Feature numbers of KnownValue: action 0, observation.state 1, then the eef vectors 2..5.
KnownDataset MakeKnownDataset(DatasetVersion version);

// Writes `dataset` with MakeDatasetWriter into `root`.
void WriteKnownDataset(const KnownDataset& dataset, const std::string& root);

}  // namespace tavis::batch::dataset::testing
