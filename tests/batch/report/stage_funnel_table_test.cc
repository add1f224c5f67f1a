// `tavis table`'s stage funnel section, read from the cells' summary.json files.
#include "batch/report/stage_funnel_table.h"
#include "tests/support/test_folder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

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
  EXPECT_NE(clutter.find("| clutter-pick-cube | gr1t2 id head | 20 | target_approached 90.0 → target_grasped 70.0 → "
                         "target_lifted 50.0 | 50.0 | 1 |"),
            std::string::npos)
      << clutter;
  const std::string hands = FormatFunnelMarkdown(BuildResultsTable(cells, "tavis-hands"), cells);
  EXPECT_NE(hands.find("| peeking-box | gr1t2 id wrists-only | 4 | - | 25.0 | 2 |"), std::string::npos) << hands;
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
