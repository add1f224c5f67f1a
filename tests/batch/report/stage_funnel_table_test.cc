// `tavis table`'s stage funnel section, read from the cells' summary.json files.
#include "batch/report/stage_funnel_table.h"
#include "tests/support/test_folder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace tavis::batch::report {
namespace {

namespace fs = std::filesystem;

using StageFunnelTableTest = testing::TestFolder;

TEST_F(StageFunnelTableTest, PoolsSeedsPerTaskAndColumnWithTheSimulatorFaultsApart) {
  const std::string stages =
      R"("stages": [{"stage": "target_approached", "reached": A}, {"stage": "target_grasped", "reached": G},
                                          {"stage": "target_lifted", "reached": L}])";
  auto cell = [&](int seed, int episodes, int successes, int approached, int grasped, int lifted, int faults) {
    std::string funnel = stages;
    funnel.replace(funnel.find('A'), 1, std::to_string(approached));
    funnel.replace(funnel.find('G'), 1, std::to_string(grasped));
    funnel.replace(funnel.find('L'), 1, std::to_string(lifted));
    return R"({"task": "clutter-pick-cube", "robot": "gr1t2", "split": "id", "camera": "head", "policy": "p", "seed": )" +
           std::to_string(seed) + R"(, "n_episodes": )" + std::to_string(episodes) + R"(, "n_successful": )" +
           std::to_string(successes) + R"(, "simulator_faults": )" + std::to_string(faults) + ", " + funnel + "}";
  };
  testing::WriteTextFile(root_ / "s0" / "summary.json", cell(0, 10, 4, 8, 6, 4, 1));
  testing::WriteTextFile(root_ / "s1" / "summary.json", cell(1, 10, 6, 10, 8, 6, 0));
  // A cell written before stages existed: its faults come from "ends".
  testing::WriteTextFile(
      root_ / "old" / "summary.json",
      R"({"task": "peeking-box", "robot": "gr1t2", "split": "id", "camera": "wrists-only", "policy": "p",
                  "n_episodes": 4, "n_successful": 1, "ends": {"physics_blow_up": 2, "success": 1, "time_out": 1}})");
  const std::vector<CellCounts> cells = LoadCellResults(root_);
  const std::string clutter = FormatFunnelMarkdown(BuildResultsTable(cells, "tavis-head"), cells);
  EXPECT_NE(clutter.find("| policy | task | robot | split | stage | head % | head alone % |"), std::string::npos)
      << clutter;
  // Written before "reached_alone" existed: the alone share is unknown.
  EXPECT_NE(clutter.find("| p | clutter-pick-cube | gr1t2 | id | target_approached | 90.0 | - |"), std::string::npos)
      << clutter;
  EXPECT_NE(clutter.find("| p | clutter-pick-cube | gr1t2 | id | target_lifted | 50.0 | - |"), std::string::npos)
      << clutter;
  EXPECT_NE(clutter.find("| p | clutter-pick-cube | gr1t2 | id | head | 20 | 50.0 | 1 |"), std::string::npos)
      << clutter;
  const std::string hands = FormatFunnelMarkdown(BuildResultsTable(cells, "tavis-hands"), cells);
  EXPECT_NE(hands.find("| p | peeking-box | gr1t2 | id | wrists-only | 4 | 25.0 | 2 |"), std::string::npos) << hands;
}

// The rows of every pipe table in `markdown`, its heading row first.
std::vector<std::vector<std::string>> PipeRows(const std::string& markdown) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(markdown);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("|", 0) != 0 || line.find("---") != std::string::npos) continue;
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream parts(line.substr(1));
    while (std::getline(parts, cell, '|')) cells.push_back(cell.substr(1, cell.size() - 2));
    rows.push_back(cells);
  }
  return rows;
}

TEST_F(StageFunnelTableTest, HeadAndFixedSitSideBySideTheFixedGazeStageNotApplicable) {
  auto cell = [&](const std::string& camera, const std::string& cue, int approached) {
    return R"({"task": "conditional-pick", "robot": "gr1t2", "split": "id", "policy": "expert", "seed": 0,
               "camera": ")" +
           camera + R"(", "n_episodes": 4, "n_successful": 4, "simulator_faults": 0, "stages": [)" + cue +
           R"(, {"stage": "target_approached", "applies": true, "reached": )" + std::to_string(approached) +
           R"(, "reached_alone": 4}, {"stage": "target_grasped", "applies": true, "reached": 4, "reached_alone": 4},
               {"stage": "target_lifted", "applies": true, "reached": 4, "reached_alone": 4}]})";
  };
  testing::WriteTextFile(
      root_ / "head" / "summary.json",
      cell("head", R"({"stage": "cue_fixated", "applies": true, "reached": 2, "reached_alone": 2})", 2));
  testing::WriteTextFile(
      root_ / "fixed" / "summary.json",
      cell("fixed", R"({"stage": "cue_fixated", "applies": false, "reached": null, "reached_alone": null})", 4));
  const std::vector<CellCounts> cells = LoadCellResults(root_);
  const std::string text = FormatFunnelMarkdown(BuildResultsTable(cells, "tavis-head"), cells);
  const std::vector<std::vector<std::string>> rows = PipeRows(text);
  ASSERT_GE(rows.size(), 5U) << text;
  const std::vector<std::string> headings = {"policy", "task",         "robot",   "split",        "stage",
                                             "head %", "head alone %", "fixed %", "fixed alone %"};
  EXPECT_EQ(rows[0], headings) << text;
  EXPECT_EQ(rows[1], (std::vector<std::string>{"expert", "conditional-pick", "gr1t2", "id", "cue_fixated", "50.0",
                                               "50.0", "n/a", "n/a"}))
      << text;
  EXPECT_EQ(rows[2], (std::vector<std::string>{"expert", "conditional-pick", "gr1t2", "id", "target_approached", "50.0",
                                               "100.0", "100.0", "100.0"}))
      << text;
  // Every row of every table has one value per heading.
  std::size_t width = 0;
  for (const std::vector<std::string>& row : rows) {
    if (row.size() != width && (row[0] == "policy")) width = row.size();
    EXPECT_EQ(row.size(), width) << text;
  }
}

TEST_F(StageFunnelTableTest, AMalformedFunnelNamesTheFile) {
  testing::WriteTextFile(root_ / "bad" / "summary.json",
                         R"({"stages": [{"stage": "target_grasped", "reached": "many"}]})");
  try {
    ReadCellFunnel((root_ / "bad" / "summary.json").string());
    FAIL() << "expected an error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("bad/summary.json"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace tavis::batch::report
