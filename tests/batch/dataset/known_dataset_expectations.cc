#include "tests/batch/dataset/known_dataset_expectations.h"

#include <gtest/gtest.h>

#include <vector>

namespace tavis::batch::dataset::testing {

void ExpectRowsHoldKnownValues(const DatasetView& view, const KnownDataset& known) {
  ASSERT_EQ(view.episodes.size(), known.episodes.size());
  ASSERT_EQ(view.tasks, known.layout.tasks);
  const std::vector<VectorFeature> features = VectorFeatures(known.layout);
  for (std::size_t e = 0; e < known.episodes.size(); ++e) {
    const RecordedEpisode& episode = known.episodes[e];
    const EpisodeEntry& entry = view.episodes[e];
    ASSERT_EQ(entry.length, episode.frames) << "episode " << e;
    EXPECT_EQ(entry.tasks, std::vector<std::string>{known.layout.tasks[static_cast<std::size_t>(episode.task_index)]})
        << "episode " << e;
    for (int64_t k = 0; k < episode.frames; ++k) {
      const nlohmann::json& row = view.hyparquet_rows.at(static_cast<std::size_t>(entry.from_index + k));
      EXPECT_EQ(Int(row["task_index"]), episode.task_index);
      EXPECT_EQ(row["language_instruction"], episode.prompt);
      for (std::size_t f = 0; f < features.size(); ++f) {
        const nlohmann::json& values = row[features[f].name];
        ASSERT_EQ(values.size(), static_cast<std::size_t>(features[f].size)) << features[f].name;
        for (int d = 0; d < features[f].size; ++d) {
          // Exact: a float32 read back is the float written.
          EXPECT_EQ(values[static_cast<std::size_t>(d)].get<double>(),
                    static_cast<double>(KnownValue(static_cast<int>(f), static_cast<int>(e), static_cast<int>(k), d)))
              << features[f].name << "[" << d << "] episode " << e << " frame " << k;
        }
      }
    }
  }
}

void ExpectLookedUpFramesAreKnown(const LookedUpFrames& frames, const KnownDataset& known) {
  EXPECT_EQ(frames.size(), known.layout.cameras.size() * known.episodes.size() * 3);
  for (const auto& [where, decoded] : frames) {
    const auto& [key, episode, k] = where;
    std::size_t camera = 0;
    while (camera < known.layout.cameras.size() && CameraVideoKey(known.layout.cameras[camera]) != key) ++camera;
    ASSERT_LT(camera, known.layout.cameras.size()) << key;
    const std::vector<RgbFrame>& encoded = known.frames[static_cast<std::size_t>(episode)][camera];
    const std::string name = key + " episode " + std::to_string(episode) + " frame " + std::to_string(k);
    EXPECT_GE(Psnr(decoded, encoded[static_cast<std::size_t>(k)]), 30.0) << name;
    EXPECT_LT(Psnr(decoded, encoded[static_cast<std::size_t>(k == 0 ? 1 : k - 1)]), 25.0) << name << " (the neighbour)";
  }
}

}  // namespace tavis::batch::dataset::testing
