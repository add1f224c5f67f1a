// GenerateDemos end to end: the simulator's scripted expert recorded into a small v3.0 dataset
// that the independent readers load, and the same dataset, byte for byte, with 1 and 2 threads.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "batch/dataset/demo_generation.h"
#include "batch/dataset/video/video_log.h"
#include "batch/output/setting_error.h"
#include "tests/batch/dataset/lerobot_dataset_checks.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch::dataset {
namespace {

using namespace testing;  // NOLINT: the test support's many helpers

DemoConfig SmallConfig(const std::string& out) {
  DemoConfig config;
  config.tasks = {"clutter-pick-cube"};
  config.robot = "gr1t2";
  config.episodes = 2;
  config.envs = 2;
  config.seed = 3;
  config.fps = 20;
  config.cameras = {"head", "left_wrist"};
  config.video.width = 64;
  config.video.height = 48;
  config.video.codec = video::VideoCodec::kH264;
  config.config_dir = TAVIS_CONFIG_DIR;
  config.out = out;
  return config;
}

DemoReport Generate(const std::string& out, int threads, bool lock_step = false) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  DemoConfig config = SmallConfig(out);
  config.lock_step = lock_step;
  return GenerateDemos(config);
}

// Every file under `root` by its relative path.
std::map<std::string, std::vector<std::uint8_t>> Files(const std::string& root) {
  std::map<std::string, std::vector<std::uint8_t>> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    if (entry.is_regular_file())
      files[std::filesystem::relative(entry.path(), root).string()] = ReadBytes(entry.path().string());
  }
  return files;
}

class DemoGeneration : public ::testing::Test {
 protected:
  void SetUp() override {
    video::ShowOnlyVideoErrors();
    scratch_ = ScratchDir();
  }
  std::string scratch_;
};

TEST_F(DemoGeneration, ExpertEpisodesLoadAsALeRobotDataset) {
  const DemoReport report = Generate(scratch_ + "/dataset", 2);
  EXPECT_EQ(report.episodes, 2);
  const DatasetView view = LoadDataset(scratch_ + "/dataset");
  EXPECT_EQ(view.info["total_frames"], report.frames);
  EXPECT_EQ(view.info["robot_type"], "gr1t2");
  EXPECT_EQ(view.video_keys.size(), 2u);
  ExpectDataRowsAsLeRobotReadsThem(view);
  ExpectStatsJsonComplete(view);
  ExpectVideosAsLeRobotReadsThem(view, scratch_);

  const std::size_t state_size = tavis::testing::LoadRobot("gr1t2").observation_state.size();
  EXPECT_EQ(view.info["features"]["observation.state"]["shape"], nlohmann::json({state_size}));
  ASSERT_FALSE(view.hyparquet_rows.empty());
  const nlohmann::json& first_state = view.hyparquet_rows[0]["observation.state"];
  ASSERT_EQ(first_state.size(), state_size);
  for (const nlohmann::json& value : first_state)
    EXPECT_TRUE(value.is_number() && std::isfinite(value.get<double>())) << first_state;
  for (const EpisodeEntry& episode : view.episodes) {
    EXPECT_GT(episode.length, 1);
    EXPECT_EQ(episode.tasks, view.tasks) << "one task";
    const nlohmann::json& prompt =
        view.hyparquet_rows.at(static_cast<std::size_t>(episode.from_index))["language_instruction"];
    ASSERT_TRUE(prompt.is_string() && !prompt.get<std::string>().empty());
    for (int64_t row = episode.from_index; row < episode.to_index; ++row) {
      EXPECT_EQ(view.hyparquet_rows[static_cast<std::size_t>(row)]["language_instruction"], prompt) << "row " << row;
    }
  }
}

// Per slot (each slot's frames rendered and encoded on its own thread) on 1 and 2 threads, and
// lock-step (the batch's frames rendered in one call): the same dataset.
TEST_F(DemoGeneration, OneAndTwoThreadsAndEitherScheduleWriteTheSameBytes) {
  Generate(scratch_ + "/one", 1);
  const auto one = Files(scratch_ + "/one");
  const std::vector<std::tuple<std::string, int, bool>> variants = {
      {"two", 2, false}, {"lock_step", 2, true}, {"lock_step_one", 1, true}};
  for (const auto& [name, threads, lock_step] : variants) {
    Generate(scratch_ + "/" + name, threads, lock_step);
    const auto other = Files(scratch_ + "/" + name);
    ASSERT_EQ(one.size(), other.size()) << name;
    int compared_media = 0;
    for (const auto& [path, bytes] : one) {
      ASSERT_TRUE(other.count(path)) << path << " only with one thread per slot, not " << name;
      EXPECT_TRUE(bytes == other.at(path)) << path << " differs between one thread per slot and " << name;
      const std::string extension = std::filesystem::path(path).extension().string();
      compared_media += extension == ".parquet" || extension == ".mp4" ? 1 : 0;
    }
    EXPECT_EQ(compared_media, 3 + 2) << "data, episodes and tasks tables and two mp4 files";
  }
}

// A bad setting is named by its key in the spool's settings (`tavis demos` names its flag).
TEST(DemoConfigCheck, BadSettingsAreNamedByTheirKeys) {
  const auto error_of = [](const DemoConfig& config) -> std::string {
    try {
      ValidateDemoConfig(config);
    } catch (const output::SettingError& error) {
      return error.what();
    }
    return "accepted";
  };
  DemoConfig config = SmallConfig("unused");
  EXPECT_EQ(error_of(config), "accepted");
  config.episodes = 0;
  EXPECT_EQ(error_of(config), "episodes must be at least 1, got 0");
  config = SmallConfig("unused");
  config.max_attempts = 1;
  EXPECT_EQ(error_of(config), "max_attempts 1 is below episodes 2 (0: 2 x episodes + 20)");
  config = SmallConfig("unused");
  config.fps = 30;
  EXPECT_EQ(error_of(config), "fps must be 60 or 20, got 30");
  config = SmallConfig("unused");
  config.expert_hz = 10;
  EXPECT_EQ(error_of(config), "expert_hz must be 60 or 20, got 10");
}

}  // namespace
}  // namespace tavis::batch::dataset
