// `tavis sweep` end to end on a small sweep: the results do not depend on the thread count or on
// running cells at once; a sweep killed mid-cell and rerun ends with the records of an
// uninterrupted run; three shards merged equal the unsharded sweep; bad specs are named; the
// HTML report read back by headless Chromium shows summary.json's numbers.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/support/child_process.h"
#include "tool_runner.h"

namespace tavis::tools {
namespace {

using SweepCommand = TavisCommandTest;

// 4 cells (2 splits x head/fixed) of 6 episodes: a second or two.
const char* kSpec =
    "tasks: [clutter-pick-cube]\n"
    "robots: [gr1t2]\n"
    "splits: [id, ood-spatial]\n"
    "cameras: [head, fixed]\n"
    "seeds: [3]\n"
    "episodes: 6\n"
    "envs: 2\n"
    "policy:\n"
    "  name: expert\n";

const char* kFirstCell = "clutter-pick-cube_gr1t2_id_head_expert_s3";

class SweepRuns : public SweepCommand {
 protected:
  void SetUp() override {
    SweepCommand::SetUp();
    spec_ = root_ / "small.yaml";
    std::ofstream(spec_) << kSpec;
  }
  RunResult Sweep(const fs::path& out, const std::string& options = "") const {
    return Run("sweep " + Quote(spec_.string()) + " --out " + Quote(out.string()) + " --quiet " + options);
  }
  // What a run decides: every file but the manifest, each cell's summary without the fields that
  // say how it ran (time, threads, resumed episodes, the control ticks of its last run only, the
  // provenance: machine and time split), the episode times without their seconds, the report
  // without the manifest it shows.
  static std::map<std::string, std::string> Results(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& [path, text] : Snapshot(dir)) {
      const std::string name = fs::relative(path, dir).string();
      if (name == "manifest.json") continue;
      if (name.rfind("cells/", 0) == 0 && fs::path(name).filename() == "summary.json") {
        nlohmann::json summary = nlohmann::json::parse(text);
        for (const char* timing :
             {"wall_s", "control_ticks_per_s", "threads", "resumed_episodes", "control_ticks", "provenance"}) {
          summary.erase(timing);
        }
        files[name] = summary.dump(2);
      } else if (name == "report.html") {
        files[name] = std::regex_replace(text, std::regex("<pre id=\"manifest\">[^]*?</pre>"), "");
      } else if (fs::path(name).filename() == "episode_times.jsonl") {
        files[name] = TimedEpisodes(text);
      } else {
        files[name] = text;
      }
    }
    return files;
  }

  // An episode's seconds are how it ran; which episodes were timed, once each, in order, is what
  // the run decides.
  static std::string TimedEpisodes(const std::string& times) {
    std::string episodes;
    std::istringstream lines(times);
    for (std::string line; std::getline(lines, line);) {
      const nlohmann::json time = nlohmann::json::parse(line);
      EXPECT_GE(time.at("span_s").get<double>(), 0.0) << line;
      episodes += std::to_string(time.at("episode").get<int>()) + "\n";
    }
    return episodes;
  }

  static void ExpectSameResults(const fs::path& expected, const fs::path& actual) {
    const auto want = Results(expected);
    const auto got = Results(actual);
    ASSERT_FALSE(want.empty());
    for (const auto& [name, text] : want) {
      const auto it = got.find(name);
      ASSERT_NE(it, got.end()) << actual << " lacks " << name;
      EXPECT_EQ(it->second, text) << name << " differs between " << expected << " and " << actual;
    }
    EXPECT_EQ(got.size(), want.size());
  }

  fs::path spec_;
};

TEST_F(SweepRuns, ThreadsAndConcurrentCellsGiveIdenticalResults) {
  const RunResult one = Sweep(root_ / "one", "--threads 1");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(Sweep(root_ / "two", "--threads 2").exit_code, 0);  // two cells at once
  ASSERT_EQ(Sweep(root_ / "two_in_one_cell", "--threads 2 --concurrent-cells 1").exit_code, 0);
  ASSERT_EQ(Sweep(root_ / "one_thread_two_cells", "--threads 1 --concurrent-cells 2").exit_code, 0);
  ExpectSameResults(root_ / "one", root_ / "two");
  ExpectSameResults(root_ / "one", root_ / "two_in_one_cell");
  ExpectSameResults(root_ / "one", root_ / "one_thread_two_cells");
  // One line per finished cell, with the counts in quiet mode.
  EXPECT_EQ(Lines(one.out).size(), 5U) << one.out;
  EXPECT_NE(one.out.find("[cells 4/4, episodes 24/24"), std::string::npos) << one.out;
  const nlohmann::json manifest = nlohmann::json::parse(ReadText(root_ / "one" / "manifest.json"));
  EXPECT_EQ(manifest["cells"][kFirstCell], "complete");
  EXPECT_FALSE(manifest["version"].get<std::string>().empty());
  EXPECT_FALSE(manifest["machine"]["hostname"].get<std::string>().empty());
  EXPECT_EQ(manifest["spec_yaml"], kSpec);
}

TEST_F(SweepRuns, KilledMidCellAndRerunEqualsAnUninterruptedRun) {
  ASSERT_EQ(Sweep(root_ / "whole", "--threads 1").exit_code, 0);
  const fs::path out = root_ / "killed";
  const fs::path first = out / "cells" / kFirstCell / "episodes.jsonl";
  ASSERT_TRUE(KillWhenLinesAppear(
      "sweep " + Quote(spec_.string()) + " --out " + Quote(out.string()) + " --quiet --threads 1 --concurrent-cells 1",
      first, 2, SIGKILL))
      << "the sweep finished before it could be killed";
  const std::size_t kept = Lines(ReadText(first)).size();
  ASSERT_LT(kept, 6U) << "killed after the cell ended: nothing was interrupted";
  EXPECT_FALSE(fs::exists(out / "cells" / kFirstCell / "summary.json"));
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  EXPECT_EQ(nlohmann::json::parse(ReadText(out / "manifest.json"))["cells"][kFirstCell], "running");

  const RunResult rerun = Sweep(out, "--threads 2");
  ASSERT_EQ(rerun.exit_code, 0) << rerun.err;
  ExpectSameResults(root_ / "whole", out);
  // Every episode exactly once, in order, in every cell.
  for (const auto& cell : fs::directory_iterator(out / "cells")) {
    const std::vector<std::string> lines = Lines(ReadText(cell.path() / "episodes.jsonl"));
    ASSERT_EQ(lines.size(), 6U) << cell.path();
    for (std::size_t i = 0; i < lines.size(); ++i)
      EXPECT_EQ(nlohmann::json::parse(lines[i])["episode"], i) << cell.path();
  }
  EXPECT_EQ(nlohmann::json::parse(ReadText(out / "cells" / kFirstCell / "summary.json"))["resumed_episodes"], kept);

  // A complete sweep reruns nothing; a cell whose files do not match is run again.
  const RunResult again = Sweep(out);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(Lines(again.out).size(), 1U) << again.out;
  std::ofstream(out / "cells" / kFirstCell / "episodes.jsonl", std::ios::app) << "{\"episode\": 6}\n";
  const RunResult repaired = Sweep(out);
  ASSERT_EQ(repaired.exit_code, 0) << repaired.err;
  EXPECT_EQ(Lines(repaired.out).size(), 2U) << repaired.out;
  ExpectSameResults(root_ / "whole", out);
}

TEST_F(SweepRuns, ThreeShardsMergedEqualTheUnshardedSweep) {
  ASSERT_EQ(Sweep(root_ / "whole").exit_code, 0);
  std::string shards;
  for (int index = 0; index < 3; ++index) {
    const fs::path shard = root_ / ("shard" + std::to_string(index));
    const RunResult run = Sweep(shard, "--shard " + std::to_string(index) + "/3");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_FALSE(fs::exists(shard / "summary.json")) << "a shard alone is not the sweep's result";
    shards += " " + Quote(shard.string());
  }
  const RunResult merged = Run("sweep merge --out " + Quote((root_ / "merged").string()) + shards);
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  ExpectSameResults(root_ / "whole", root_ / "merged");

  // Refused: a shard missing, a shard given twice, a shard of another spec.
  const RunResult missing = Run("sweep merge --out " + Quote((root_ / "m2").string()) + " " +
                                Quote((root_ / "shard0").string()) + " " + Quote((root_ / "shard2").string()));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("missing 1/3"), std::string::npos) << missing.err;
  std::string other_spec = kSpec;
  other_spec.replace(other_spec.find("episodes: 6"), 11, "episodes: 5");
  std::ofstream(root_ / "other.yaml") << other_spec;
  ASSERT_EQ(Run("sweep " + Quote((root_ / "other.yaml").string()) + " --quiet --shard 1/3 --out " +
                Quote((root_ / "other1").string()))
                .exit_code,
            0);
  const RunResult mixed =
      Run("sweep merge --out " + Quote((root_ / "m3").string()) + " " + Quote((root_ / "shard0").string()) + " " +
          Quote((root_ / "other1").string()) + " " + Quote((root_ / "shard2").string()));
  EXPECT_EQ(mixed.exit_code, 1);
  EXPECT_NE(mixed.err.find("different sweeps"), std::string::npos) << mixed.err;
  EXPECT_NE(mixed.err.find("/spec/episodes 6 -> 5"), std::string::npos) << mixed.err;
  // And a folder of one sweep does not take another's cells.
  const RunResult reuse =
      Run("sweep " + Quote((root_ / "other.yaml").string()) + " --quiet --out " + Quote((root_ / "whole").string()));
  EXPECT_EQ(reuse.exit_code, 1);
  EXPECT_NE(reuse.err.find("holds another sweep"), std::string::npos) << reuse.err;
}

TEST_F(SweepRuns, BadSpecNamesFileKeyAndValueAndWritesNothing) {
  std::string bad = kSpec;
  bad.replace(bad.find("[head, fixed]"), 13, "[head, side]");
  std::ofstream(root_ / "bad.yaml") << bad;
  const RunResult run =
      Run("sweep " + Quote((root_ / "bad.yaml").string()) + " --out " + Quote((root_ / "out").string()));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find((root_ / "bad.yaml").string() + ": cameras[1]: unknown camera protocol 'side'"),
            std::string::npos)
      << run.err;
  EXPECT_FALSE(fs::exists(root_ / "out"));
  const RunResult shard = Sweep(root_ / "out", "--shard 3/3");
  EXPECT_EQ(shard.exit_code, 1);
  EXPECT_NE(shard.err.find("'3/3'"), std::string::npos) << shard.err;
}

// `tavis table --in SWEEP` tables the sweep's cells (its own summary.json is not a cell), with
// each rate counted here from the cell's episodes.jsonl; a copied cell is refused whatever its
// summary says about its seed, records that disagree with their summary name the cell, and a
// cell without episodes is left out with a note naming it.
TEST_F(SweepRuns, TableReadsTheSweepFolderAndChecksItsCells) {
  const fs::path sweep = root_ / "sweep";
  ASSERT_EQ(Sweep(sweep).exit_code, 0);
  const std::string table =
      "table --suite tavis-head --no-ci --in " + Quote(sweep.string()) + " --out " + Quote((root_ / "t").string());
  const RunResult run = Run(table);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // The table's row of the task (the suite's other tasks have no cells).
  const auto task_row = [this] {
    for (const std::string& line : Lines(ReadText(root_ / "t.csv"))) {
      if (line.rfind("clutter-pick-cube,", 0) == 0) return line;
    }
    return std::string("no clutter-pick-cube row");
  };
  std::string expected_row = "clutter-pick-cube";
  for (const char* column : {"id_head", "id_fixed", "ood-spatial_head", "ood-spatial_fixed"}) {
    int successes = 0;
    for (const std::string& line : Lines(ReadText(
             sweep / "cells" / ("clutter-pick-cube_gr1t2_" + std::string(column) + "_expert_s3") / "episodes.jsonl"))) {
      successes += nlohmann::json::parse(line)["success"].get<bool>() ? 1 : 0;
    }
    char rate[16];
    std::snprintf(rate, sizeof rate, ",%.1f", 100.0 * successes / 6);
    expected_row += rate;
  }
  EXPECT_EQ(task_row(), expected_row);

  const fs::path cell = sweep / "cells" / kFirstCell, copy = sweep / "cells" / "copy";
  fs::copy(cell, copy, fs::copy_options::recursive);
  nlohmann::json summary = nlohmann::json::parse(ReadText(copy / "summary.json"));
  for (const nlohmann::json& seed : {nlohmann::json("3"), nlohmann::json()}) {
    seed.is_null() ? static_cast<void>(summary.erase("seed")) : static_cast<void>(summary["seed"] = seed);
    std::ofstream(copy / "summary.json") << summary.dump();
    const RunResult copied = Run(table);
    EXPECT_EQ(copied.exit_code, 1) << "seed " << seed;
    EXPECT_NE(copied.err.find((cell / "summary.json").string() + " and " + (copy / "summary.json").string()),
              std::string::npos)
        << copied.err;
  }
  summary["n_episodes"] = 0;
  summary["n_successful"] = 0;
  std::ofstream(copy / "summary.json") << summary.dump();
  std::ofstream(copy / "episodes.jsonl", std::ios::trunc).close();
  const RunResult empty = Run(table);
  EXPECT_EQ(empty.exit_code, 0) << empty.err;
  EXPECT_NE(empty.err.find("note: " + (copy / "summary.json").string() +
                           " holds no episodes (n_episodes 0): left out of the table"),
            std::string::npos)
      << empty.err;
  EXPECT_EQ(task_row(), expected_row);

  fs::remove_all(copy);
  const std::string first_record = Lines(ReadText(cell / "episodes.jsonl"))[0];
  std::ofstream(cell / "episodes.jsonl", std::ios::app) << first_record << "\n";
  const RunResult doubled = Run(table);
  EXPECT_EQ(doubled.exit_code, 1);
  EXPECT_NE(doubled.err.find("cell " + cell.string() + ": episodes.jsonl holds 7 episodes"), std::string::npos)
      << doubled.err;
}

TEST_F(SweepRuns, HtmlReportInHeadlessChromiumShowsTheJsonNumbers) {
  ASSERT_EQ(Sweep(root_ / "out").exit_code, 0);
  fs::create_directories(root_ / "chromium");
  testing::ChildProcess check(testing::kDebianPython,
                              {TAVIS_TEST_DATA_DIR "/sweep/check_report_in_chromium.py", (root_ / "out").string(),
                               (root_ / "chromium").string()},
                              "needs Debian's chromium and python3-av (.ci/install-deps)");
  const std::string report = check.ReadAllOutput(std::chrono::seconds(180));
  EXPECT_NE(report.find("report ok: 4 cells"), std::string::npos) << report;
}

// The expert on the two cue tasks under head and fixed: the fixed funnels show the stages the
// expert reached (the gaze stage does not apply to a zeroed neck), the report's funnel puts head
// beside fixed, and every table of the report and of `tavis table` (the gaze and anchor tables too), read value by
// value under its heading, holds summary.json's numbers.
TEST_F(SweepCommand, HeadAndFixedFunnelsOfTheCueTasksSitSideBySide) {
  // One YAML flow mapping: the two cue tasks, head and fixed, 3 expert episodes a cell.
  std::ofstream(root_ / "cue.yaml") << "{tasks: [conditional-pick, wait-then-act], robots: [gr1t2], splits: [id], "
                                       "cameras: [head, fixed], seeds: [0], episodes: 3, envs: 3, "
                                       "policy: {name: expert}}\n";
  const fs::path out = root_ / "out";
  const RunResult sweep =
      Run("sweep " + Quote((root_ / "cue.yaml").string()) + " --out " + Quote(out.string()) + " --quiet");
  ASSERT_EQ(sweep.exit_code, 0) << sweep.err;
  const nlohmann::json summary = nlohmann::json::parse(ReadText(out / "summary.json"));
  ASSERT_EQ(summary["stages"].size(), 4U);
  for (const nlohmann::json& row : summary["stages"]) {
    SCOPED_TRACE(row.dump());
    const bool fixed = row["camera"] == "fixed";
    EXPECT_EQ(row["stages"][0]["stage"], "cue_fixated");
    EXPECT_EQ(row["stages"][0]["applies"].get<bool>(), !fixed);
    for (std::size_t s = fixed ? 1 : 0; s < row["stages"].size(); ++s) EXPECT_EQ(row["stages"][s]["reached"], 3);
  }
  const std::string funnel = ReadText(out / "tables" / "stage_funnel.md");
  EXPECT_NE(funnel.find("| policy | task | robot | split | stage | head % | head alone % | fixed % | fixed alone % |"),
            std::string::npos)
      << funnel;
  EXPECT_NE(funnel.find("| expert | wait-then-act | gr1t2 | id | cue_fixated | 100.0 | 100.0 | n/a | n/a |"),
            std::string::npos)
      << funnel;
  EXPECT_NE(funnel.find("| expert | conditional-pick | gr1t2 | id | target_lifted | 100.0 | 100.0 | 100.0 | 100.0 |"),
            std::string::npos)
      << funnel;
  const RunResult table = Run("table --in " + Quote((out / "cells").string()) + " --suite tavis-head --out " +
                              Quote((root_ / "head_table").string()));
  ASSERT_EQ(table.exit_code, 0) << table.err;
  fs::create_directories(root_ / "chromium");
  testing::ChildProcess check(testing::kDebianPython,
                              {TAVIS_TEST_DATA_DIR "/sweep/check_report_in_chromium.py", out.string(),
                               (root_ / "chromium").string(), "--table", (root_ / "head_table.md").string(), "expert"},
                              "needs Debian's chromium and python3-av (.ci/install-deps)");
  const std::string report = check.ReadAllOutput(std::chrono::seconds(180));
  EXPECT_NE(report.find("report ok: 4 cells"), std::string::npos) << report;
  EXPECT_NE(report.find("tavis table's"), std::string::npos) << report;
  // The gaze and anchor tables (a row per cell, three anchors each) were among the values read.
  EXPECT_NE(report.find("(" + std::to_string(4 * 12 + 12 * 14) + " of them the gaze and anchor tables')"),
            std::string::npos)
      << report;
}

}  // namespace
}  // namespace tavis::tools
