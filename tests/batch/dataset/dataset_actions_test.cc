// reader::ReadDatasetActions: the actions of v3.0 and v2.1 datasets come back per episode, in frame
// order, with their tasks; every malformed input fails with an error naming the file and the
// problem.
#include "batch/dataset/reader/dataset_actions.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/batch/dataset/parquet_fixtures.h"
#include "tests/batch/dataset/synthetic_dataset.h"

namespace tavis::batch::dataset::testing {
namespace {

namespace fs = std::filesystem;

// Three conformance episodes, each with one task.
std::vector<SyntheticEpisode> ThreeEpisodes() {
  std::vector<SyntheticEpisode> episodes = {LoadGaltVector("ep0097.csv", 0), LoadGaltVector("ep0107.csv", 1),
                                            LoadGaltVector("ep0079.csv", 2)};
  episodes[0].tasks = {"ClutterPickCubeTask"};
  episodes[1].tasks = {"WaitThenActTask"};
  episodes[2].tasks = {"ClutterPickCubeTask", "second task"};
  return episodes;
}

void ExpectSameActions(const reader::DatasetActions& read, const std::vector<SyntheticEpisode>& written) {
  ASSERT_EQ(read.episodes.size(), written.size());
  for (std::size_t e = 0; e < written.size(); ++e) {
    SCOPED_TRACE("episode " + std::to_string(e));
    const reader::EpisodeActions& episode = read.episodes[e];
    EXPECT_EQ(episode.episode_index, written[e].episode_index);
    EXPECT_EQ(episode.tasks, written[e].tasks);
    ASSERT_EQ(episode.num_steps, written[e].num_steps);
    ASSERT_EQ(episode.values.size(), written[e].actions.size());
    for (std::size_t i = 0; i < episode.values.size(); ++i) {
      ASSERT_EQ(episode.values[i], static_cast<double>(static_cast<float>(written[e].actions[i]))) << "value " << i;
    }
  }
}

std::string ReadError(const fs::path& dir) {
  try {
    reader::ReadDatasetActions(dir);
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "no error";
}

class DatasetActionsTest : public ::testing::Test {
 protected:
  ScratchDir scratch_;
  fs::path dir_ = fs::path(scratch_.path()) / "dataset";
};

TEST_F(DatasetActionsTest, ReadsV30EpisodesAcrossTwoDataFiles) {
  const std::vector<SyntheticEpisode> episodes = ThreeEpisodes();
  WriteSyntheticDataset(dir_, episodes);
  ASSERT_TRUE(fs::exists(dir_ / "data/chunk-000/file-001.parquet"));
  const reader::DatasetActions read = reader::ReadDatasetActions(dir_);
  EXPECT_EQ(read.info.codebase_version, "v3.0");
  EXPECT_EQ(read.info.version, reader::DatasetVersion::kV30);
  EXPECT_EQ(read.info.fps, 60.0);
  EXPECT_EQ(read.info.robot_type, "gr1t2");
  EXPECT_EQ(read.info.total_episodes, 3);
  ExpectSameActions(read, episodes);
}

TEST_F(DatasetActionsTest, ReadsV21OneFilePerEpisodeWithJsonlTasks) {
  const std::vector<SyntheticEpisode> episodes = ThreeEpisodes();
  SyntheticDatasetOptions options;
  options.codebase_version = "v2.1";
  options.robot_type = std::nullopt;
  WriteSyntheticDataset(dir_, episodes, options);
  ASSERT_TRUE(fs::exists(dir_ / "data/chunk-000/episode_000002.parquet"));
  const reader::DatasetActions read = reader::ReadDatasetActions(dir_);
  EXPECT_EQ(read.info.version, reader::DatasetVersion::kV21);
  EXPECT_EQ(read.info.robot_type, std::nullopt);
  ExpectSameActions(read, episodes);
}

TEST_F(DatasetActionsTest, TasksAreOptional) {
  std::vector<SyntheticEpisode> episodes = ThreeEpisodes();
  WriteSyntheticDataset(dir_, episodes);
  fs::remove_all(dir_ / "meta" / "episodes");
  for (SyntheticEpisode& episode : episodes) episode.tasks.clear();
  ExpectSameActions(reader::ReadDatasetActions(dir_), episodes);
}

TEST_F(DatasetActionsTest, MissingInfoJsonIsNamed) {
  WriteSyntheticDataset(dir_, ThreeEpisodes());
  fs::remove(dir_ / "meta" / "info.json");
  const std::string error = ReadError(dir_);
  EXPECT_NE(error.find("meta/info.json: missing"), std::string::npos) << error;
}

TEST_F(DatasetActionsTest, UnknownCodebaseVersionIsNamed) {
  SyntheticDatasetOptions options;
  options.codebase_version = "v1.6";
  WriteSyntheticDataset(dir_, ThreeEpisodes(), options);
  const std::string error = ReadError(dir_);
  EXPECT_NE(error.find("info.json: unknown codebase_version \"v1.6\""), std::string::npos) << error;
}

TEST_F(DatasetActionsTest, ActionNot19WideIsNamed) {
  std::vector<SyntheticEpisode> episodes = ThreeEpisodes();
  SyntheticEpisode& narrow = episodes[2];
  narrow.width = 18;
  narrow.actions.resize(static_cast<std::size_t>(narrow.num_steps) * 18);
  WriteSyntheticDataset(dir_, episodes);
  const std::string error = ReadError(dir_);
  EXPECT_NE(error.find("file-001.parquet: row 0: action has 18 values, expected 19"), std::string::npos) << error;
}

TEST_F(DatasetActionsTest, NonFiniteActionIsNamed) {
  std::vector<SyntheticEpisode> episodes = ThreeEpisodes();
  episodes[1].actions[5 * 19 + 15] = std::numeric_limits<double>::quiet_NaN();
  WriteSyntheticDataset(dir_, episodes);
  const std::string error = ReadError(dir_);
  const std::size_t second_episode_row = static_cast<std::size_t>(episodes[0].num_steps) + 5;
  EXPECT_NE(error.find("file-000.parquet: row " + std::to_string(second_episode_row) +
                       ": action[15] is nan (episode 1, frame 5)"),
            std::string::npos)
      << error;
}

TEST_F(DatasetActionsTest, FrameIndexOutOfOrderIsNamed) {
  std::vector<SyntheticEpisode> episodes = ThreeEpisodes();
  for (int t = 0; t < episodes[0].num_steps; ++t) episodes[0].frame_index.push_back(t == 7 ? 8 : t);
  WriteSyntheticDataset(dir_, episodes);
  const std::string error = ReadError(dir_);
  EXPECT_NE(error.find("row 7: episode 0 has frame_index 8, expected 7"), std::string::npos) << error;
}

TEST_F(DatasetActionsTest, EpisodesNotGroupedAreNamed) {
  std::vector<SyntheticEpisode> episodes = ThreeEpisodes();
  std::swap(episodes[0].episode_index, episodes[1].episode_index);  // file-000 holds 1 then 0
  WriteSyntheticDataset(dir_, episodes);
  const std::string error = ReadError(dir_);
  EXPECT_NE(error.find("file-000.parquet: row " + std::to_string(episodes[0].num_steps) +
                       ": episode_index 0 after episode 1"),
            std::string::npos)
      << error;
}

TEST_F(DatasetActionsTest, EpisodeCountDisagreeingWithInfoIsNamed) {
  SyntheticDatasetOptions options;
  options.total_episodes = 4;
  WriteSyntheticDataset(dir_, ThreeEpisodes(), options);
  const std::string error = ReadError(dir_);
  EXPECT_NE(error.find("info.json: total_episodes is 4 but the data files hold 3 episodes"), std::string::npos)
      << error;
}

TEST_F(DatasetActionsTest, TruncatedDataFileIsNamed) {
  WriteSyntheticDataset(dir_, ThreeEpisodes());
  const fs::path file = dir_ / "data/chunk-000/file-001.parquet";
  fs::resize_file(file, fs::file_size(file) / 2);
  const std::string error = ReadError(dir_);
  EXPECT_NE(error.find(file.string()), std::string::npos) << error;
}

TEST_F(DatasetActionsTest, NoDataFilesIsNamed) {
  WriteSyntheticDataset(dir_, ThreeEpisodes());
  fs::remove_all(dir_ / "data");
  const std::string error = ReadError(dir_);
  EXPECT_NE(error.find("no data files data/*/*.parquet"), std::string::npos) << error;
}

}  // namespace
}  // namespace tavis::batch::dataset::testing
