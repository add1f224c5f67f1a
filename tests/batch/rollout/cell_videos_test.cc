#include "batch/rollout/cell_videos.h"

#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "batch/rollout/video_frame.h"
#include "render/image_io.h"
#include "tests/support/test_folder.h"

namespace tavis::batch::rollout {
namespace {

namespace fs = std::filesystem;

class CellVideosTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TestFolderPath("cell_videos");
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static cell::EvaluationCellConfig Cell(const std::string& task, int episodes) {
    cell::EvaluationCellConfig config;
    config.task = task;
    config.episodes = episodes;
    config.envs = 2;
    config.seed = 5;
    config.config_dir = TAVIS_CONFIG_DIR;
    config.keep_actions = true;
    return config;
  }

  // The cell's records, filming it with `videos` (none when videos.episodes is 0).
  std::vector<cell::EpisodeRecord> Run(const cell::EvaluationCellConfig& config, const EpisodeVideoSettings& videos) {
    CellVideos films(videos, config, [this] { return dir_ / "videos"; });
    cell::CellResult result = cell::RunEvaluationCell(
        config, nullptr, [&films](const cell::EpisodeRecord& record) { films.RecordFinished(record); }, films.Sinks());
    return result.episodes;
  }

  static std::set<std::string> Entries(const fs::path& dir) {
    std::set<std::string> names;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename().string());
    return names;
  }

  fs::path dir_;
};

TEST_F(CellVideosTest, FilmingChangesNoRecordAndFilmsOnlyTheFirstEpisodes) {
  const cell::EvaluationCellConfig config = Cell("clutter-pick-cube", 3);
  const std::vector<cell::EpisodeRecord> plain = Run(config, {});
  EXPECT_FALSE(fs::exists(dir_ / "videos"));
  EpisodeVideoSettings videos;
  videos.episodes = 2;
  videos.tile_width = 96;
  videos.tile_height = 72;
  const std::vector<cell::EpisodeRecord> filmed = Run(config, videos);
  ASSERT_EQ(plain.size(), filmed.size());
  for (std::size_t i = 0; i < plain.size(); ++i) {
    EXPECT_EQ(plain[i].episode, filmed[i].episode);
    EXPECT_EQ(plain[i].end, filmed[i].end);
    EXPECT_EQ(plain[i].length_control_ticks, filmed[i].length_control_ticks);
    EXPECT_EQ(plain[i].actions, filmed[i].actions) << "episode " << i;
  }
  EXPECT_EQ(Entries(dir_ / "videos"), (std::set<std::string>{"episode_0.mp4", "episode_1.mp4"}));
  EXPECT_GT(fs::file_size(dir_ / "videos" / "episode_0.mp4"), 1000u);
  // Each episode's time split (cell/episode_times.h): a filmed episode's time has video in it,
  // one of a cell without videos none.
  for (std::size_t i = 0; i < plain.size(); ++i) {
    ASSERT_TRUE(plain[i].times.has_value() && filmed[i].times.has_value()) << "episode " << i;
    EXPECT_EQ(plain[i].times->part(cell::EpisodeTimes::kVideo), 0.0) << "episode " << i;
  }
  EXPECT_GT(filmed[0].times->part(cell::EpisodeTimes::kVideo), 0.0);
  EXPECT_GT(filmed[1].times->part(cell::EpisodeTimes::kVideo), 0.0);
}

TEST_F(CellVideosTest, PngFramesOnePerPolicyStepAndTheEndWithTheTasksBlackCameraBlack) {
  // blocked-clutter-pick-cube's head camera is black for the policy, so in the video too.
  cell::EvaluationCellConfig config = Cell("blocked-clutter-pick-cube", 1);
  config.episode_start = 4;  // one chosen episode: its video is named by its index
  config.first_episode = 4;
  EpisodeVideoSettings videos;
  videos.episodes = 1;
  videos.cameras = {"head", "fixed"};
  videos.tile_width = 64;
  videos.tile_height = 48;
  videos.format = VideoFormat::kPng;
  const std::vector<cell::EpisodeRecord> records = Run(config, videos);
  ASSERT_EQ(records.size(), 1u);
  const fs::path frames = dir_ / "videos" / "episode_4";
  const std::set<std::string> names = Entries(frames);
  ASSERT_EQ(names.size(), static_cast<std::size_t>(records[0].length_steps + 1));
  EXPECT_EQ(*names.begin(), "frame_00000.png");
  const render::RgbImage last = render::ReadPng((frames / *names.rbegin()).string());
  const auto [width, height] = VideoFrameSize(2, 64, 48);
  EXPECT_EQ(last.width, width);
  EXPECT_EQ(last.height, height);
  // Bottom rows of the two tiles (labels sit at the top): head black, fixed lit.
  long head = 0, fixed = 0;
  for (int y = height - 4 - 10; y < height - 4; ++y) {
    for (int x = 4 + 10; x < 4 + 54; ++x) head += last.pixels[(static_cast<std::size_t>(y) * width + x) * 3 + 1];
    for (int x = 8 + 64 + 10; x < 8 + 64 + 54; ++x)
      fixed += last.pixels[(static_cast<std::size_t>(y) * width + x) * 3 + 1];
  }
  EXPECT_EQ(head, 0);
  EXPECT_GT(fixed, 10 * 44 * 30);
}

TEST(EpisodeVideoSettings, DefaultCamerasArePoliciesThenFixed) {
  const EpisodeVideoSettings none;
  EXPECT_EQ(VideoCameras(none, {}, CameraProtocol::kHead),
            (std::vector<std::string>{"head", "left_wrist", "right_wrist", "fixed"}));
  EXPECT_EQ(VideoCameras(none, {}, CameraProtocol::kFixed),
            (std::vector<std::string>{"fixed", "left_wrist", "right_wrist"}));
  EXPECT_EQ(VideoCameras(none, {"head"}, CameraProtocol::kHead), (std::vector<std::string>{"head", "fixed"}));
  EpisodeVideoSettings chosen;
  chosen.cameras = {"right_wrist"};
  EXPECT_EQ(VideoCameras(chosen, {"head"}, CameraProtocol::kHead), (std::vector<std::string>{"right_wrist"}));
}

TEST(EpisodeVideoCaption, NamesTheFurthestStageReached) {
  EXPECT_EQ(StageCaption({}), "");
  EXPECT_EQ(StageCaption({{"cue_fixated", -1}, {"target_grasped", -1}}), "   stage 0/2 none yet");
  EXPECT_EQ(StageCaption({{"cue_fixated", 12}, {"target_grasped", -1}}), "   stage 1/2 cue_fixated");
  // The furthest one, though an earlier one was missed (the grasp test can miss a grasp).
  EXPECT_EQ(StageCaption({{"target_approached", 40}, {"target_grasped", -1}, {"target_lifted", 90}}),
            "   stage 3/3 target_lifted");
}

TEST(EpisodeVideoSettings, BadValuesAreNamed) {
  const auto message = [](const EpisodeVideoSettings& settings) {
    try {
      ValidateEpisodeVideoSettings(settings);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EpisodeVideoSettings odd;
  odd.tile_width = 101;
  EXPECT_NE(message(odd).find("101x240"), std::string::npos) << message(odd);
  // The library names the setting by its key (as a sweep spec does); tavis eval names its flag.
  EXPECT_EQ(message(odd).rfind("video_size must be even", 0), 0u) << message(odd);
  EpisodeVideoSettings tiny;
  tiny.tile_height = 20;
  EXPECT_NE(message(tiny).find("320x20"), std::string::npos) << message(tiny);
  EpisodeVideoSettings negative;
  negative.episodes = -1;
  EXPECT_EQ(message(negative), "videos must be at least 0, got -1");
  EpisodeVideoSettings camera;
  camera.cameras = {"belly"};
  EXPECT_NE(message(camera).find("belly"), std::string::npos) << message(camera);
  EXPECT_EQ(message(EpisodeVideoSettings()), "accepted");
  EXPECT_THROW(ParseVideoFormat("gif"), std::invalid_argument);
}

}  // namespace
}  // namespace tavis::batch::rollout
