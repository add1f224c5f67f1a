// The sweep summary's gaze section (verified GALT, gaze on target, the tasks' anchors), its tables
// and the gaze figures drawn from it, every drawn number read back from the SVG.
#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <vector>

#include "batch/report/gaze_figures.h"
#include "batch/report/gaze_section.h"
#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {
namespace {

// A conditional-pick cell of three successful episodes and a failed one: GALT 1.1, 1.6 (verified)
// and 2.1 (the head off the target at the grasp); card_to_reach 0.5, 0.7 and none; the grasp led
// by 1.0, 1.2, 1.4 s; the gaze-on-target ratios 0.8, 0.6, 0.4.
CellEpisodes Cell(const std::string& label, CameraProtocol camera) {
  CellEpisodes cell;
  cell.id = label + "_" + ToString(camera);
  cell.label = label;
  cell.config.task = "conditional-pick";
  cell.config.robot = "gr1t2";
  cell.config.split = scenarios::Split::kId;
  cell.config.camera = camera;
  cell.config.policy = "expert";
  const double galt[] = {1.1, 1.6, 2.1}, card[] = {0.5, 0.7, -1}, grasp[] = {1.0, 1.2, 1.4}, ratio[] = {0.8, 0.6, 0.4};
  for (int i = 0; i < 4; ++i) {
    cell::EpisodeRecord record;
    record.episode = i;
    record.success = i < 3;
    record.end = record.success ? engine::EpisodeEnd::kSuccess : engine::EpisodeEnd::kTimeOut;
    record.length_steps = 100;
    record.gaze.traced = true;
    record.gaze.fixations = {{cell::GazeTarget::kTarget, 0, 100}};
    if (record.success) {
      kinematics::GaltResult result;
      result.galt_s = galt[i];
      result.reason = kinematics::GaltReason::kOk;
      record.galt = result;
      record.gaze.galt_verified_reason = i < 2 ? "verified" : "off_target";
      if (i < 2) record.gaze.galt_verified_s = galt[i];
      record.gaze.gaze_on_target_ratio = ratio[i] - (camera == CameraProtocol::kFixed ? 0.4 : 0.0);
      record.gaze.cue_before_reach = i < 2;
      record.gaze.anchors = {{"card_to_reach", card[i] > 0 ? std::optional<double>(card[i]) : std::nullopt},
                             {"target_to_grasp", grasp[i]},
                             {"target_to_lift", grasp[i] + 0.5}};
    }
    cell.episodes.push_back(record);
  }
  return cell;
}

const TextTable* Find(const std::vector<TextTable>& tables, const std::string& name) {
  for (const TextTable& table : tables) {
    if (table.name == name) return &table;
  }
  return nullptr;
}

TEST(GazeSection, PoolsEachSettingsGazeAndAnchorsIntoTheSummaryAndTables) {
  const nlohmann::ordered_json summary = SweepSummaryJson(
      {{"episodes", 4}}, {Cell("expert", CameraProtocol::kHead), Cell("expert", CameraProtocol::kFixed)});
  ASSERT_EQ(summary["gaze"].size(), 2U);
  const nlohmann::ordered_json& row = summary["gaze"][0];
  EXPECT_EQ(row["label"], "expert");
  EXPECT_EQ(row["camera"], "head");
  EXPECT_EQ(row["gaze"]["n_episodes"], 3);
  EXPECT_EQ(row["gaze"]["n_verified"], 2);
  EXPECT_DOUBLE_EQ(row["gaze"]["gaze_on_target_ratio_mean"].get<double>(), 0.6);
  EXPECT_EQ(row["galt_verified_values_s"], nlohmann::ordered_json({1.1, 1.6}));
  EXPECT_EQ(row["galt_unverified_values_s"], nlohmann::ordered_json({2.1}));
  const nlohmann::ordered_json& card = row["gaze"]["anchors"][0];
  EXPECT_EQ(card["anchor"], "card_to_reach");
  EXPECT_EQ(card["event"], "reach_onset");
  EXPECT_EQ(card["n"], 2);
  EXPECT_EQ(card["n_missing"], 1);
  EXPECT_DOUBLE_EQ(card["median_s"].get<double>(), 0.6);

  const std::vector<TextTable> tables = SweepTables(summary);
  const TextTable* gaze = Find(tables, "gaze");
  ASSERT_NE(gaze, nullptr);
  ASSERT_EQ(gaze->rows.size(), 2U);
  EXPECT_EQ(gaze->rows[0], (std::vector<std::string>{"expert", "conditional-pick", "gr1t2", "id", "head", "3", "3", "2",
                                                     "66.7", "1.35", "60.0", "66.7"}));
  const TextTable* anchors = Find(tables, "gaze_anchors");
  ASSERT_NE(anchors, nullptr);
  ASSERT_EQ(anchors->rows.size(), 6U);  // three anchors per camera
  EXPECT_EQ(anchors->rows[1],
            (std::vector<std::string>{"expert", "conditional-pick", "gr1t2", "id", "head", "target_to_grasp", "target",
                                      "grasp", "3", "0", "1.20", "1.10", "1.30", "0.20"}));
  EXPECT_EQ(anchors->rows[2][7], "target_lifted");
}

// The values of attribute `name` on the SVG marks that carry attribute `key`="value".
std::vector<std::string> Attributes(const std::string& svg, const std::string& key, const std::string& value,
                                    const std::string& name) {
  std::vector<std::string> found;
  const std::regex mark("<(rect|line)[^>]*>");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), mark); it != std::sregex_iterator(); ++it) {
    const std::string text = it->str();
    if (text.find("data-" + key + "=\"" + value + "\"") == std::string::npos) continue;
    std::smatch match;
    if (std::regex_search(text, match, std::regex("data-" + name + "=\"([^\"]*)\""))) found.push_back(match[1]);
  }
  return found;
}

TEST(GazeFigures, DrawTheVerifiedHistogramTheAnchorsAndTheRatioPerPolicyAndCamera) {
  const nlohmann::ordered_json summary = SweepSummaryJson(
      {{"episodes", 4}}, {Cell("expert", CameraProtocol::kHead), Cell("expert", CameraProtocol::kFixed),
                          Cell("other", CameraProtocol::kHead)});
  const nlohmann::ordered_json& figures = summary["gaze_figures"];
  ASSERT_FALSE(figures["galt_verified"].is_null());
  EXPECT_EQ(figures["galt_verified"]["policy"], "expert");  // the first label
  const nlohmann::ordered_json& task = figures["galt_verified"]["tasks"][0];
  EXPECT_EQ(task["verified"]["n"], 2);
  EXPECT_EQ(task["unverified"]["n"], 1);
  EXPECT_DOUBLE_EQ(task["verified"]["median"].get<double>(), 1.35);
  ASSERT_EQ(figures["anchors"]["rows"].size(), 3U);
  EXPECT_EQ(figures["gaze_on_target"]["series"], nlohmann::ordered_json({"expert head", "expert fixed", "other head"}));

  const std::vector<Figure> drawn = DrawGazeFigures(figures);
  ASSERT_EQ(drawn.size(), 3U);
  EXPECT_EQ(drawn[0].name, "gaze_galt_verified");
  const std::string histogram = drawn[0].canvas.Svg(drawn[0].name);
  // Bins of 0.25 s from -0.5 s: 1.1 and 1.6 s in bins 6 and 8, 2.1 s in bin 10.
  const std::vector<std::string> verified = Attributes(histogram, "series", "verified", "count");
  ASSERT_EQ(verified.size(), static_cast<std::size_t>(kGazeGaltBins));
  EXPECT_EQ(verified[6], "1");
  EXPECT_EQ(verified[8], "1");
  EXPECT_EQ(Attributes(histogram, "series", "unverified", "count")[10], "1");
  EXPECT_EQ(Attributes(histogram, "series", "verified", "median"), std::vector<std::string>{"1.35"});

  EXPECT_EQ(drawn[1].name, "gaze_anchors");
  const std::string boxes = drawn[1].canvas.Svg(drawn[1].name);
  EXPECT_EQ(Attributes(boxes, "anchor", "target_to_grasp", "median"), std::vector<std::string>{"1.2"});
  EXPECT_EQ(Attributes(boxes, "anchor", "target_to_grasp", "q1"), std::vector<std::string>{"1.1"});
  EXPECT_EQ(Attributes(boxes, "anchor", "card_to_reach", "n"), std::vector<std::string>{"2"});

  EXPECT_EQ(drawn[2].name, "gaze_on_target");
  const std::string bars = drawn[2].canvas.Svg(drawn[2].name);
  EXPECT_EQ(Attributes(bars, "series", "expert head", "value"), std::vector<std::string>{"0.6"});
  EXPECT_EQ(Attributes(bars, "series", "expert fixed", "value"), std::vector<std::string>{"0.2"});

  // figures.gaze picks another label for the first two.
  const nlohmann::ordered_json other =
      SweepSummaryJson({{"episodes", 4}, {"figures", {{"gaze", "other"}}}},
                       {Cell("expert", CameraProtocol::kHead), Cell("other", CameraProtocol::kHead)})["gaze_figures"];
  EXPECT_EQ(other["galt_verified"]["policy"], "other");
  EXPECT_EQ(other["anchors"]["rows"][0]["label"], "other");
}

}  // namespace
}  // namespace tavis::batch::report
