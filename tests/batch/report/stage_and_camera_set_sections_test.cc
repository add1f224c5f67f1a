// The sweep summary's stage funnel (with simulator faults apart) and its camera sets paired with
// head episode by episode, and the tables that print them.
#include <gtest/gtest.h>

#include <algorithm>

#include "batch/report/paired_statistics.h"
#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {
namespace {

// Episode i: success as given; reaches the first reached[i] stages of clutter-pick-cube (target
// approached, grasped, lifted); faults[i]: its physics blew up.
CellEpisodes Cell(CameraProtocol camera, const std::vector<bool>& successes, const std::vector<int>& reached = {},
                  const std::vector<bool>& faults = {}) {
  CellEpisodes cell;
  cell.id = ToString(camera);
  cell.config.task = "clutter-pick-cube";
  cell.config.robot = "gr1t2";
  cell.config.split = scenarios::Split::kId;
  cell.config.camera = camera;
  const std::vector<std::string> stages = {"target_approached", "target_grasped", "target_lifted"};
  for (std::size_t i = 0; i < successes.size(); ++i) {
    cell::EpisodeRecord record;
    record.episode = static_cast<int64_t>(i);
    record.success = successes[i];
    record.end = successes[i] ? engine::EpisodeEnd::kSuccess : engine::EpisodeEnd::kTimeOut;
    if (!faults.empty() && faults[i]) record.end = engine::EpisodeEnd::kPhysicsBlowUp;
    record.length_steps = 100;
    for (std::size_t s = 0; s < stages.size(); ++s) {
      const bool got = !reached.empty() && static_cast<int>(s) < reached[i];
      record.stages.push_back({stages[s], got ? 10 * static_cast<int>(s + 1) : -1});
    }
    cell.episodes.push_back(record);
  }
  return cell;
}

// The table named `name` of `tables` (an empty one when there is none).
void Table(const std::vector<TextTable>& tables, const std::string& name, TextTable* out) {
  for (const TextTable& table : tables) {
    if (table.name == name) *out = table;
  }
}

TEST(StageFunnelSection, CountsEachStageWithEveryStageBeforeItAndTheFaultsApart) {
  const std::vector<CellEpisodes> cells = {Cell(CameraProtocol::kHead, {true, false, false, false, false},
                                                {3, 2, 1, 0, 0}, {false, false, false, true, false})};
  const nlohmann::ordered_json summary = SweepSummaryJson({{"episodes", 5}}, cells);
  ASSERT_EQ(summary["stages"].size(), 1U);
  const auto& row = summary["stages"][0];
  EXPECT_EQ(row["episodes"], 5);
  EXPECT_EQ(row["successes"], 1);
  EXPECT_EQ(row["simulator_faults"], 1);
  ASSERT_EQ(row["stages"].size(), 3U);
  EXPECT_EQ(row["stages"][0]["stage"], "target_approached");
  EXPECT_EQ(row["stages"][0]["reached"], 3);
  EXPECT_EQ(row["stages"][1]["reached"], 2);
  EXPECT_EQ(row["stages"][2]["reached"], 1);

  TextTable table;
  Table(SweepTables(summary), "stage_funnel", &table);
  ASSERT_EQ(table.name, "stage_funnel");
  ASSERT_EQ(table.rows.size(), 1U);
  EXPECT_EQ(table.rows[0][6], "target_approached 60.0, target_grasped 40.0, target_lifted 20.0");
  EXPECT_EQ(table.rows[0][7], "20.0");
  EXPECT_EQ(table.rows[0][8], "1");
}

TEST(CameraSetPairs, PairEachSetWithHeadEpisodeByEpisode) {
  // Episode:       0     1      2      3
  // head:          yes   yes    no     no
  // wrists-only:   yes   no     yes    no   -> both 1, head only 1, set only 1, neither 1
  // head-only:     no    no     no     no   -> head only 2, neither 2
  const std::vector<CellEpisodes> cells = {Cell(CameraProtocol::kHead, {true, true, false, false}),
                                           Cell(CameraProtocol::kWristsOnly, {true, false, true, false}),
                                           Cell(CameraProtocol::kHeadOnly, {false, false, false, false}),
                                           Cell(CameraProtocol::kFixed, {false, false, false, false})};
  const nlohmann::ordered_json summary = SweepSummaryJson({{"episodes", 4}}, cells);
  ASSERT_EQ(summary["paired_camera_sets"].size(), 2U) << "fixed has its own section";
  const auto& wrists = summary["paired_camera_sets"][0];
  EXPECT_EQ(wrists["camera"], "wrists-only");
  EXPECT_EQ(wrists["both"], 1);
  EXPECT_EQ(wrists["head_only"], 1);
  EXPECT_EQ(wrists["set_only"], 1);
  EXPECT_EQ(wrists["neither"], 1);
  EXPECT_DOUBLE_EQ(wrists["mcnemar_p"].get<double>(), McNemarExactP(1, 1));
  const auto& head_only = summary["paired_camera_sets"][1];
  EXPECT_EQ(head_only["camera"], "head-only");
  EXPECT_EQ(head_only["head_only"], 2);
  EXPECT_EQ(head_only["neither"], 2);
  EXPECT_DOUBLE_EQ(head_only["difference"].get<double>(), 0.5);
  ASSERT_EQ(summary["paired"].size(), 1U);
  EXPECT_EQ(summary["paired"][0]["head_only"], 2) << "head vs fixed as before";

  TextTable table;
  Table(SweepTables(summary), "paired_camera_sets", &table);
  ASSERT_EQ(table.rows.size(), 2U);
  EXPECT_EQ(table.rows[0][4], "wrists-only");
  // Under wrists-only GALT is computed as under head (the head still moves); under fixed it is not.
  EXPECT_FALSE(summary["cells"][1]["galt"].is_null());
  EXPECT_TRUE(summary["cells"][3]["galt"].is_null());
}

}  // namespace
}  // namespace tavis::batch::report
