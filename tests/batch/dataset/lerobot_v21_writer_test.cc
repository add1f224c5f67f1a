// The v2.1 writer (what openpi trains from) on the known episodes: one data file and one mp4 per
// camera per episode at info.json's templates, JSON-lines metadata, each mp4 starting at 0.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/batch/dataset/known_dataset_expectations.h"

namespace tavis::batch::dataset {
namespace {

using namespace testing;  // NOLINT: the test support's many helpers

std::vector<nlohmann::json> JsonLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<nlohmann::json> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

class LeRobotV21Writer : public ::testing::Test {
 protected:
  void SetUp() override {
    scratch_ = ScratchDir();
    root_ = scratch_ + "/dataset";
    known_ = MakeKnownDataset(DatasetVersion::kV21);
    WriteKnownDataset(known_, root_);
  }

  std::string scratch_, root_;
  KnownDataset known_;
};

TEST_F(LeRobotV21Writer, OneFilePerEpisodeAtInfoJsonsTemplates) {
  const nlohmann::json info = nlohmann::json::parse(std::ifstream(root_ + "/meta/info.json"));
  EXPECT_EQ(info["codebase_version"], "v2.1");
  EXPECT_EQ(info["total_episodes"], 3);
  EXPECT_EQ(info["total_frames"], 24);
  EXPECT_EQ(info["total_tasks"], 2);
  EXPECT_EQ(info["total_chunks"], 1);
  EXPECT_EQ(info["total_videos"], 6);
  EXPECT_EQ(info["data_path"], "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet");
  EXPECT_EQ(info["video_path"], "videos/chunk-{episode_chunk:03d}/{video_key}/episode_{episode_index:06d}.mp4");
  for (int e = 0; e < 3; ++e) {
    const std::string name = "episode_00000" + std::to_string(e);
    EXPECT_TRUE(std::filesystem::exists(root_ + "/data/chunk-000/" + name + ".parquet")) << name;
    for (const std::string& camera : known_.layout.cameras) {
      EXPECT_TRUE(std::filesystem::exists(root_ + "/videos/chunk-000/" + CameraVideoKey(camera) + "/" + name + ".mp4"))
          << camera << name;
    }
  }
  EXPECT_FALSE(std::filesystem::exists(root_ + "/meta/episodes")) << "v3.0's episodes table in a v2.1 dataset";
  const std::vector<nlohmann::json> tasks = JsonLines(root_ + "/meta/tasks.jsonl");
  EXPECT_EQ(tasks, (std::vector<nlohmann::json>{{{"task_index", 0}, {"task", "PickTask"}},
                                                {{"task_index", 1}, {"task", "PlaceTask"}}}));
  const std::vector<nlohmann::json> episodes = JsonLines(root_ + "/meta/episodes.jsonl");
  ASSERT_EQ(episodes.size(), 3u);
  for (std::size_t e = 0; e < 3; ++e) {
    EXPECT_EQ(episodes[e],
              (nlohmann::json{{"episode_index", e},
                              {"tasks", {known_.layout.tasks[static_cast<std::size_t>(kKnownTaskIndex[e])]}},
                              {"length", kKnownLengths[e]}}));
  }
}

TEST_F(LeRobotV21Writer, EpisodesStatsHoldEachEpisodesStatistics) {
  const std::vector<nlohmann::json> lines = JsonLines(root_ + "/meta/episodes_stats.jsonl");
  ASSERT_EQ(lines.size(), 3u);
  for (std::size_t e = 0; e < 3; ++e) {
    EXPECT_EQ(lines[e]["episode_index"], e);
    const nlohmann::json& stats = lines[e]["stats"];
    EXPECT_EQ(stats["action"]["count"], nlohmann::json({kKnownLengths[e]}));
    EXPECT_EQ(stats["action"]["min"][0].get<double>(), static_cast<double>(KnownValue(0, static_cast<int>(e), 0, 0)));
    EXPECT_EQ(stats["frame_index"]["max"], nlohmann::json({kKnownLengths[e] - 1.0}));
    EXPECT_EQ(stats["observation.images.OBS_HEAD"]["mean"].size(), 3u);
  }
}

TEST_F(LeRobotV21Writer, ReadersSeeTheWrittenRowsAndFrames) {
  const DatasetView view = LoadDataset(root_);
  ExpectDataRowsAsLeRobotReadsThem(view);
  ExpectRowsHoldKnownValues(view, known_);
  ExpectStatsJsonComplete(view);
  ExpectLookedUpFramesAreKnown(ExpectVideosAsLeRobotReadsThem(view, scratch_), known_);
}

}  // namespace
}  // namespace tavis::batch::dataset
