// `tavis eval --record`'s dataset end to end: a cell's rollouts written through CellRecording pass
// the independent-reader checks `tavis demos` datasets pass (hyparquet and DuckDB for the Parquet
// files, PyAV with LeRobot's lookup for the videos), hold one frame per policy step, leave the
// records as they are, and their action column, read back by hyparquet and replayed, gives the
// same records.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "batch/action_csv.h"
#include "batch/cell/cell_report.h"
#include "batch/dataset/video/video_log.h"
#include "batch/rollout/cell_recording.h"
#include "tests/batch/dataset/lerobot_dataset_checks.h"
#include "tests/batch/dataset/synthetic_frames.h"

namespace tavis::batch::rollout {
namespace {

namespace fs = std::filesystem;
using namespace dataset::testing;  // NOLINT: the dataset test support's helpers

cell::EvaluationCellConfig Cell(const std::string& policy, const std::string& actions) {
  cell::EvaluationCellConfig config;
  config.task = "clutter-pick-cube";
  config.episodes = 2;
  config.envs = 2;
  config.seed = 3;
  config.config_dir = TAVIS_CONFIG_DIR;
  config.policy = policy;
  config.actions_file = actions;
  if (policy == "expert") config.expert_hz = 20;  // its actions kept at 20 Hz for replay
  return config;
}

std::vector<std::string> Lines(const std::vector<cell::EpisodeRecord>& records, uint64_t seed) {
  std::vector<std::string> lines;
  for (const cell::EpisodeRecord& record : records) lines.push_back(cell::EpisodeJsonLine(record, seed));
  return lines;
}

class RolloutDataset : public ::testing::Test {
 protected:
  void SetUp() override {
    dataset::video::ShowOnlyVideoErrors();
    scratch_ = ScratchDir();
  }
  std::string scratch_;
};

TEST_F(RolloutDataset, LoadsAsLeRobotDatasetAndItsActionsReplayTheRecords) {
  // A policy whose actions are float32 values (the dataset's action dtype), so that the dataset
  // holds them exactly: the 20 Hz expert's actions rounded to float, replayed.
  const cell::CellResult expert = cell::RunEvaluationCell(Cell("expert", ""));
  const fs::path rounded = fs::path(scratch_) / "rounded";
  fs::create_directories(rounded);
  for (const cell::EpisodeRecord& record : expert.episodes) {
    std::vector<kinematics::Action> rows = record.replay_actions;
    for (kinematics::Action& row : rows) {
      for (double& value : row) value = static_cast<float>(value);
    }
    WriteActionCsv(rounded / ("episode_" + std::to_string(record.episode) + ".csv"), rows);
  }
  const cell::EvaluationCellConfig cell = Cell("replay", rounded.string());
  const cell::CellResult plain = cell::RunEvaluationCell(cell);

  RolloutDatasetSettings settings;
  settings.root = scratch_ + "/dataset";
  settings.width = 64;
  settings.height = 48;
  CellRecording recording(settings, cell);
  const cell::CellResult recorded = cell::RunEvaluationCell(
      cell, nullptr, [&recording](const cell::EpisodeRecord& record) { recording.RecordFinished(record); },
      recording.Sinks());
  recording.Finish();
  EXPECT_EQ(Lines(recorded.episodes, cell.seed), Lines(plain.episodes, cell.seed)) << "recording changed the records";

  const DatasetView view = LoadDataset(settings.root);
  ExpectDataRowsAsLeRobotReadsThem(view);
  ExpectStatsJsonComplete(view);
  ExpectVideosAsLeRobotReadsThem(view, scratch_);
  EXPECT_EQ(view.fps, 20);
  EXPECT_EQ(view.video_keys,
            (std::vector<std::string>{"observation.images.OBS_HEAD", "observation.images.OBS_WRIST_LEFT",
                                      "observation.images.OBS_WRIST_RIGHT"}));
  ASSERT_EQ(view.episodes.size(), plain.episodes.size());
  for (std::size_t i = 0; i < view.episodes.size(); ++i) {
    EXPECT_EQ(view.episodes[i].length, plain.episodes[i].length_steps) << "episode " << i;
  }
  // tavis_rollouts.jsonl: each dataset episode's index and the cell's record of it.
  std::ifstream rollouts(settings.root + "/tavis_rollouts.jsonl");
  std::size_t index = 0;
  for (std::string line; std::getline(rollouts, line); ++index) {
    ASSERT_LT(index, plain.episodes.size());
    const nlohmann::json entry = nlohmann::json::parse(line);
    EXPECT_EQ(entry.at("episode_index"), index);
    EXPECT_EQ(entry.at("episode"), plain.episodes[index].episode);
    EXPECT_EQ(entry.at("success"), plain.episodes[index].success);
    EXPECT_EQ(entry.at("end"), engine::ToString(plain.episodes[index].end));
  }
  EXPECT_EQ(index, plain.episodes.size());

  // The action column as hyparquet reads it, replayed at 20 Hz, gives the same records.
  std::map<int64_t, std::vector<kinematics::Action>> actions;
  for (const nlohmann::json& row : view.hyparquet_rows) {
    kinematics::Action action{};
    ASSERT_EQ(row.at("action").size(), action.size());
    for (std::size_t d = 0; d < action.size(); ++d) action[d] = row.at("action")[d].get<double>();
    actions[Int(row.at("episode_index"))].push_back(action);
  }
  const fs::path from_dataset = fs::path(scratch_) / "from_dataset";
  fs::create_directories(from_dataset);
  for (const auto& [episode, rows] : actions)
    WriteActionCsv(from_dataset / ("episode_" + std::to_string(episode) + ".csv"), rows);
  const cell::CellResult replayed = cell::RunEvaluationCell(Cell("replay", from_dataset.string()));
  EXPECT_EQ(Lines(replayed.episodes, cell.seed), Lines(plain.episodes, cell.seed));
}

}  // namespace
}  // namespace tavis::batch::rollout
