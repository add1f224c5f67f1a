// `tavis sweep` with labelled policies end to end: two policies that behave differently (the
// expert and hold) and a seed group of three expert checkpoints over 2 tasks x 2 cameras. The
// tables keep the labels apart, `tavis table` refuses to pool labels unless told, the seed group
// has its mean and spread, and every paper product read back equals summary.json (figures' SVG
// data and PNGs, Table 1, the headline numbers, report.html).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/child_process.h"
#include "tests/tools/tool_runner.h"

namespace tavis::tools::sweep {
namespace {

const char* kLabelledSpec =
    "tasks: [clutter-pick-cube, blocked-clutter-pick-cube]\n"
    "robots: [gr1t2]\n"
    "splits: [id]\n"
    "cameras: [head, fixed]\n"
    "seeds: [0]\n"
    "episodes: 3\n"
    "envs: 3\n"
    "policies:\n"
    "  - {label: expert-a, name: expert, seed_group: expert-recipe}\n"
    "  - {label: expert-b, name: expert, seed_group: expert-recipe}\n"
    "  - {label: expert-c, name: expert, seed_group: expert-recipe}\n"
    "  - {label: still, name: hold}\n"
    "figures:\n"
    "  policy: expert-a\n"
    "  single_vs_multi: [still, expert-recipe]\n"
    "  galt_reference: expert-b\n";

class LabelledSweep : public TavisCommandTest {
 protected:
  void SetUp() override {
    TavisCommandTest::SetUp();
    std::ofstream(root_ / "labelled.yaml") << kLabelledSpec;
  }
};

double HeadRate(const nlohmann::json& summary, const std::string& label, const std::string& task) {
  for (const auto& cell : summary["cells"]) {
    if (cell["label"] == label && cell["task"] == task && cell["camera"] == "head") return cell["success_rate"];
  }
  ADD_FAILURE() << label << " " << task;
  return -1;
}

TEST_F(LabelledSweep, KeepsLabelsApartAndItsProductsEqualTheSummary) {
  const fs::path out = root_ / "out";
  const RunResult run =
      Run("sweep " + Quote((root_ / "labelled.yaml").string()) + " --out " + Quote(out.string()) + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(ReadText(out / "summary.json"));
  ASSERT_EQ(summary["labels"].size(), 4U);
  ASSERT_EQ(summary["cells"].size(), 16U);
  // They behave differently: the expert succeeds, hold never does; separate tables.
  EXPECT_GT(HeadRate(summary, "expert-a", "clutter-pick-cube"), 0.5);
  EXPECT_EQ(HeadRate(summary, "still", "clutter-pick-cube"), 0.0);
  EXPECT_TRUE(fs::exists(out / "tables" / "success_tavis-head_still.md"));
  EXPECT_TRUE(fs::exists(out / "tables" / "success_tavis-head_expert-a.md"));
  EXPECT_NE(ReadText(out / "tables" / "success_tavis-head_still.md").find("| clutter-pick-cube | 0.0 [0.0, 56.2] |"),
            std::string::npos)
      << ReadText(out / "tables" / "success_tavis-head_still.md");
  EXPECT_EQ(nlohmann::json::parse(
                ReadText(out / "cells" / "clutter-pick-cube_gr1t2_id_head_still_s0" / "policy.json"))["label"],
            "still");
  // The seed group: the three checkpoints (the same expert here, so no spread) give the rate.
  ASSERT_EQ(summary["seed_groups"].size(), 1U);
  const auto& row = summary["seed_groups"][0]["rows"][0];
  EXPECT_EQ(row["n"], 3);
  EXPECT_DOUBLE_EQ(row["mean"].get<double>(), HeadRate(summary, "expert-a", "clutter-pick-cube"));
  EXPECT_DOUBLE_EQ(row["std"].get<double>(), 0.0);

  // `tavis table` refuses to pool the four labels, and takes one or a declared pooling.
  const std::string table = "table --in " + Quote((out / "cells").string()) + " --suite tavis-head --out ";
  const RunResult refused = Run(table + Quote((root_ / "pooled").string()));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(
      refused.err.find("4 policy labels: expert-a (4 cells), expert-b (4 cells), expert-c (4 cells), still (4 cells)"),
      std::string::npos)
      << refused.err;
  EXPECT_FALSE(fs::exists(root_ / "pooled.md"));
  const RunResult still = Run(table + Quote((root_ / "still").string()) + " --label still");
  ASSERT_EQ(still.exit_code, 0) << still.err;
  EXPECT_NE(ReadText(root_ / "still.md").find("0.0 [0.0, 56.2]"), std::string::npos) << ReadText(root_ / "still.md");
  fs::create_directories(root_ / "two");
  for (const char* label : {"expert-a", "expert-b"}) {
    fs::copy(out / "cells" / ("clutter-pick-cube_gr1t2_id_head_" + std::string(label) + "_s0"), root_ / "two" / label,
             fs::copy_options::recursive);
  }
  const std::string two = "table --in " + Quote((root_ / "two").string()) + " --suite tavis-head --out " +
                          Quote((root_ / "two_table").string());
  EXPECT_EQ(Run(two).exit_code, 1);
  const RunResult pooled = Run(two + " --pool-labels");
  ASSERT_EQ(pooled.exit_code, 0) << pooled.err;
  const int successes = static_cast<int>(std::lround(3 * HeadRate(summary, "expert-a", "clutter-pick-cube")));
  char expected[64];
  std::snprintf(expected, sizeof(expected), "%.1f", 100.0 * (2 * successes) / 6.0);
  EXPECT_NE(ReadText(root_ / "two_table.md").find(expected), std::string::npos) << ReadText(root_ / "two_table.md");

  // Every product read back by an independent reader equals summary.json.
  testing::ChildProcess figures(testing::kDebianPython,
                                {TAVIS_TEST_DATA_DIR "/sweep/check_paper_figures.py", out.string()},
                                "needs Debian's python3-av and python3-numpy (.ci/install-deps)");
  const std::string checked = figures.ReadAllOutput(std::chrono::seconds(120));
  // The paper's five and the three gaze figures (docs/paper-figures.md, "Gaze figures").
  EXPECT_NE(checked.find("figures ok: 8 figures"), std::string::npos) << checked;
  fs::create_directories(root_ / "chromium");
  testing::ChildProcess chromium(
      testing::kDebianPython,
      {TAVIS_TEST_DATA_DIR "/sweep/check_report_in_chromium.py", out.string(), (root_ / "chromium").string()},
      "needs Debian's chromium and python3-av (.ci/install-deps)");
  const std::string report = chromium.ReadAllOutput(std::chrono::seconds(180));
  EXPECT_NE(report.find("report ok: 16 cells"), std::string::npos) << report;
}

}  // namespace
}  // namespace tavis::tools::sweep
