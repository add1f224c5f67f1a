// The v3.0 writer on hand-built episodes of known values (no simulator), read back by readers we
// did not write: hyparquet and DuckDB for the Parquet files, nlohmann for the JSON, PyAV for the
// mp4 files with LeRobot's lookup.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include "tests/batch/dataset/known_dataset_expectations.h"
#include "tests/batch/dataset/node_parquet.h"

namespace tavis::batch::dataset {
namespace {

using namespace testing;  // NOLINT: the test support's many helpers

// The dataset is written and read once for the suite: each test checks one side of it.
struct Written {
  KnownDataset known;
  DatasetView view;
};

const Written& V30() {
  static const Written written = [] {
    // Its own folder: ScratchDir() empties the running test's.
    const std::string root =
        (std::filesystem::path(::testing::TempDir()) / ("tavis_dataset_v30_" + std::to_string(getpid()))).string();
    std::filesystem::remove_all(root);
    Written result{MakeKnownDataset(DatasetVersion::kV30), {}};
    WriteKnownDataset(result.known, root);
    result.view = LoadDataset(root);
    return result;
  }();
  return written;
}

int64_t TotalFrames() { return std::accumulate(kKnownLengths.begin(), kKnownLengths.end(), int64_t{0}); }

TEST(LeRobotV30Writer, DataRowsHoldWhatWasWritten) {
  const Written& written = V30();
  ASSERT_EQ(written.view.data_files.size(), 1u);
  EXPECT_EQ(written.view.data_files[0], written.view.root + "/data/chunk-000/file-000.parquet");
  ExpectDataRowsAsLeRobotReadsThem(written.view);
  ExpectRowsHoldKnownValues(written.view, written.known);
}

TEST(LeRobotV30Writer, EpisodesTableLocatesEveryEpisode) {
  const Written& written = V30();
  const nlohmann::json& table = written.view.episodes_table;
  ASSERT_EQ(table["hyparquet"]["rows"], table["duckdb"]["rows"]);
  const nlohmann::json& rows = table["hyparquet"]["rows"];
  ASSERT_EQ(rows.size(), kKnownLengths.size());
  int64_t from = 0;
  for (std::size_t e = 0; e < rows.size(); ++e) {
    const nlohmann::json& row = rows[e];
    const int64_t length = kKnownLengths[e];
    EXPECT_EQ(Int(row["episode_index"]), static_cast<int64_t>(e));
    EXPECT_EQ(Int(row["length"]), length);
    EXPECT_EQ(row["tasks"], nlohmann::json({written.known.layout.tasks[static_cast<std::size_t>(kKnownTaskIndex[e])]}));
    EXPECT_EQ(Int(row["data/chunk_index"]), 0);
    EXPECT_EQ(Int(row["data/file_index"]), 0);
    EXPECT_EQ(Int(row["dataset_from_index"]), from);
    EXPECT_EQ(Int(row["dataset_to_index"]), from + length);
    EXPECT_EQ(Int(row["meta/episodes/chunk_index"]), 0);
    EXPECT_EQ(Int(row["meta/episodes/file_index"]), 0);
    for (const std::string& camera : written.known.layout.cameras) {
      const std::string prefix = "videos/" + CameraVideoKey(camera) + "/";
      EXPECT_EQ(Int(row[prefix + "chunk_index"]), 0) << prefix;
      EXPECT_EQ(Int(row[prefix + "file_index"]), 0) << prefix;
      EXPECT_DOUBLE_EQ(row[prefix + "from_timestamp"].get<double>(), static_cast<double>(from) / kKnownFps) << prefix;
      // The stats columns: vectors [n], count [1] (the episode's frames), cameras 3x1x1.
      EXPECT_EQ(row["stats/" + CameraVideoKey(camera) + "/count"], nlohmann::json({std::to_string(length)}));
      const nlohmann::json& mean = row["stats/" + CameraVideoKey(camera) + "/mean"];
      ASSERT_EQ(mean.size(), 3u) << prefix;
      for (const nlohmann::json& channel : mean)
        EXPECT_TRUE(channel.size() == 1 && channel[0].size() == 1 && channel[0][0].is_number()) << mean;
    }
    for (const VectorFeature& feature : VectorFeatures(written.known.layout)) {
      for (const char* stat : {"min", "max", "mean", "std", "q01", "q10", "q50", "q90", "q99"}) {
        EXPECT_EQ(row["stats/" + feature.name + "/" + stat].size(), static_cast<std::size_t>(feature.size))
            << feature.name << stat;
      }
      EXPECT_EQ(row["stats/" + feature.name + "/count"], nlohmann::json({std::to_string(length)})) << feature.name;
    }
    for (const std::string& scalar : kIndexFeatures) EXPECT_EQ(row["stats/" + scalar + "/max"].size(), 1u) << scalar;
    // The episode's own action mean, of dimension 0.
    double sum = 0;
    for (int k = 0; k < length; ++k) sum += static_cast<double>(KnownValue(0, static_cast<int>(e), k, 0));
    EXPECT_NEAR(row["stats/action/mean"][0].get<double>(), sum / static_cast<double>(length), 1e-6);
    from += length;
  }
}

TEST(LeRobotV30Writer, TasksTableIsAPandasFrameIndexedByTask) {
  const nlohmann::json& table = V30().view.tasks_table;
  EXPECT_EQ(table["hyparquet"]["rows"], table["duckdb"]["rows"]);
  EXPECT_EQ(
      table["duckdb"]["rows"],
      nlohmann::json::parse(R"([{"task_index": "0", "task": "PickTask"}, {"task_index": "1", "task": "PlaceTask"}])"));
  bool pandas = false;
  for (const nlohmann::json& entry : table["duckdb"]["key_value_metadata"]) {
    if (entry["key"] != "pandas") continue;
    pandas = true;
    EXPECT_EQ(nlohmann::json::parse(entry["value"].get<std::string>())["index_columns"], nlohmann::json({"task"}));
  }
  EXPECT_TRUE(pandas) << "pandas would not rebuild the task index: " << table["duckdb"]["key_value_metadata"];
}

TEST(LeRobotV30Writer, InfoJsonDeclaresTheLayout) {
  const Written& written = V30();
  const nlohmann::json& info = written.view.info;
  EXPECT_EQ(info["codebase_version"], "v3.0");
  EXPECT_EQ(info["robot_type"], "known");
  EXPECT_EQ(info["total_episodes"], 3);
  EXPECT_EQ(info["total_frames"], TotalFrames());
  EXPECT_EQ(info["total_tasks"], 2);
  EXPECT_TRUE(info["fps"].is_number_integer()) << info["fps"];
  EXPECT_EQ(info["fps"], kKnownFps);
  EXPECT_EQ(info["splits"]["train"], "0:3");
  EXPECT_EQ(info["data_path"], "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet");
  EXPECT_EQ(info["video_path"], "videos/{video_key}/chunk-{chunk_index:03d}/file-{file_index:03d}.mp4");
  const nlohmann::json& features = info["features"];
  EXPECT_EQ(features["action"]["shape"], nlohmann::json({19}));
  EXPECT_EQ(features["observation.state"]["shape"], nlohmann::json({kKnownStateSize}));
  EXPECT_EQ(features["observation.state"]["names"], nlohmann::json({"s0", "s1", "s2", "s3", "s4"}));
  for (const std::string key : {"observation.images.OBS_HEAD", "observation.images.OBS_WRIST_LEFT"}) {
    EXPECT_EQ(features[key]["dtype"], "video") << key;
    EXPECT_EQ(features[key]["shape"], nlohmann::json({48, 64, 3})) << key;
    EXPECT_EQ(features[key]["names"], nlohmann::json({"height", "width", "channels"})) << key;
    EXPECT_EQ(features[key]["info"]["video.codec"], "h264") << key;
  }
  EXPECT_EQ(written.view.video_keys.size(), 2u);
}

TEST(LeRobotV30Writer, StatsJsonHasEveryStatisticOfTheWrittenValues) {
  const Written& written = V30();
  ExpectStatsJsonComplete(written.view);
  const nlohmann::json& action = written.view.stats["action"];
  for (int d = 0; d < 19; ++d) {
    double sum = 0, min = 1e30, max = -1e30;
    for (std::size_t e = 0; e < kKnownLengths.size(); ++e) {
      for (int k = 0; k < kKnownLengths[e]; ++k) {
        const double value = KnownValue(0, static_cast<int>(e), k, d);
        sum += value;
        min = std::min(min, value);
        max = std::max(max, value);
      }
    }
    EXPECT_NEAR(action["mean"][static_cast<std::size_t>(d)].get<double>(), sum / static_cast<double>(TotalFrames()),
                1e-6)
        << d;
    EXPECT_EQ(action["min"][static_cast<std::size_t>(d)].get<double>(), min) << d;
    EXPECT_EQ(action["max"][static_cast<std::size_t>(d)].get<double>(), max) << d;
  }
  EXPECT_EQ(written.view.stats["episode_index"]["max"], nlohmann::json({2.0}));
  EXPECT_EQ(written.view.stats["index"]["max"], nlohmann::json({static_cast<double>(TotalFrames() - 1)}));
}

TEST(LeRobotV30Writer, VideosPlayTheEncodedFramesAtLeRobotsTimestamps) {
  const Written& written = V30();
  for (const std::string& key : written.view.video_keys) {
    EXPECT_TRUE(std::filesystem::exists(written.view.root + "/videos/" + key + "/chunk-000/file-000.mp4")) << key;
  }
  const LookedUpFrames frames = ExpectVideosAsLeRobotReadsThem(written.view, ScratchDir());
  ExpectLookedUpFramesAreKnown(frames, written.known);
}

}  // namespace
}  // namespace tavis::batch::dataset
