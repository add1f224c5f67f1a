// `tavis galt --dataset`: the real program on synthetic LeRobot datasets built from GALT
// conformance vectors. Per-episode results equal the reference's, the 20 Hz row equals GALT on
// every third row of the 60 Hz CSV, and every bad input exits 1 with an error naming it.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/batch/dataset/synthetic_dataset.h"
#include "tests/tools/tool_runner.h"

namespace tavis::tools {
namespace {

using batch::dataset::testing::ExpectedGaltLine;
using batch::dataset::testing::LoadGaltVector;
using batch::dataset::testing::SyntheticDatasetOptions;
using batch::dataset::testing::SyntheticEpisode;
using batch::dataset::testing::WriteSyntheticDataset;

const std::vector<std::string> kVectors = {"ep0097.csv", "ep0107.csv", "ep0079.csv"};

std::vector<SyntheticEpisode> ConformanceEpisodes() {
  std::vector<SyntheticEpisode> episodes;
  for (std::size_t i = 0; i < kVectors.size(); ++i) {
    episodes.push_back(LoadGaltVector(kVectors[i], static_cast<std::int64_t>(i)));
    episodes.back().tasks = {"Task" + std::to_string(i)};
  }
  return episodes;
}

// Every `stride`-th row of `episode` from row 0, as CSV text.
std::string EveryNthRowCsv(const SyntheticEpisode& episode, int stride) {
  std::string csv;
  for (int t = 0; t < episode.num_steps; t += stride) {
    for (int j = 0; j < episode.width; ++j) {
      // The dataset stores float32: the CSV carries the same values, printed exactly.
      const double value = static_cast<float>(episode.actions[static_cast<std::size_t>(t * episode.width + j)]);
      csv += (j ? "," : "") + nlohmann::json(value).dump();
    }
    csv += "\n";
  }
  return csv;
}

class GaltDatasetCommandTest : public TavisCommandTest {
 protected:
  // root_ is set in SetUp, after member initialisation.
  fs::path Dataset() const { return root_ / "dataset"; }

  nlohmann::json TableJson() const { return nlohmann::json::parse(ReadText(root_ / "table.json")); }
};

void ExpectReferenceResults(const RunResult& run) {
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::vector<std::string> lines = Lines(run.out);
  ASSERT_GE(lines.size(), kVectors.size());
  for (std::size_t i = 0; i < kVectors.size(); ++i) {
    SCOPED_TRACE(kVectors[i]);
    nlohmann::json got = nlohmann::json::parse(lines[i]);
    nlohmann::json expected = nlohmann::json::parse(ExpectedGaltLine(kVectors[i]));
    EXPECT_EQ(got["episode"], i);
    EXPECT_EQ(got["task"], "Task" + std::to_string(i));
    EXPECT_EQ(got["reason"], expected["reason"]);
    EXPECT_EQ(got["arm"], expected["arm"]);
    for (const char* key : {"galt_s", "t_head_arrival_s", "t_hand_arrival_s", "t_hand_onset_s", "arm_reach_s"}) {
      if (expected[key].is_null()) {
        EXPECT_TRUE(got[key].is_null()) << key;
      } else {
        EXPECT_NEAR(got[key].get<double>(), expected[key].get<double>(), 1e-9) << key;
      }
    }
  }
}

TEST_F(GaltDatasetCommandTest, V30EpisodesMatchTheReference) {
  WriteSyntheticDataset(Dataset(), ConformanceEpisodes());
  const RunResult run =
      Run("galt --dataset " + Quote(Dataset().string()) + " --json-out " + Quote((root_ / "table.json").string()));
  ExpectReferenceResults(run);
  EXPECT_NE(run.out.find("| robot | rate | episodes | detected | mean s | median s |"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("| gr1t2 | 60 Hz | 3 | 2 (66.7 %) | 1.49 | 1.49 |"), std::string::npos) << run.out;

  const nlohmann::json table = TableJson();
  ASSERT_EQ(table["rows"].size(), 2U);
  const nlohmann::json& at_60 = table["rows"][0];
  EXPECT_EQ(at_60["robot"], "gr1t2");
  EXPECT_EQ(at_60["rate_hz"], 60.0);
  EXPECT_EQ(at_60["n_episodes"], 3);
  EXPECT_EQ(at_60["n_valid"], 2);
  const double mean = (0.9666666666666667 + 2.0166666666666666) / 2;
  EXPECT_NEAR(at_60["mean_s"].get<double>(), mean, 1e-12);
  EXPECT_NEAR(at_60["median_s"].get<double>(), mean, 1e-12);
  EXPECT_EQ(at_60["reasons"], (nlohmann::json{{"ok", 2}, {"no_hand_onset", 1}}));
}

TEST_F(GaltDatasetCommandTest, V21EpisodesMatchTheReference) {
  SyntheticDatasetOptions options;
  options.codebase_version = "v2.1";
  options.robot_type = std::nullopt;
  WriteSyntheticDataset(Dataset(), ConformanceEpisodes(), options);
  const RunResult run = Run("galt --dataset " + Quote(Dataset().string()));
  ExpectReferenceResults(run);
  EXPECT_NE(run.out.find("| unknown | 60 Hz | 3 |"), std::string::npos) << run.out;
}

TEST_F(GaltDatasetCommandTest, TwentyHertzRowIsEveryThirdRowOfTheCsv) {
  const std::vector<SyntheticEpisode> episodes = ConformanceEpisodes();
  WriteSyntheticDataset(Dataset(), episodes);
  std::string csv_files;
  for (std::size_t i = 0; i < episodes.size(); ++i) {
    const fs::path csv = root_ / ("every_third_" + std::to_string(i) + ".csv");
    std::ofstream(csv) << EveryNthRowCsv(episodes[i], 3);
    csv_files += " " + Quote(csv.string());
  }
  const RunResult csv_run = Run("galt --fps 20" + csv_files);
  ASSERT_EQ(csv_run.exit_code, 0) << csv_run.err;
  std::vector<double> valid;
  nlohmann::json reasons = nlohmann::json::object();
  for (const std::string& line : Lines(csv_run.out)) {
    const nlohmann::json result = nlohmann::json::parse(line);
    if (!result["galt_s"].is_null()) valid.push_back(result["galt_s"].get<double>());
    reasons[result["reason"].get<std::string>()] = reasons.value(result["reason"].get<std::string>(), 0) + 1;
  }

  const RunResult run = Run("galt --table-only --dataset " + Quote(Dataset().string()) + " --json-out " +
                            Quote((root_ / "table.json").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out.find('{'), std::string::npos) << "--table-only prints no JSON lines:\n" << run.out;
  EXPECT_NE(run.out.find("| gr1t2 | 20 Hz | 3 |"), std::string::npos) << run.out;
  const nlohmann::json at_20 = TableJson()["rows"][1];
  EXPECT_EQ(at_20["rate_hz"], 20.0);
  EXPECT_EQ(at_20["stride"], 3);
  EXPECT_EQ(at_20["n_valid"], valid.size());
  EXPECT_EQ(at_20["reasons"], reasons);
  if (!valid.empty()) {
    double sum = 0.0;
    for (const double v : valid) sum += v;
    EXPECT_NEAR(at_20["mean_s"].get<double>(), sum / static_cast<double>(valid.size()), 1e-12);
  }
}

// Each bad input: exit status 1 and an error naming the file and the problem.
TEST_F(GaltDatasetCommandTest, BadInputsExitOneWithNamedErrors) {
  struct Case {
    std::string name;
    void (*break_dataset)(const fs::path& dir);
    std::string expected_error;
  };
  const std::vector<Case> cases = {
      {"missing info", [](const fs::path& dir) { fs::remove(dir / "meta/info.json"); }, "meta/info.json: missing"},
      {"unknown version",
       [](const fs::path& dir) {
         std::string info = ReadText(dir / "meta/info.json");
         info.replace(info.find("v3.0"), 4, "v9.9");
         std::ofstream(dir / "meta/info.json") << info;
       },
       "unknown codebase_version \"v9.9\""},
      {"truncated parquet",
       [](const fs::path& dir) {
         const fs::path file = dir / "data/chunk-000/file-001.parquet";
         fs::resize_file(file, fs::file_size(file) - 9);
       },
       "file-001.parquet: "},
  };
  for (const Case& bad : cases) {
    SCOPED_TRACE(bad.name);
    fs::remove_all(Dataset());
    WriteSyntheticDataset(Dataset(), ConformanceEpisodes());
    bad.break_dataset(Dataset());
    const RunResult run = Run("galt --dataset " + Quote(Dataset().string()));
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_NE(run.err.find(bad.expected_error), std::string::npos) << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
  }
}

TEST_F(GaltDatasetCommandTest, BadActionsExitOneWithNamedErrors) {
  std::vector<SyntheticEpisode> narrow = ConformanceEpisodes();
  narrow[0].width = 18;
  narrow[0].actions.resize(static_cast<std::size_t>(narrow[0].num_steps) * 18);
  WriteSyntheticDataset(Dataset(), narrow);
  RunResult run = Run("galt --dataset " + Quote(Dataset().string()));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("file-000.parquet: row 0: action has 18 values, expected 19"), std::string::npos) << run.err;

  std::vector<SyntheticEpisode> infinite = ConformanceEpisodes();
  infinite[2].actions[3] = std::numeric_limits<double>::infinity();
  fs::remove_all(Dataset());
  WriteSyntheticDataset(Dataset(), infinite);
  run = Run("galt --dataset " + Quote(Dataset().string()));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("file-001.parquet: row 0: action[3] is inf"), std::string::npos) << run.err;
}

TEST_F(GaltDatasetCommandTest, RatesThatCannotBeDownsampledAndOptionMistakesAreRefused) {
  SyntheticDatasetOptions options;
  options.fps = 30;
  WriteSyntheticDataset(Dataset(), ConformanceEpisodes(), options);
  RunResult run = Run("galt --dataset " + Quote(Dataset().string()));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("cannot downsample 30 fps to the 20 Hz policy rate"), std::string::npos) << run.err;

  run = Run("galt --dataset " + Quote(Dataset().string()) + " --fps 60");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("--fps 60 overrides the dataset's fps 30"), std::string::npos) << run.err;

  // An absurd rate in info.json is refused naming the file (before: GALT ran at 1e9 fps); --fps
  // still overrides a file known to be wrong.
  nlohmann::json info = nlohmann::json::parse(ReadText(Dataset() / "meta/info.json"));
  info["fps"] = 1e9;
  std::ofstream(Dataset() / "meta/info.json") << info.dump();
  run = Run("galt --dataset " + Quote(Dataset().string()));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find(Dataset().string() + "/meta/info.json: fps must be a number from 1 to 1000, got 1000000000.0"),
            std::string::npos)
      << run.err;
  run = Run("galt --dataset " + Quote(Dataset().string()) + " --fps 60");
  EXPECT_EQ(run.exit_code, 0) << run.err;

  run = Run("galt --dataset " + Quote(Dataset().string()) + " " + Quote((root_ / "x.csv").string()));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("exactly one of them"), std::string::npos) << run.err;

  run = Run("galt " + Quote((root_ / "x.csv").string()));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("--fps is required with CSV files"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace tavis::tools
