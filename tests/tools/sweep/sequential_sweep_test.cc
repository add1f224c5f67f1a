// The sequential paired test through the real program: the expert against hold stops within 20
// pairs and says so in its cells, summary, table and report; its episodes are the episodes a
// sweep without the test runs; an interrupted run resumed, and the sweep run as two shards and
// merged, stop at the same n with the same files.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/child_process.h"
#include "tests/tools/tool_runner.h"

namespace tavis::tools::sweep {
namespace {

// Two seeds, each an expert cell and a hold cell under head: two groups of one pair each.
std::string Spec(int episodes, bool sequential) {
  return "tasks: [clutter-pick-cube]\n"
         "robots: [gr1t2]\n"
         "splits: [id]\n"
         "cameras: [head]\n"
         "seeds: [0, 1]\n"
         "episodes: " +
         std::to_string(episodes) +
         "\n"
         "envs: 4\n"
         "policies:\n"
         "  - {label: expert, name: expert}\n"
         "  - {label: hold, name: hold}\n" +
         (sequential ? "sequential: {alpha: 0.05, block: 4, pairs: [], policies: [[expert, hold]]}\n" : "");
}

const std::vector<std::string> kCells = {
    "clutter-pick-cube_gr1t2_id_head_expert_s0", "clutter-pick-cube_gr1t2_id_head_expert_s1",
    "clutter-pick-cube_gr1t2_id_head_hold_s0", "clutter-pick-cube_gr1t2_id_head_hold_s1"};

class SequentialSweep : public TavisCommandTest {
 protected:
  fs::path WriteSpec(const std::string& name, const std::string& text) const {
    std::ofstream(root_ / name) << text;
    return root_ / name;
  }
  RunResult Sweep(const fs::path& spec, const fs::path& out, const std::string& options = "") const {
    return Run("sweep " + Quote(spec.string()) + " --out " + Quote(out.string()) + " --quiet --threads 2 " + options);
  }
  static nlohmann::json Json(const fs::path& path) { return nlohmann::json::parse(ReadText(path)); }
  // The files a sweep's result is: each cell's records and stop, the summary, the tables.
  static std::map<std::string, std::string> Results(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const std::string& cell : kCells) {
      for (const char* name : {"episodes.jsonl", "sequential.json", "cell.json"})
        files[cell + "/" + name] = ReadText(dir / "cells" / cell / name);
    }
    files["summary.json"] = ReadText(dir / "summary.json");
    for (const auto& entry : fs::directory_iterator(dir / "tables"))
      files["tables/" + entry.path().filename().string()] = ReadText(entry.path());
    return files;
  }
};

TEST_F(SequentialSweep, ExpertAgainstHoldStopsEarlyTheSameWayResumedShardedOrNot) {
  constexpr int kCap = 40;
  const fs::path spec = WriteSpec("sequential.yaml", Spec(kCap, true));
  const fs::path out = root_ / "sweep";
  const RunResult run = Sweep(spec, out);
  ASSERT_EQ(run.exit_code, 0) << run.err;

  // Each cell says where and why it stopped; both cells of a pair at the same n, within 20 pairs.
  int64_t stopped_at = -1;
  for (const std::string& cell : kCells) {
    const nlohmann::json stop = Json(out / "cells" / cell / "sequential.json");
    EXPECT_EQ(stop["why"], "decided") << cell;
    EXPECT_EQ(stop["cap"], kCap);
    EXPECT_LE(stop["stopped_at"].get<int64_t>(), 20) << cell;
    EXPECT_EQ(stop["stopped_at"].get<int64_t>() % 4, 0) << "stops at a look: " << cell;
    ASSERT_EQ(stop["pairs"].size(), 1u);
    EXPECT_EQ(stop["pairs"][0]["outcome"], "first_better") << cell;
    EXPECT_EQ(Lines(ReadText(out / "cells" / cell / "episodes.jsonl")).size(), stop["stopped_at"].get<std::size_t>());
    EXPECT_EQ(Json(out / "cells" / cell / "summary.json")["n_episodes"], stop["stopped_at"]);
    if (cell.find("_s0") != std::string::npos) stopped_at = stop["stopped_at"];
  }
  ASSERT_GT(stopped_at, 0);
  const nlohmann::json summary = Json(out / "summary.json");
  const nlohmann::json& section = summary["sequential"];
  ASSERT_EQ(section["pairs"].size(), 2u);
  for (const nlohmann::json& pair : section["pairs"]) {
    EXPECT_EQ(pair["kind"], "policy");
    EXPECT_EQ(pair["first_label"], "expert");
    EXPECT_EQ(pair["second_label"], "hold");
    EXPECT_EQ(pair["outcome"], "first_better");
    EXPECT_TRUE(pair["stopped_early"].get<bool>());
    EXPECT_EQ(pair["decided_at"], pair["stopped_at"]);
    EXPECT_GE(pair["e_value"].get<double>(), 20.0);
    EXPECT_EQ(pair["episodes_saved"], 2 * (kCap - pair["stopped_at"].get<int64_t>()));
  }
  EXPECT_EQ(section["cells_stopped_early"], 4);
  EXPECT_EQ(section["episodes_cap"], 4 * kCap);
  EXPECT_GT(section["episodes_saved"].get<int64_t>(), 0);
  const std::string table = ReadText(out / "tables" / "sequential_pairs.md");
  EXPECT_NE(table.find("| policy | expert head | hold head |"), std::string::npos) << table;
  EXPECT_NE(table.find("expert head better"), std::string::npos) << table;
  EXPECT_NE(ReadText(out / "report.html").find("<p id=\"sequential\">2 of 2 pairs stopped before the cap of 40"),
            std::string::npos);
  // The report read in Chromium as a person reads it: every table, sequential_pairs among them,
  // each value under its heading equal to summary.json's.
  fs::create_directories(root_ / "chromium");
  testing::ChildProcess check(
      testing::kDebianPython,
      {TAVIS_TEST_DATA_DIR "/sweep/check_report_in_chromium.py", out.string(), (root_ / "chromium").string()},
      "needs Debian's chromium and python3-av (.ci/install-deps)");
  const std::string report = check.ReadAllOutput(std::chrono::seconds(180));
  EXPECT_NE(report.find("report ok: 4 cells"), std::string::npos) << report;

  // Episode k is the episode a sweep without the test runs: the same record, byte for byte.
  const fs::path plain = root_ / "plain";
  ASSERT_EQ(Sweep(WriteSpec("plain.yaml", Spec(static_cast<int>(stopped_at), false)), plain).exit_code, 0);
  for (const std::string& cell : {kCells[0], kCells[2]}) {
    EXPECT_EQ(ReadText(plain / "cells" / cell / "episodes.jsonl"), ReadText(out / "cells" / cell / "episodes.jsonl"))
        << cell;
    EXPECT_FALSE(fs::exists(plain / "cells" / cell / "sequential.json"));
  }
  EXPECT_FALSE(Json(plain / "summary.json").contains("sequential"));

  // Interrupted mid-block (the hold cell of seed 0 paused at 5 episodes, its stop not yet
  // written) and resumed: the same files.
  const fs::path resumed = root_ / "resumed";
  fs::copy(out, resumed, fs::copy_options::recursive);
  const fs::path hold = resumed / "cells" / kCells[2];
  fs::remove(hold / "summary.json");
  fs::remove(hold / "sequential.json");
  fs::remove(resumed / "summary.json");
  const std::vector<std::string> lines = Lines(ReadText(hold / "episodes.jsonl"));
  ASSERT_GT(lines.size(), 5u);
  std::string kept;
  for (std::size_t i = 0; i < 5; ++i) kept += lines[i] + "\n";
  std::ofstream(hold / "episodes.jsonl", std::ios::trunc) << kept;
  const RunResult again = Sweep(spec, resumed);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(Results(resumed), Results(out));

  // Two shards (a group each) merged: the same files.
  ASSERT_EQ(Sweep(spec, root_ / "shard0", "--shard 0/2").exit_code, 0);
  ASSERT_EQ(Sweep(spec, root_ / "shard1", "--shard 1/2").exit_code, 0);
  EXPECT_TRUE(fs::exists(root_ / "shard0" / "cells" / kCells[2])) << "a group runs in the shard of its first cell";
  const RunResult merged = Run("sweep merge --out " + Quote((root_ / "merged").string()) + " " +
                               Quote((root_ / "shard0").string()) + " " + Quote((root_ / "shard1").string()));
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  EXPECT_EQ(Results(root_ / "merged"), Results(out));
}

// A stopped cell whose records disagree with its pair's test (a folder mixed from other runs) is
// refused when the results are written, naming the cell.
TEST_F(SequentialSweep, ResultsRefuseAStopTheRecordsDoNotGive) {
  const fs::path spec = WriteSpec("sequential.yaml", Spec(12, true));
  const fs::path out = root_ / "sweep";
  ASSERT_EQ(Sweep(spec, out).exit_code, 0);
  // The expert cell of seed 1 claims to have stopped at 4, one look early.
  const fs::path cell = out / "cells" / kCells[1];
  nlohmann::json stop = Json(cell / "sequential.json");
  stop["stopped_at"] = 4;
  std::ofstream(cell / "sequential.json", std::ios::trunc) << stop.dump(2);
  const std::vector<std::string> lines = Lines(ReadText(cell / "episodes.jsonl"));
  ASSERT_GE(lines.size(), 4u);
  std::string first_four;
  int successes = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    first_four += lines[i] + "\n";
    successes += nlohmann::json::parse(lines[i])["success"].get<bool>() ? 1 : 0;
  }
  std::ofstream(cell / "episodes.jsonl", std::ios::trunc) << first_four;
  nlohmann::json summary = Json(cell / "summary.json");
  summary["n_episodes"] = 4;
  summary["n_successful"] = successes;  // a complete cell of 4 episodes, as far as its own files go
  std::ofstream(cell / "summary.json", std::ios::trunc) << summary.dump(2);
  fs::remove(out / "summary.json");
  const RunResult rerun = Sweep(spec, out);
  EXPECT_NE(rerun.exit_code, 0);
  EXPECT_NE(rerun.err.find("cell " + kCells[1] + " holds 4 episodes where the sequential test over its pairs stops at"),
            std::string::npos)
      << rerun.err;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}

}  // namespace
}  // namespace tavis::tools::sweep
