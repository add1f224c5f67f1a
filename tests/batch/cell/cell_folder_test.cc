#include "batch/cell/cell_folder.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/episode_times.h"
#include "batch/output/setting_error.h"
#include "tests/support/test_folder.h"

namespace tavis::batch::cell {
namespace {

namespace fs = std::filesystem;

// The default cell (the expert on clutter-pick-cube), two episodes on two slots.
EvaluationCellConfig TwoExpertEpisodes() {
  EvaluationCellConfig config;
  config.episodes = config.envs = 2;
  config.seed = 7;
  config.config_dir = TAVIS_CONFIG_DIR;
  return config;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> Lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// What the attachments heard: the plan's first episode to run, the folder at attach time, the
// records and the results they were finished with.
struct Heard {
  int64_t first_episode = -1;
  fs::path folder_at_attach;
  std::vector<int64_t> records;
  std::vector<fs::path> folder_at_record;
  int finished = 0;
};

AttachToCell Listen(Heard& heard) {
  return [&heard](const CellPlan& plan, const std::function<fs::path()>& folder) {
    heard.first_episode = plan.config.first_episode;
    heard.folder_at_attach = folder();
    CellAttachments attached;
    attached.on_record = [&heard, folder](const EpisodeRecord& record) {
      heard.records.push_back(record.episode);
      heard.folder_at_record.push_back(folder());
    };
    attached.finish = [&heard](const CellResult&) { ++heard.finished; };
    return attached;
  };
}

class CellFolder : public testing::TestFolder {
 protected:
  CellFolder() : TestFolder("cell_folder") {}
  fs::path Out() const { return root() / "cell"; }
  CellFolderOptions Options() const {
    CellFolderOptions options;
    options.out = Out();
    options.threads = 2;
    return options;
  }
};

TEST_F(CellFolder, AFreshFolderGetsTheSettingsEveryRecordAndTheSummaryLast) {
  Heard heard;
  const CellResult result = RunCellInFolder(PlanCell(TwoExpertEpisodes()), Options(), Listen(heard));
  ASSERT_EQ(result.episodes.size(), 2u);
  EXPECT_EQ(heard.first_episode, 0);
  EXPECT_EQ(heard.folder_at_attach, Out());
  EXPECT_EQ(heard.records, (std::vector<int64_t>{0, 1}));
  EXPECT_EQ(heard.finished, 1);
  EXPECT_EQ(Lines(Out() / "episodes.jsonl").size(), 2u);
  const nlohmann::json summary = nlohmann::json::parse(ReadText(Out() / "summary.json"));
  EXPECT_EQ(summary.at("n_episodes"), 2);
  EXPECT_EQ(summary.at("n_successful"), result.successes);
  EXPECT_TRUE(fs::exists(Out() / "cell.json"));
}

TEST_F(CellFolder, AResumedFolderRunsOnlyTheMissingEpisodesAndSummarisesTheWholeCell) {
  RunCellInFolder(PlanCell(TwoExpertEpisodes()), Options());
  const std::vector<std::string> whole = Lines(Out() / "episodes.jsonl");
  const std::string whole_summary = ReadText(Out() / "summary.json");
  // Interrupted after episode 0: its line kept, the second torn, no summary.
  fs::remove(Out() / "summary.json");
  std::ofstream(Out() / "episodes.jsonl", std::ios::binary | std::ios::trunc) << whole[0] << "\n{\"episode\": 1, \"su";

  CellFolderOptions options = Options();
  options.resume = true;
  Heard heard;
  const CellResult result = RunCellInFolder(PlanCell(TwoExpertEpisodes()), options, Listen(heard));
  EXPECT_EQ(heard.first_episode, 1);
  EXPECT_EQ(heard.records, (std::vector<int64_t>{1}));
  ASSERT_EQ(result.episodes.size(), 2u) << "the resumed record first";
  EXPECT_EQ(result.episodes[0].episode, 0);
  EXPECT_EQ(Lines(Out() / "episodes.jsonl"), whole);
  const nlohmann::json summary = nlohmann::json::parse(ReadText(Out() / "summary.json"));
  const nlohmann::json was = nlohmann::json::parse(whole_summary);
  EXPECT_EQ(summary.at("n_episodes"), was.at("n_episodes"));
  EXPECT_EQ(summary.at("n_successful"), was.at("n_successful"));
}

// Each line's episode index, in the file's order.
std::vector<int64_t> EpisodesOf(const std::vector<std::string>& lines) {
  std::vector<int64_t> episodes;
  for (const std::string& line : lines) episodes.push_back(nlohmann::json::parse(line).at("episode").get<int64_t>());
  return episodes;
}

TEST_F(CellFolder, EveryEpisodeGetsOneTimeLineBesideTheRecordsWhichTimingLeavesAlone) {
  RunCellInFolder(PlanCell(TwoExpertEpisodes()), Options());
  const std::string records = ReadText(Out() / "episodes.jsonl");
  const std::vector<std::string> times = Lines(Out() / "episode_times.jsonl");
  EXPECT_EQ(EpisodesOf(times), (std::vector<int64_t>{0, 1})) << "in the records' order";
  for (const std::string& line : times) {
    const EpisodeTimesLine parsed = ParseEpisodeTimesJsonLine(line);
    ASSERT_TRUE(parsed.times.has_value()) << line;
    EXPECT_GT(parsed.times->span_s, 0.0) << line;
    EXPECT_GT(parsed.times->part(EpisodeTimes::kPhysics), 0.0) << line;
  }
  const nlohmann::json summary = nlohmann::json::parse(ReadText(Out() / "summary.json"));
  const nlohmann::json& aggregated = summary.at("provenance").at("time").at("episodes");
  EXPECT_EQ(aggregated.at("measured"), 2);
  EXPECT_GT(aggregated.at("physics_s").at("total_s").get<double>(), 0.0);

  // The same cell again: the same records byte for byte, other times.
  fs::remove_all(Out());
  RunCellInFolder(PlanCell(TwoExpertEpisodes()), Options());
  EXPECT_EQ(ReadText(Out() / "episodes.jsonl"), records);
  EXPECT_NE(Lines(Out() / "episode_times.jsonl"), times) << "timing differs from run to run";
}

TEST_F(CellFolder, AResumedCellHasExactlyOneTimeLinePerEpisode) {
  RunCellInFolder(PlanCell(TwoExpertEpisodes()), Options());
  const std::vector<std::string> records = Lines(Out() / "episodes.jsonl");
  const std::vector<std::string> times = Lines(Out() / "episode_times.jsonl");
  CellFolderOptions options = Options();
  options.resume = true;
  // Killed between episode 1's time line and its record: the time line without a record goes.
  fs::remove(Out() / "summary.json");
  std::ofstream(Out() / "episodes.jsonl", std::ios::binary | std::ios::trunc) << records[0] << "\n";
  RunCellInFolder(PlanCell(TwoExpertEpisodes()), options);
  EXPECT_EQ(Lines(Out() / "episodes.jsonl"), records);
  std::vector<std::string> resumed = Lines(Out() / "episode_times.jsonl");
  EXPECT_EQ(EpisodesOf(resumed), (std::vector<int64_t>{0, 1}));
  EXPECT_EQ(resumed[0], times[0]) << "the resumed episode keeps its times";

  // A cell begun without the time file (an older tavis): the resumed episode's line says its
  // times are unknown, and the summary aggregates the measured one.
  fs::remove(Out() / "summary.json");
  fs::remove(Out() / "episode_times.jsonl");
  std::ofstream(Out() / "episodes.jsonl", std::ios::binary | std::ios::trunc) << records[0] << "\n{\"episode\": 1";
  RunCellInFolder(PlanCell(TwoExpertEpisodes()), options);
  EXPECT_EQ(Lines(Out() / "episodes.jsonl"), records);
  resumed = Lines(Out() / "episode_times.jsonl");
  EXPECT_EQ(EpisodesOf(resumed), (std::vector<int64_t>{0, 1}));
  EXPECT_FALSE(ParseEpisodeTimesJsonLine(resumed[0]).times.has_value());
  EXPECT_TRUE(ParseEpisodeTimesJsonLine(resumed[1]).times.has_value());
  const nlohmann::json summary = nlohmann::json::parse(ReadText(Out() / "summary.json"));
  EXPECT_EQ(summary.at("provenance").at("time").at("episodes").at("measured"), 1);
}

TEST_F(CellFolder, AnOverwriteBuildsTheNewCellBesideTheOldOneUntilItsFirstRecord) {
  RunCellInFolder(PlanCell(TwoExpertEpisodes()), Options());
  EvaluationCellConfig other = TwoExpertEpisodes();
  other.seed = 8;
  CellFolderOptions options = Options();
  options.overwrite = true;
  Heard heard;
  RunCellInFolder(PlanCell(other), options, Listen(heard));
  EXPECT_NE(heard.folder_at_attach, Out()) << "the new cell starts beside the old one";
  ASSERT_EQ(heard.folder_at_record.size(), 2u);
  // What goes with a record (its video) is finished before the record is written: the first one's
  // beside the old cell, which that record then swaps in, with it.
  EXPECT_EQ(heard.folder_at_record[0], heard.folder_at_attach);
  EXPECT_EQ(heard.folder_at_record[1], Out()) << "the first record swaps it in";
  EXPECT_EQ(nlohmann::json::parse(ReadText(Out() / "cell.json")).at("seed"), 8);
  EXPECT_EQ(Lines(Out() / "episodes.jsonl").size(), 2u);
}

TEST_F(CellFolder, FoldersThatCannotTakeTheCellAreRefusedNamingThem) {
  CellFolderOptions options = Options();
  options.resume = true;
  try {
    RunCellInFolder(PlanCell(TwoExpertEpisodes()), options);
    FAIL() << "a resume of a folder that does not exist must throw";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find(Out().string() + " does not exist"), std::string::npos) << error.what();
    // It names the setting by its key; tavis eval names its flag.
    EXPECT_EQ(std::string(error.what()).rfind("resume: ", 0), 0u) << error.what();
    const auto* named = dynamic_cast<const output::NamesSettings*>(&error);
    ASSERT_NE(named, nullptr);
    EXPECT_EQ(named->MessageNaming([](const std::string& key) { return "--" + key; }).rfind("--resume: ", 0), 0u);
  }
  fs::create_directories(Out());
  std::ofstream(Out() / "notes.txt") << "someone else's\n";
  options.resume = false;
  options.overwrite = true;
  try {
    RunCellInFolder(PlanCell(TwoExpertEpisodes()), options);
    FAIL() << "an overwrite of a folder tavis did not write must throw";
  } catch (const std::invalid_argument& error) {
    const std::string advice =
        "; overwrite replaces only a cell tavis wrote: move those files away or give another out";
    EXPECT_EQ(std::string(error.what()),
              Out().string() + " holds files that are not a tavis evaluation cell's: notes.txt" + advice);
    const auto* named = dynamic_cast<const output::NamesSettings*>(&error);
    ASSERT_NE(named, nullptr);
    EXPECT_NE(named->MessageNaming([](const std::string& key) { return "--" + key; }).find("give another --out"),
              std::string::npos);
  }
  EXPECT_EQ(ReadText(Out() / "notes.txt"), "someone else's\n") << "a folder tavis did not write stays as it was";
  options.overwrite = false;
  EXPECT_THROW(RunCellInFolder(PlanCell(TwoExpertEpisodes()), options), std::invalid_argument);
}

// A served cell whose server does not answer fails before its first record.
TEST_F(CellFolder, ANewFolderOfACellThatFailedBeforeItsFirstRecordGoesUnlessTheCallerKeepsIt) {
  EvaluationCellConfig config;
  config.policy = "openpi";
  config.servers = {"ws://127.0.0.1:1"};
  config.server_ready_timeout_s = 0.05;
  config.episodes = 1;
  config.envs = 1;
  config.config_dir = TAVIS_CONFIG_DIR;
  EXPECT_THROW(RunCellInFolder(PlanCell(config), Options()), std::runtime_error);
  EXPECT_FALSE(fs::exists(Out()));
  CellFolderOptions keep = Options();
  keep.remove_new_folder_on_failure = false;
  EXPECT_THROW(RunCellInFolder(PlanCell(config), keep), std::runtime_error);
  EXPECT_TRUE(fs::exists(Out() / "cell.json")) << "the sweep's next run continues it";
}

}  // namespace
}  // namespace tavis::batch::cell
