#include "batch/cell/gaze_anchors.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <string>
#include <vector>

#include "batch/cell/cell_report.h"
#include "batch/cell/evaluation_cell.h"
#include "scenarios/registry.h"

namespace tavis::batch::cell {
namespace {

std::vector<FixationSegment> Fixations(const std::vector<std::pair<GazeTarget, int>>& steps) {
  std::vector<FixationSegment> segments;
  int step = 0;
  for (const auto& [target, count] : steps) {
    for (int i = 0; i < count; ++i) AppendFixation(target, step++, segments);
  }
  return segments;
}

TEST(GazeAnchors, TheArrivalIsTheStartOfTheLastFixationBeforeTheEvent) {
  // Steps: table 0-9, target 10-29, table 30-34, target 35-59.
  const std::vector<FixationSegment> fixations = Fixations(
      {{GazeTarget::kTable, 10}, {GazeTarget::kTarget, 20}, {GazeTarget::kTable, 5}, {GazeTarget::kTarget, 25}});
  EXPECT_EQ(ArrivalStep(fixations, GazeTarget::kTarget, 50, 20.0), 35);
  EXPECT_EQ(ArrivalStep(fixations, GazeTarget::kTarget, 30, 20.0), 10);  // the second began at the event
  EXPECT_EQ(ArrivalStep(fixations, GazeTarget::kTarget, 10, 20.0), std::nullopt);
  EXPECT_EQ(ArrivalStep(fixations, GazeTarget::kCue, 50, 20.0), std::nullopt);
}

TEST(GazeAnchors, AGlanceAwayShorterThanAFixationDoesNotEndIt) {
  // One step (0.05 s < GALT's 0.08 s persistence) on the table splits the target's fixation in the
  // segments, not in the lead time; two steps (0.10 s) do.
  const std::vector<FixationSegment> glance = Fixations(
      {{GazeTarget::kTable, 10}, {GazeTarget::kTarget, 10}, {GazeTarget::kTable, 1}, {GazeTarget::kTarget, 20}});
  EXPECT_EQ(ArrivalStep(glance, GazeTarget::kTarget, 40, 20.0), 10);
  const std::vector<FixationSegment> look = Fixations(
      {{GazeTarget::kTable, 10}, {GazeTarget::kTarget, 10}, {GazeTarget::kTable, 2}, {GazeTarget::kTarget, 20}});
  EXPECT_EQ(ArrivalStep(look, GazeTarget::kTarget, 40, 20.0), 22);
}

TEST(GazeAnchors, EachAnchorLeadsItsOwnEvent) {
  // 20 Hz: cue 5-14, target from 15 on; onset 1.0 s, grasp 2.0 s, lifted at control tick 150 (2.5 s).
  const std::vector<FixationSegment> fixations =
      Fixations({{GazeTarget::kTable, 5}, {GazeTarget::kCue, 10}, {GazeTarget::kTarget, 45}});
  kinematics::GaltResult galt;
  galt.t_hand_onset_s = 1.0;
  galt.t_hand_arrival_s = 2.0;
  const std::vector<scenarios::StageDef> stages = scenarios::FindScenario("conditional-pick").stages;
  std::vector<int> first_ticks(stages.size(), -1);
  for (std::size_t s = 0; s < stages.size(); ++s) {
    if (stages[s].name == "target_lifted") first_ticks[s] = 150;
  }
  const std::vector<scenarios::GazeAnchor>& anchors = scenarios::FindScenario("conditional-pick").gaze_anchors;
  const std::vector<AnchorLead> leads =
      MeasureGazeAnchors(anchors, fixations, AnchorEvents{&galt, &stages, &first_ticks, 60.0}, 20.0);
  ASSERT_EQ(leads.size(), 3U);
  EXPECT_EQ(leads[0].name, "card_to_reach");
  ASSERT_TRUE(leads[0].lead_s);
  EXPECT_DOUBLE_EQ(*leads[0].lead_s, 1.0 - 0.25);
  EXPECT_EQ(leads[1].name, "target_to_grasp");
  EXPECT_DOUBLE_EQ(*leads[1].lead_s, 2.0 - 0.75);
  EXPECT_EQ(leads[2].name, "target_to_lift");
  EXPECT_DOUBLE_EQ(*leads[2].lead_s, 2.5 - 0.75);

  // No GALT, no lift: nothing to lead.
  const std::vector<AnchorLead> none = MeasureGazeAnchors(anchors, fixations, AnchorEvents{}, 20.0);
  for (const AnchorLead& lead : none) EXPECT_FALSE(lead.lead_s) << lead.name;
}

TEST(GazeAnchors, TheSummaryGivesEachAnchorsMedianQuartilesAndCounts) {
  const std::vector<scenarios::GazeAnchor>& anchors = scenarios::FindScenario("clutter-pick-cube").gaze_anchors;
  std::vector<GazeRecord> records(5);
  const double grasp[] = {1.0, 2.0, 3.0, 4.0};
  for (std::size_t i = 0; i < records.size(); ++i) {
    records[i].traced = true;
    records[i].anchors = {{"target_to_grasp", i < 4 ? std::optional<double>(grasp[i]) : std::nullopt},
                          {"target_to_lift", std::nullopt}};
  }
  std::vector<const GazeRecord*> successful;
  for (const GazeRecord& record : records) successful.push_back(&record);
  const nlohmann::json summary = GazeAnchorSummaryJson(anchors, successful);
  ASSERT_EQ(summary.size(), 2U);
  EXPECT_EQ(summary[0]["anchor"], "target_to_grasp");
  EXPECT_EQ(summary[0]["fixation"], "target");
  EXPECT_EQ(summary[0]["event"], "grasp");
  EXPECT_EQ(summary[0]["n"], 4);
  EXPECT_EQ(summary[0]["n_missing"], 1);
  EXPECT_DOUBLE_EQ(summary[0]["median_s"].get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(summary[0]["q1_s"].get<double>(), 1.75);
  EXPECT_DOUBLE_EQ(summary[0]["q3_s"].get<double>(), 3.25);
  EXPECT_DOUBLE_EQ(summary[0]["iqr_s"].get<double>(), 1.5);
  EXPECT_EQ(summary[1]["event"], "target_lifted");
  EXPECT_EQ(summary[1]["n"], 0);
  EXPECT_TRUE(summary[1]["median_s"].is_null());
  // The cell's gaze block carries them; a cell without a traced head has none.
  EXPECT_EQ(GazeBlockJson(anchors, successful)["anchors"], summary);
  GazeRecord untraced;
  EXPECT_TRUE(GazeBlockJson(anchors, {&untraced}).is_null());
}

EvaluationCellConfig ExpertCell(const std::string& task, int episodes) {
  EvaluationCellConfig config;
  config.task = task;
  config.robot = "gr1t2";
  config.policy = "expert";
  config.episodes = episodes;
  config.envs = 2;
  config.seed = 5;
  config.config_dir = TAVIS_CONFIG_DIR;
  return config;
}

// The expert looks at the card, then the target, before it reaches, grasps and lifts: every
// anchor is measured in its successful episodes, in order (the card before the target), the same
// on one thread as on several, and the records carry them.
TEST(GazeAnchors, TheExpertsAnchorsAreMeasuredInOrderAndDeterministically) {
  CellResult one;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = RunEvaluationCell(ExpertCell("conditional-pick", 4));
  }
  const CellResult two = RunEvaluationCell(ExpertCell("conditional-pick", 4));
  ASSERT_GT(one.successes, 0);
  for (std::size_t i = 0; i < one.episodes.size(); ++i) {
    const EpisodeRecord& record = one.episodes[i];
    EXPECT_EQ(record.gaze.anchors, two.episodes[i].gaze.anchors) << "episode " << i;
    const nlohmann::json line = nlohmann::json::parse(EpisodeJsonLine(record, 5));
    ASSERT_TRUE(line.contains("gaze_anchors"));
    EXPECT_EQ(line["gaze_anchors"].size(), 3U);
    if (!record.success) continue;
    ASSERT_EQ(record.gaze.anchors.size(), 3U);
    const std::optional<double>& grasp = record.gaze.anchors[1].lead_s;
    const std::optional<double>& lift = record.gaze.anchors[2].lead_s;
    ASSERT_TRUE(grasp) << "episode " << i;
    ASSERT_TRUE(lift) << "episode " << i;
    EXPECT_GT(*grasp, 0.0);
    EXPECT_GT(*lift, *grasp);  // the same fixation leads the later lift by more
    if (const std::optional<double>& card = record.gaze.anchors[0].lead_s) {
      EXPECT_GT(*card, 0.0);
    }
  }
}

}  // namespace
}  // namespace tavis::batch::cell
