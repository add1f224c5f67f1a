// The sweep summary pairs head and fixed cells episode by episode, pools seeds, and the tables
// print its numbers.
#include "batch/report/sweep_summary.h"

#include <gtest/gtest.h>

#include "batch/report/paired_statistics.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {
namespace {

CellEpisodes Cell(const std::string& id, CameraProtocol camera, scenarios::Split split,
                  const std::vector<bool>& successes) {
  CellEpisodes cell;
  cell.id = id;
  cell.config.task = "clutter-pick-cube";
  cell.config.robot = "gr1t2";
  cell.config.split = split;
  cell.config.camera = camera;
  for (std::size_t i = 0; i < successes.size(); ++i) {
    cell::EpisodeRecord record;
    record.episode = static_cast<int64_t>(i);
    record.success = successes[i];
    record.length_steps = 40 + 20 * static_cast<int>(i);  // 2 s, 3 s, ...
    if (camera == CameraProtocol::kHead && successes[i]) {
      kinematics::GaltResult galt;
      galt.reason = kinematics::GaltReason::kOk;
      galt.galt_s = 1.0 + static_cast<double>(i);
      record.galt = galt;
    }
    cell.episodes.push_back(record);
  }
  return cell;
}

TEST(SweepSummary, PairsHeadAndFixedEpisodeByEpisode) {
  const auto id = scenarios::Split::kId;
  // Episode:      0     1      2      3      4      5
  // head:         yes   yes    yes    no     yes    no
  // fixed:        yes   no     no     yes    no     no    -> both 1, head only 3, fixed only 1, neither 1
  const std::vector<CellEpisodes> cells = {
      Cell("h", CameraProtocol::kHead, id, {true, true, true, false, true, false}),
      Cell("f", CameraProtocol::kFixed, id, {true, false, false, true, false, false})};
  const nlohmann::ordered_json summary = SweepSummaryJson({{"episodes", 6}}, cells);
  ASSERT_EQ(summary["paired"].size(), 1U);
  const auto& pair = summary["paired"][0];
  EXPECT_EQ(pair["both"], 1);
  EXPECT_EQ(pair["head_only"], 3);
  EXPECT_EQ(pair["fixed_only"], 1);
  EXPECT_EQ(pair["neither"], 1);
  EXPECT_DOUBLE_EQ(pair["mcnemar_p"].get<double>(), McNemarExactP(3, 1));
  EXPECT_DOUBLE_EQ(pair["difference"].get<double>(), 4.0 / 6.0 - 2.0 / 6.0);
  // Successful head episodes 0, 1, 2, 4: lengths 2, 3, 4, 6 s; GALT 1, 2, 3, 5 s.
  const auto& head = summary["cells"][0];
  EXPECT_DOUBLE_EQ(head["successful_length_s"]["mean"].get<double>(), 3.75);
  EXPECT_DOUBLE_EQ(head["successful_length_s"]["median"].get<double>(), 3.5);
  EXPECT_DOUBLE_EQ(head["galt"]["mean_s"].get<double>(), 2.75);
  EXPECT_TRUE(summary["cells"][1]["galt"].is_null());
  ASSERT_EQ(summary["galt"].size(), 1U);
  EXPECT_EQ(summary["galt"][0]["n_valid"], 4);
}

TEST(SweepSummary, GivesIdMinusOodAndTablesPrintTheNumbers) {
  const std::vector<CellEpisodes> cells = {
      Cell("a", CameraProtocol::kHead, scenarios::Split::kId, {true, true, true, false}),
      Cell("b", CameraProtocol::kHead, scenarios::Split::kOodSpatial, {true, false, false, false})};
  const nlohmann::ordered_json summary = SweepSummaryJson({{"episodes", 4}}, cells);
  ASSERT_EQ(summary["id_minus_ood"].size(), 1U);
  EXPECT_DOUBLE_EQ(summary["id_minus_ood"][0]["difference"].get<double>(), 0.5);
  const std::vector<TextTable> tables = SweepTables(summary);
  ASSERT_EQ(tables[0].name, "success_tavis-head");
  EXPECT_EQ(tables[0].header.back(), "gr1t2 head id - ood-spatial");
  EXPECT_EQ(tables[0].rows[1].back(), "+50.0") << "clutter-pick-cube is the suite's second task";
  EXPECT_EQ(tables[0].rows[0].back(), "-") << "clutter-pick-lift was not evaluated";
  std::string markdown;
  for (const TextTable& table : SweepTables(summary)) markdown += ToMarkdown(table) + ToCsv(table) + ToLatex(table);
  EXPECT_NE(markdown.find("| clutter-pick-cube | gr1t2 | head | ood-spatial | 75.0 | 25.0 | +50.0 |"),
            std::string::npos)
      << markdown;
  EXPECT_NE(markdown.find("75.0 [30.1, 95.4]"), std::string::npos) << markdown;  // Wilson 3/4
  EXPECT_NE(markdown.find("\\begin{tabular}"), std::string::npos);
}

}  // namespace
}  // namespace tavis::batch::report
