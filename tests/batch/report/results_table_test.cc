#include "batch/report/results_table.h"
#include "tests/support/test_folder.h"
#include "tests/support/thrown_message.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace tavis::batch::report {
namespace {

namespace fs = std::filesystem;

// A fresh folder per test, removed afterwards.
class ResultsTableTest : public testing::TestFolder {
 protected:
  ResultsTableTest() : TestFolder("results_table") {}

  void WriteSummary(const std::string& cell_dir, const std::string& json) {
    testing::WriteTextFile(root_ / cell_dir / "summary.json", json);
  }

  void WriteCell(const std::string& cell_dir, const std::string& task, const std::string& robot,
                 const std::string& split, const std::string& camera, int successes, int episodes) {
    std::ostringstream json;
    json << R"({"task": ")" << task << R"(", "robot": ")" << robot << R"(", "split": ")" << split << R"(", "camera": ")"
         << camera << R"(", "policy": "expert", "n_episodes": )" << episodes << R"(, "n_successful": )" << successes
         << R"(, "success_rate": 0.0, "wall_s": 1.0})";
    WriteSummary(cell_dir, json.str());
  }

  // The paper's GR1T2 id head column of TAVIS-Head (reference spec 14), plus: one id fixed
  // cell, a reachy2 ood-spatial column with two seeds of one task pooled and unequal episode
  // counts, and a TAVIS-Hands cell that the TAVIS-Head table leaves out.
  void WriteSweep() {
    WriteCell("gr1t2/id/head/conditional-pick", "conditional-pick", "gr1t2", "id", "head", 84, 96);
    WriteCell("gr1t2/id/head/wait-then-act", "wait-then-act", "gr1t2", "id", "head", 63, 96);
    WriteCell("gr1t2/id/head/clutter-pick-cube", "clutter-pick-cube", "gr1t2", "id", "head", 40, 96);
    WriteCell("gr1t2/id/head/clutter-pick-lift", "clutter_pick_lift", "gr1t2", "id", "head", 22, 96);
    WriteCell("gr1t2/id/head/multi-shelf-scan", "multi-shelf-scan", "gr1t2", "id", "head", 17, 96);
    WriteCell("gr1t2/id/fixed/conditional-pick", "conditional-pick", "gr1t2", "id", "fixedcam", 57, 96);
    WriteCell("reachy2/ood/seed1/clutter-pick-cube", "clutter-pick-cube", "reachy2", "ood_spatial", "head", 12, 48);
    WriteCell("reachy2/ood/seed2/clutter-pick-cube", "clutter-pick-cube", "reachy2", "ood-spatial", "head", 13, 48);
    WriteCell("reachy2/ood/seed1/multi-shelf-scan", "multi-shelf-scan", "reachy2", "ood-spatial", "head", 16, 48);
    WriteCell("gr1t2/id/head/peeking-box", "peeking_box", "gr1t2", "id", "head", 62, 96);
  }
};

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST_F(ResultsTableTest, PaperLayoutWithIntervals) {
  WriteSweep();
  const ResultsTable table = BuildResultsTable(LoadCellResults(root_), "tavis-head");
  ASSERT_EQ(table.columns.size(), 3u);
  EXPECT_EQ(table.columns[0].label(), "gr1t2 id head");
  EXPECT_EQ(table.columns[1].label(), "gr1t2 id fixed");
  EXPECT_EQ(table.columns[2].label(), "reachy2 ood-spatial head");

  const std::vector<std::string> lines = Lines(FormatMarkdown(table, true));
  // caption, blank, header, rule, 5 tasks, 2 suite means, blank, note
  ASSERT_EQ(lines.size(), 13u);
  EXPECT_EQ(lines[2], "| task | gr1t2 id head | gr1t2 id fixed | reachy2 ood-spatial head |");
  EXPECT_EQ(lines[4], "| clutter-pick-lift | 22.9 [15.6, 32.3] | - | - |");
  EXPECT_EQ(lines[5], "| clutter-pick-cube | 41.7 [32.3, 51.7] | - | 26.0 [18.3, 35.6] |");
  EXPECT_EQ(lines[6], "| conditional-pick | 87.5 [79.4, 92.7] | 59.4 [49.4, 68.7] | - |");
  EXPECT_EQ(lines[7], "| wait-then-act | 65.6 [55.7, 74.4] | - | - |");
  EXPECT_EQ(lines[8], "| multi-shelf-scan | 17.7 [11.4, 26.5] | - | 33.3 [21.7, 47.5] |");
  // Equal counts: the task average equals the pooled rate (the paper's 47.1 [42.7, 51.6] over
  // 480 episodes); unequal counts: (26.04 + 33.33) / 2 = 29.7 against 41 / 144 = 28.5.
  EXPECT_EQ(lines[9], "| TAVIS-Head mean (task average) | 47.1 | 59.4 | 29.7 |");
  EXPECT_EQ(lines[10],
            "| TAVIS-Head mean (pooled over episodes) | 47.1 [42.7, 51.6] | 59.4 [49.4, 68.7] | "
            "28.5 [21.7, 36.3] |");
  EXPECT_EQ(lines[12],
            "Suite means over the evaluated tasks only: gr1t2 id fixed (1 of 5 tasks); "
            "reachy2 ood-spatial head (2 of 5 tasks).");
}

TEST_F(ResultsTableTest, CsvWithAndWithoutIntervals) {
  WriteSweep();
  const ResultsTable table = BuildResultsTable(LoadCellResults(root_), "tavis-head");
  const std::vector<std::string> with = Lines(FormatCsv(table, true));
  ASSERT_EQ(with.size(), 8u);
  EXPECT_EQ(with[0],
            "task,gr1t2 id head,gr1t2 id head ci_low,gr1t2 id head ci_high,gr1t2 id fixed,"
            "gr1t2 id fixed ci_low,gr1t2 id fixed ci_high,reachy2 ood-spatial head,"
            "reachy2 ood-spatial head ci_low,reachy2 ood-spatial head ci_high");
  EXPECT_EQ(with[3], "conditional-pick,87.5,79.4,92.7,59.4,49.4,68.7,,,");
  EXPECT_EQ(with[6], "TAVIS-Head mean (task average),47.1,,,59.4,,,29.7,,");
  EXPECT_EQ(with[7],
            "TAVIS-Head mean (pooled over episodes),47.1,42.7,51.6,59.4,49.4,68.7,28.5,"
            "21.7,36.3");

  const std::vector<std::string> without = Lines(FormatCsv(table, false));
  EXPECT_EQ(without[0], "task,gr1t2 id head,gr1t2 id fixed,reachy2 ood-spatial head");
  EXPECT_EQ(without[2], "clutter-pick-cube,41.7,,26.0");
  EXPECT_EQ(without[7], "TAVIS-Head mean (pooled over episodes),47.1,59.4,28.5");
  EXPECT_EQ(Lines(FormatMarkdown(table, false))[6], "| conditional-pick | 87.5 | 59.4 | - |");
}

TEST_F(ResultsTableTest, HandsSuiteTakesOnlyItsTasks) {
  WriteSweep();
  const ResultsTable table = BuildResultsTable(LoadCellResults(root_), "tavis-hands");
  ASSERT_EQ(table.columns.size(), 1u);
  ASSERT_EQ(table.tasks.size(), 3u);
  EXPECT_EQ(table.tasks[0], "peeking-box");
  ASSERT_TRUE(table.cells[0][0].has_value());
  EXPECT_EQ(table.cells[0][0]->n_successful, 62);
  EXPECT_FALSE(table.cells[1][0].has_value());
  EXPECT_EQ(table.pooled[0]->n_episodes, 96);
}

TEST_F(ResultsTableTest, ErrorsNameTheFileAndKey) {
  WriteSummary("bad", R"({"task": "wait-then-act", "robot": "gr1t2", "split": "id",
                           "n_episodes": 96, "n_successful": 97})");
  try {
    LoadCellResults(root_);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad/summary.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("n_successful = 97"), std::string::npos) << e.what();
  }
  WriteSummary("bad", R"({"task": "wait-then-act", "split": "id", "n_episodes": 96,
                           "n_successful": 9})");
  EXPECT_THROW(LoadCellResults(root_), std::runtime_error);
  WriteSummary("bad", R"({"task": "wait-then-act", "robot": "gr1t2", "split": "id",
                           "n_episodes": "96", "n_successful": 9})");
  EXPECT_THROW(LoadCellResults(root_), std::runtime_error);
  WriteSummary("bad", "{not json");
  EXPECT_THROW(LoadCellResults(root_), std::runtime_error);
}

TEST_F(ResultsTableTest, CopiedCellIsRefusedNamingBothFiles) {
  const std::string cell = R"({"task": "wait-then-act", "robot": "gr1t2", "split": "id", "seed": 7,
                                "n_episodes": 4, "n_successful": 4})";
  WriteSummary("cell", cell);
  WriteSummary("cell copy", cell);
  try {
    LoadCellResults(root_);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/cell/summary.json and " + (root_ / "cell copy").string()), std::string::npos)
        << e.what();
  }
  // Another seed of the same cell is pooled.
  WriteSummary("cell copy", R"({"task": "wait-then-act", "robot": "gr1t2", "split": "id", "seed": 8,
                                 "n_episodes": 4, "n_successful": 2})");
  EXPECT_EQ(BuildResultsTable(LoadCellResults(root_), "tavis-head").pooled[0]->n_episodes, 8);
}

TEST_F(ResultsTableTest, UnknownNamesAreErrorsNamingTheFile) {
  WriteSummary("a", R"({"task": "wait-then-act", "robot": "gr1t3", "split": "id", "n_episodes": 1,
                        "n_successful": 1})");
  EXPECT_NO_THROW(LoadCellResults(root_));  // robots are checked only against a given list
  try {
    LoadCellResults(root_, {"gr1t2", "reachy2"});
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("a/summary.json: unknown robot 'gr1t3' (known: gr1t2, reachy2)"),
              std::string::npos)
        << e.what();
  }
  WriteSummary("a", R"({"task": "wait-then-act", "robot": "gr1t2", "split": "od", "n_episodes": 1,
                        "n_successful": 1})");
  EXPECT_THROW(LoadCellResults(root_), std::runtime_error);
}

TEST_F(ResultsTableTest, CountsBeyondThirtyTwoBits) {
  // Three billion episodes: an int count would wrap negative.
  WriteSummary("a", R"({"task": "wait-then-act", "robot": "gr1t2", "split": "id", "n_episodes": 3000000000,
                        "n_successful": 1500000000})");
  const ResultsTable table = BuildResultsTable(LoadCellResults(root_), "tavis-head");
  EXPECT_EQ(table.pooled[0]->n_episodes, 3000000000);
  EXPECT_DOUBLE_EQ(table.task_average[0].value(), 0.5);
}

TEST_F(ResultsTableTest, MixedPoliciesOrNoCellsAreErrors) {
  WriteCell("a", "wait-then-act", "gr1t2", "id", "head", 1, 2);
  WriteSummary("b", R"({"task": "conditional-pick", "robot": "gr1t2", "split": "id",
                         "policy": "replay", "n_episodes": 2, "n_successful": 1})");
  EXPECT_THROW(BuildResultsTable(LoadCellResults(root_), "tavis-head"), std::runtime_error);
  EXPECT_THROW(BuildResultsTable(LoadCellResults(root_), "tavis-hands"), std::runtime_error);
  EXPECT_THROW(BuildResultsTable({}, "tavis-feet"), std::invalid_argument);
}

// A tavis cell: summary.json with its seed as `seed_json` (omitted when empty) and the
// episodes.jsonl of `episodes` episodes of seed 7, the first `successes` successful.
void WriteRecordedCell(const fs::path& dir, const std::string& seed_json, int episodes, int successes,
                       int first_episode = 0) {
  fs::create_directories(dir);
  std::ofstream records(dir / "episodes.jsonl");
  for (int i = 0; i < episodes; ++i) {
    records << R"({"episode":)" << first_episode + i << R"(,"seed":7,"success":)" << (i < successes ? "true" : "false")
            << R"(,"end":")" << (i < successes ? "success" : "time_out") << R"(","length_steps":)" << 100 + i << "}\n";
  }
  std::ofstream(dir / "summary.json")
      << R"({"task": "wait-then-act", "robot": "gr1t2", "split": "id", "policy": "expert", )"
      << (seed_json.empty() ? "" : "\"seed\": " + seed_json + ", ") << "\"n_episodes\": " << episodes
      << ", \"n_successful\": " << successes << "}";
}

std::string LoadError(const fs::path& root) {
  return testing::ThrownMessage<std::runtime_error>([&root] { LoadCellResults(root); });
}

// The 192-from-96 case: a copied cell whose summary lost its seed, or names it as a string, or
// another seed, still holds the first cell's records: refused, naming both files.
TEST_F(ResultsTableTest, CopiedCellIsRefusedByItsRecordsWhateverItsSeedSays) {
  WriteRecordedCell(root_ / "cell", "7", 4, 3);
  for (const std::string& copy_seed : {std::string(), std::string("\"7\""), std::string("8")}) {
    WriteRecordedCell(root_ / "copy", copy_seed, 4, 3);
    const std::string error = LoadError(root_);
    EXPECT_NE(
        error.find((root_ / "cell" / "summary.json").string() + " and " + (root_ / "copy" / "summary.json").string()),
        std::string::npos)
        << "seed " << copy_seed << ": " << error;
  }
  // Part of the cell copied: the episodes it shares are named.
  WriteRecordedCell(root_ / "copy", "", 2, 2, 2);
  EXPECT_NE(LoadError(root_).find("both hold episode 2 of seed 7"), std::string::npos) << LoadError(root_);
  // Other episodes of the same seed (e.g. the cell's second half run apart) are pooled.
  WriteRecordedCell(root_ / "copy", "", 2, 2, 4);
  EXPECT_EQ(BuildResultsTable(LoadCellResults(root_), "tavis-head").pooled[0]->n_episodes, 6);
}

TEST_F(ResultsTableTest, RecordsThatDisagreeWithTheSummaryNameTheCell) {
  WriteRecordedCell(root_ / "cell", "7", 4, 3);
  std::ofstream(root_ / "cell" / "episodes.jsonl", std::ios::app) << R"({"episode":3,"seed":7,"success":false})"
                                                                  << "\n";
  EXPECT_NE(LoadError(root_).find(
                "cell " + (root_ / "cell").string() +
                ": episodes.jsonl holds 5 episodes (3 successful) but summary.json says n_episodes 4, n_successful 3"),
            std::string::npos)
      << LoadError(root_);
  WriteRecordedCell(root_ / "cell", "7", 4, 3);
  std::ofstream(root_ / "cell" / "summary.json")
      << R"({"task": "wait-then-act", "robot": "gr1t2", "split": "id", "seed": 7,
                                                       "n_episodes": 4, "n_successful": 4})";
  EXPECT_NE(LoadError(root_).find("holds 4 episodes (3 successful) but summary.json says n_episodes 4, n_successful 4"),
            std::string::npos)
      << LoadError(root_);
  WriteRecordedCell(root_ / "cell", "7", 4, 3);
  std::ofstream(root_ / "cell" / "episodes.jsonl", std::ios::app) << "{\"episode\":4,\"se\n";
  EXPECT_NE(LoadError(root_).find((root_ / "cell" / "episodes.jsonl").string() + ":5: not a JSON object"),
            std::string::npos)
      << LoadError(root_);
}

// A sweep folder: its own summary.json (beside manifest.json) is not a cell, nor is a result
// tavis was replacing (".NAME.tavis-old-PID").
TEST_F(ResultsTableTest, SweepFolderIsReadAsItsCells) {
  std::ofstream(root_ / "manifest.json") << R"({"cells": {}})";
  std::ofstream(root_ / "summary.json") << R"({"cells": [], "tables": {}})";
  WriteRecordedCell(root_ / "cells" / "a", "7", 4, 3);
  WriteRecordedCell(root_ / ".cells.tavis-old-123" / "a", "7", 4, 3);
  const std::vector<CellCounts> cells = LoadCellResults(root_);
  ASSERT_EQ(cells.size(), 1u);
  EXPECT_EQ(cells[0].source, (root_ / "cells" / "a" / "summary.json").string());
}

TEST_F(ResultsTableTest, CellsWithoutEpisodesAreListedAsSkipped) {
  WriteCell("a", "wait-then-act", "gr1t2", "id", "head", 1, 2);
  WriteCell("empty", "conditional-pick", "gr1t2", "id", "head", 0, 0);
  const ResultsTable table = BuildResultsTable(LoadCellResults(root_), "tavis-head");
  EXPECT_EQ(table.skipped_empty, std::vector<std::string>{(root_ / "empty" / "summary.json").string()});
}

}  // namespace
}  // namespace tavis::batch::report
