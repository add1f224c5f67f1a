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

  EXPECT_EQ(row["stages"][2]["reached_alone"], 1);

  TextTable table;
  Table(SweepTables(summary), "stage_funnel", &table);
  ASSERT_EQ(table.name, "stage_funnel");
  EXPECT_EQ(table.header,
            (std::vector<std::string>{"policy", "task", "robot", "split", "stage", "head %", "head alone %"}));
  ASSERT_EQ(table.rows.size(), 3U);
  EXPECT_EQ(table.rows[0], (std::vector<std::string>{"expert", "clutter-pick-cube", "gr1t2", "id", "target_approached",
                                                     "60.0", "60.0"}));
  EXPECT_EQ(table.rows[2][5], "20.0");
  TextTable episodes;
  Table(SweepTables(summary), "stage_funnel_episodes", &episodes);
  ASSERT_EQ(episodes.rows.size(), 1U);
  EXPECT_EQ(episodes.rows[0],
            (std::vector<std::string>{"expert", "clutter-pick-cube", "gr1t2", "id", "head", "5", "20.0", "1"}));
  for (const TextTable& any : SweepTables(summary)) {
    for (const std::vector<std::string>& row_cells : any.rows)
      EXPECT_EQ(row_cells.size(), any.header.size()) << any.name;
  }
}

// A cue task's episodes as both protocols see them: the head fixates the cue in episodes 0 and 1,
// the fixed camera never can; both approach, grasp and lift in episodes 0 to 2.
CellEpisodes CueCell(CameraProtocol camera) {
  CellEpisodes cell;
  cell.id = ToString(camera);
  cell.label = "expert";
  cell.config.task = "conditional-pick";
  cell.config.robot = "gr1t2";
  cell.config.split = scenarios::Split::kId;
  cell.config.camera = camera;
  for (int i = 0; i < 4; ++i) {
    cell::EpisodeRecord record;
    record.episode = i;
    record.success = i < 3;
    record.end = record.success ? engine::EpisodeEnd::kSuccess : engine::EpisodeEnd::kTimeOut;
    record.length_steps = 100;
    const bool fixated = camera == CameraProtocol::kHead && i < 2;
    record.stages = {{"cue_fixated", fixated ? 5 : -1},
                     {"target_approached", i < 3 ? 10 : -1},
                     {"target_grasped", i < 3 ? 20 : -1},
                     {"target_lifted", i < 3 ? 30 : -1}};
    cell.episodes.push_back(record);
  }
  return cell;
}

TEST(StageFunnelSection, AFixedCellSkipsTheGazeStageAndSitsBesideItsHeadCell) {
  const nlohmann::ordered_json summary =
      SweepSummaryJson({{"episodes", 4}}, {CueCell(CameraProtocol::kHead), CueCell(CameraProtocol::kFixed)});
  ASSERT_EQ(summary["stages"].size(), 2U);
  const auto& fixed = summary["stages"][1];
  EXPECT_EQ(fixed["camera"], "fixed");
  EXPECT_FALSE(fixed["stages"][0]["applies"].get<bool>());
  EXPECT_TRUE(fixed["stages"][0]["reached"].is_null());
  EXPECT_EQ(fixed["stages"][1]["reached"], 3) << "approached without the gaze it could not make";
  EXPECT_EQ(fixed["stages"][3]["reached"], 3);

  TextTable table;
  Table(SweepTables(summary), "stage_funnel", &table);
  EXPECT_EQ(table.header, (std::vector<std::string>{"policy", "task", "robot", "split", "stage", "head %",
                                                    "head alone %", "fixed %", "fixed alone %"}));
  ASSERT_EQ(table.rows.size(), 4U) << "one row per stage, the cameras side by side";
  EXPECT_EQ(table.rows[0], (std::vector<std::string>{"expert", "conditional-pick", "gr1t2", "id", "cue_fixated", "50.0",
                                                     "50.0", "n/a", "n/a"}));
  EXPECT_EQ(table.rows[1], (std::vector<std::string>{"expert", "conditional-pick", "gr1t2", "id", "target_approached",
                                                     "50.0", "75.0", "75.0", "75.0"}));
  EXPECT_EQ(table.rows[3][4], "target_lifted");
  EXPECT_EQ(table.rows[3][7], "75.0");
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
