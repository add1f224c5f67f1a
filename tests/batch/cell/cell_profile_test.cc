// CellProfile's critical path and thread-count estimates on hand-made costs, and its JSON.
#include "batch/cell/cell_profile.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <string>
#include <utility>

namespace tavis::batch::cell {
namespace {

// Two ticks on four envs: in the first, one env costs 3 s and three cost 1 s; in the second,
// all four cost 1 s. 0.5 s serial, 0.8 s of rendering (parallel over tiles).
CellProfile HandMadeProfile() {
  CellProfile profile;
  profile.stages = {{"step_physics", 7.0}, {"render", 0.8}, {"driver", 0.5}};
  profile.sections = {{3.0, 6.0}, {1.0, 4.0}};
  profile.slowest_env_seconds = 4.0;
  profile.serial_seconds = 0.5;
  profile.render_seconds = 0.8;
  profile.episodes = {{0, 0, 10, 4.0}, {1, 1, 10, 2.0}};
  return profile;
}

TEST(CellProfile, CriticalPathIsSerialPlusEachSectionsSlowestEnv) {
  EXPECT_DOUBLE_EQ(HandMadeProfile().critical_path_seconds(), 0.5 + 3.0 + 1.0);
}

TEST(CellProfile, EstimatesSpreadWorkButNeverBeatTheSlowestEnv) {
  const CellProfile profile = HandMadeProfile();
  // One thread does all the work in turn.
  EXPECT_DOUBLE_EQ(profile.EstimatedSeconds(1), 0.5 + 0.8 + 6.0 + 4.0);
  // Two: the first tick waits for its 3 s env, the second splits 4 s in two.
  EXPECT_DOUBLE_EQ(profile.EstimatedSeconds(2), 0.5 + 0.4 + 3.0 + 2.0);
  // Four and more: every section is as long as its slowest env; only rendering still shrinks.
  EXPECT_DOUBLE_EQ(profile.EstimatedSeconds(4), 0.5 + 0.2 + 3.0 + 1.0);
  EXPECT_DOUBLE_EQ(profile.EstimatedSeconds(16), 0.5 + 0.05 + 3.0 + 1.0);
  EXPECT_GT(profile.EstimatedSeconds(1000), profile.critical_path_seconds());
}

// The per-slot schedule: episodes of 1, 1, 3, 1 and 2 s (ended out of order) dealt in index
// order to the thread that frees up first; 0.25 s serial.
CellProfile PerSlotProfile() {
  CellProfile profile;
  profile.per_slot = true;
  profile.stages = {{"step_physics", 7.75}, {"driver", 0.25}};
  profile.serial_seconds = 0.25;
  profile.episodes = {{1, 1, 10, 1.0}, {0, 0, 10, 1.0}, {3, 1, 10, 1.0}, {2, 0, 30, 3.0}, {4, 1, 20, 2.0}};
  return profile;
}

TEST(CellProfile, PerSlotCriticalPathIsSerialPlusTheLongestEpisode) {
  EXPECT_DOUBLE_EQ(PerSlotProfile().critical_path_seconds(), 0.25 + 3.0);
}

TEST(CellProfile, PerSlotEstimatesDealEpisodesInIndexOrderToTheFirstFreeThread) {
  const CellProfile profile = PerSlotProfile();
  EXPECT_DOUBLE_EQ(profile.EstimatedSeconds(1), 0.25 + 8.0);
  // Two threads: 0 and 1 start together; episode 2 (3 s) goes to thread A at 1 s, episode 3 to
  // B at 1 s, episode 4 to B at 2 s: A ends at 4 s, B at 4 s.
  EXPECT_DOUBLE_EQ(profile.EstimatedSeconds(2), 0.25 + 4.0);
  // Three: episode 3 and 4 follow 0 and 1; episode 2 from 0 s ends last at 3 s.
  EXPECT_DOUBLE_EQ(profile.EstimatedSeconds(3), 0.25 + 3.0);
  EXPECT_DOUBLE_EQ(profile.EstimatedSeconds(16), profile.critical_path_seconds());
  const std::string text = FormatCellProfile(profile);
  EXPECT_NE(text.find("critical path (unlimited threads): 3.250 s = serial 0.250 s + longest episode 3.000 s"),
            std::string::npos)
      << text;
  EXPECT_EQ(nlohmann::json::parse(CellProfileJson(profile)).at("schedule").get<std::string>(), "per_slot");
}

TEST(CellProfile, JsonCarriesStagesEstimatesAndEveryEpisode) {
  const nlohmann::json json = nlohmann::json::parse(CellProfileJson(HandMadeProfile()));
  EXPECT_DOUBLE_EQ(json.at("work_s").get<double>(), 8.3);
  EXPECT_DOUBLE_EQ(json.at("stage_s").at("step_physics").get<double>(), 7.0);
  EXPECT_DOUBLE_EQ(json.at("critical_path_s").get<double>(), 4.5);
  EXPECT_DOUBLE_EQ(json.at("estimates").at("2").at("seconds").get<double>(), 5.9);
  // On 16 threads 8.3 s of work would ideally take 0.51875 s; the estimate is 4.55 s.
  EXPECT_NEAR(json.at("estimates").at("16").at("serial_or_tail_share").get<double>(), 1.0 - 0.51875 / 4.55, 1e-12);
  ASSERT_EQ(json.at("episodes").size(), 2u);
  EXPECT_EQ(json.at("episodes")[1].at("episode").get<int>(), 1);
  EXPECT_DOUBLE_EQ(json.at("episodes")[0].at("seconds").get<double>(), 4.0);
}

TEST(CellProfile, TextNamesEveryStageAndTheCriticalPath) {
  const std::string text = FormatCellProfile(HandMadeProfile());
  for (const char* part : {"step_physics", "render", "driver", "critical path (unlimited threads): 4.500 s",
                           "estimate on  2 threads: 5.900 s"}) {
    EXPECT_NE(text.find(part), std::string::npos) << part << " missing in\n" << text;
  }
}

// The first line names the threads the run had, in the singular for one.
TEST(CellProfile, TextNamesTheRunsThreads) {
  CellProfile profile = HandMadeProfile();
  profile.wall_seconds = 5.0;
  for (const auto& [threads, words] :
       {std::pair<int, const char*>{1, "5.00 s wall on 1 thread, 8.30 s of measured work"},
        std::pair<int, const char*>{16, "5.00 s wall on 16 threads, 8.30 s"}}) {
    profile.threads = threads;
    const std::string text = FormatCellProfile(profile);
    EXPECT_EQ(text.rfind(std::string("profile: ") + words, 0), 0u) << text;
  }
  EXPECT_NE(FormatCellProfile(profile).find("estimate on  1 thread: "), std::string::npos);
}

}  // namespace
}  // namespace tavis::batch::cell
