// Figure 4 against a dataset reference, end to end: a small dataset recorded by `tavis demos`, a
// sweep whose spec names it under figures.galt_reference_datasets, and the figure's numbers read
// back from its SVG: the reference's bins and median equal what this test computes from the
// per-episode lines of `tavis galt --dataset` on the same folder, and |delta median| / median is
// the two medians'.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/child_process.h"
#include "tests/tools/tool_runner.h"

namespace tavis::tools::sweep {
namespace {

class DatasetReference : public TavisCommandTest {};

// The data-* attributes of the SVG elements that carry `attribute`, in document order.
std::vector<std::map<std::string, std::string>> Marks(const std::string& svg, const std::string& attribute) {
  std::vector<std::map<std::string, std::string>> marks;
  const std::regex element("<(rect|line)[^>]*>");
  const std::regex data("data-([a-z_]+)=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), element); it != std::sregex_iterator(); ++it) {
    const std::string text = it->str();
    std::map<std::string, std::string> values;
    for (auto d = std::sregex_iterator(text.begin(), text.end(), data); d != std::sregex_iterator(); ++d)
      values[(*d)[1]] = (*d)[2];
    if (values.count(attribute)) marks.push_back(values);
  }
  return marks;
}

double MedianOf(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

TEST_F(DatasetReference, Figure4DrawsTheDatasetsGaltAsTavisGaltComputesIt) {
  const fs::path dataset = root_ / "demos";
  const RunResult demos =
      Run("demos --task clutter-pick-cube --episodes 3 --image-size 64x48 --cameras head --quiet --out " +
          Quote(dataset.string()));
  ASSERT_EQ(demos.exit_code, 0) << demos.err;

  // The reference as `tavis galt --dataset` reports it: one JSON line per episode, then the table.
  const RunResult galt = Run("galt --dataset " + Quote(dataset.string()));
  ASSERT_EQ(galt.exit_code, 0) << galt.err;
  std::vector<double> reference;
  int episodes = 0;
  for (const std::string& line : Lines(galt.out)) {
    if (line[0] != '{') break;  // the validation table follows
    const nlohmann::json result = nlohmann::json::parse(line);
    ++episodes;
    if (!result["galt_s"].is_null()) reference.push_back(result["galt_s"]);
  }
  ASSERT_EQ(episodes, 3);
  ASSERT_FALSE(reference.empty()) << galt.out;

  std::ofstream(root_ / "spec.yaml")
      << "tasks: [clutter-pick-cube]\nrobots: [gr1t2]\nsplits: [id]\ncameras: [head]\nseeds: [0]\n"
         "episodes: 3\nenvs: 3\npolicy: {name: expert}\n"
         "figures:\n  galt_reference_datasets: {clutter-pick-cube: "
      << Quote(dataset.string()) << "}\n";
  const fs::path out = root_ / "out";
  const RunResult sweep =
      Run("sweep " + Quote((root_ / "spec.yaml").string()) + " --out " + Quote(out.string()) + " --quiet");
  ASSERT_EQ(sweep.exit_code, 0) << sweep.err;

  // Figure 4's 20 bins on [-0.5, 3.5] s, the 3.0 s window: computed here from galt's lines.
  std::vector<int> expected_counts(20, 0);
  std::vector<double> in_window;
  for (const double value : reference) {
    if (value < -0.5 || value > 3.0) continue;
    in_window.push_back(value);
    ++expected_counts[static_cast<std::size_t>(std::min(19, static_cast<int>((value + 0.5) / 0.2)))];
  }
  ASSERT_FALSE(in_window.empty());
  const std::string svg = ReadText(out / "figures" / "fig4_galt.svg");
  std::vector<int> drawn_counts, policy_counts;
  for (const auto& bin : Marks(svg, "count")) {
    (bin.at("series") == "reference" ? drawn_counts : policy_counts).push_back(std::stoi(bin.at("count")));
  }
  EXPECT_EQ(drawn_counts, expected_counts);
  ASSERT_EQ(policy_counts.size(), 20U);
  std::map<std::string, double> medians;
  for (const auto& marker : Marks(svg, "median")) medians[marker.at("series")] = std::stod(marker.at("median"));
  ASSERT_EQ(medians.size(), 2U) << svg;
  EXPECT_NEAR(medians["reference"], MedianOf(in_window), 1e-9);

  // The policy's side is the sweep's own GALT values, and the title's |delta median| / median is
  // the two medians'.
  const nlohmann::json summary = nlohmann::json::parse(ReadText(out / "summary.json"));
  std::vector<double> policy;
  for (const auto& value : summary["cells"][0]["galt"]["values_s"]) {
    if (value.get<double>() >= -0.5 && value.get<double>() <= 3.0) policy.push_back(value);
  }
  ASSERT_FALSE(policy.empty());
  EXPECT_NEAR(medians["policy"], MedianOf(policy), 1e-9);
  char relative[64];
  std::snprintf(relative, sizeof(relative), "|delta median| / median = %.1f%%",
                100.0 * std::abs(MedianOf(policy) - MedianOf(in_window)) / MedianOf(in_window));
  EXPECT_NE(svg.find(relative), std::string::npos) << relative << "\n" << svg;
  const auto& row = summary["figures"]["fig4"]["tasks"][0];
  EXPECT_EQ(row["reference_source"], dataset.string());
  EXPECT_EQ(summary["figures"]["fig4"]["reference"], dataset.string());
  EXPECT_EQ(summary["spec"]["figures"]["galt_reference_datasets"]["clutter-pick-cube"], dataset.string());

  // Every product read back equals summary.json (the figures' SVG data, PNGs, report.html).
  testing::ChildProcess figures(testing::kDebianPython,
                                {TAVIS_TEST_DATA_DIR "/sweep/check_paper_figures.py", out.string()},
                                "needs Debian's python3-av and python3-numpy (.ci/install-deps)");
  const std::string checked = figures.ReadAllOutput(std::chrono::seconds(120));
  EXPECT_NE(checked.find("figures ok: 6 figures"), std::string::npos) << checked;
}

TEST_F(DatasetReference, AMissingOrUnreadableDatasetStopsTheSweepBeforeItRuns) {
  const auto spec = [this](const std::string& figures) {
    std::ofstream(root_ / "spec.yaml") << "tasks: [clutter-pick-cube]\nrobots: [gr1t2]\nsplits: [id]\ncameras: [head]\n"
                                          "seeds: [0]\nepisodes: 1\npolicy: {name: expert}\nfigures:\n"
                                       << figures;
    return Run("sweep " + Quote((root_ / "spec.yaml").string()) + " --out " + Quote((root_ / "out").string()) +
               " --quiet");
  };
  const std::string missing = (root_ / "nowhere").string();
  const RunResult none = spec("  galt_reference_datasets: {clutter-pick-cube: " + Quote(missing) + "}\n");
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_NE(
      none.err.find("figures.galt_reference_datasets.clutter-pick-cube: '" + missing + "' is not a LeRobot dataset"),
      std::string::npos)
      << none.err;
  EXPECT_FALSE(fs::exists(root_ / "out"));
  // A folder that has meta/info.json but no data: named when the sweep starts, before any cell.
  fs::create_directories(root_ / "empty" / "meta");
  std::ofstream(root_ / "empty" / "meta" / "info.json")
      << R"({"codebase_version": "v3.0", "fps": 20, "total_episodes": 1})";
  const RunResult empty =
      spec("  galt_reference_datasets: {clutter-pick-cube: " + Quote((root_ / "empty").string()) + "}\n");
  EXPECT_EQ(empty.exit_code, 1);
  EXPECT_NE(empty.err.find("figures.galt_reference_datasets.clutter-pick-cube: "), std::string::npos) << empty.err;
  EXPECT_FALSE(fs::exists(root_ / "out" / "cells" / "clutter-pick-cube_gr1t2_id_head_expert_s0" / "episodes.jsonl"));
}

}  // namespace
}  // namespace tavis::tools::sweep
