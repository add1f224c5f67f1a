// `tavis demos` with the rest of the program: the GALT table of a recorded dataset equals the one
// `tavis eval` reports for the same episodes, and a recording killed mid-way and resumed ends
// byte-identical to an uninterrupted one.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "tool_runner.h"

namespace tavis::tools {
namespace {

using DemosPipeline = TavisCommandTest;

nlohmann::json ReadJson(const fs::path& path) { return nlohmann::json::parse(ReadText(path)); }

TEST_F(DemosPipeline, GaltTableOfTheDatasetEqualsTheCellsForTheSameEpisodes) {
  const std::string episodes = "--task clutter-pick-cube --robot gr1t2 --episodes 6 --seed 3";
  const RunResult cell = Run("eval " + episodes + " --quiet --out " + Quote((root_ / "cell").string()));
  ASSERT_EQ(cell.exit_code, 0) << cell.err;
  const nlohmann::json summary = ReadJson(root_ / "cell" / "summary.json");
  ASSERT_EQ(summary["n_successful"], 6) << "the comparison needs every episode in the dataset";

  const RunResult demos = Run("demos " + episodes + " --cameras '' --quiet --out " + Quote((root_ / "dataset").string()));
  ASSERT_EQ(demos.exit_code, 0) << demos.err;
  const RunResult galt = Run("galt --dataset " + Quote((root_ / "dataset").string()) + " --table-only --json-out " +
                             Quote((root_ / "table.json").string()));
  ASSERT_EQ(galt.exit_code, 0) << galt.err;
  const nlohmann::json table = ReadJson(root_ / "table.json");
  ASSERT_EQ(table["rows"].size(), 2U);
  // 60 Hz: every control tick's action, as the cell's GALT; 20 Hz: every third, as its policy-rate GALT.
  for (const auto& [row, cell_galt] : {std::pair{table["rows"][0], summary["galt"]}, std::pair{table["rows"][1], summary["galt_policy_rate"]}}) {
    EXPECT_EQ(row["n_episodes"], cell_galt["n_episodes"]);
    EXPECT_EQ(row["n_valid"], cell_galt["n_valid"]);
    EXPECT_EQ(row["mean_s"], cell_galt["mean_s"]) << row.dump();
    EXPECT_EQ(row["median_s"], cell_galt["median_s"]) << row.dump();
  }
}

TEST_F(DemosPipeline, KilledAndResumedRecordingEqualsAnUninterruptedOne) {
  const std::string args = "demos --task clutter-pick-cube --episodes 16 --fps 20 --image-size 64x48 --cameras head,left_wrist --quiet";
  ASSERT_EQ(Run(args + " --out " + Quote((root_ / "whole").string())).exit_code, 0);

  // Killed once the spool holds a few kept episodes (bounded: the whole run takes seconds).
  const fs::path out = root_ / "resumed";
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const std::string command = Quote(TAVIS_BINARY) + " " + args + " --threads 2 --out " + Quote(out.string()) + " >/dev/null 2>&1";
    execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(out / ".tavis_spool" / "episode_000003" / "episode.json") && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the recording finished before it could be killed";
  EXPECT_TRUE(fs::exists(out / "INCOMPLETE"));
  EXPECT_FALSE(fs::exists(out / "meta" / "info.json")) << "an interrupted dataset must not look finished";

  const RunResult refused = Run(args + " --out " + Quote(out.string()));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("--resume"), std::string::npos) << refused.err;
  const RunResult other = Run(args + " --seed 9 --resume --out " + Quote(out.string()));
  EXPECT_EQ(other.exit_code, 1);
  EXPECT_NE(other.err.find("seed 0 -> 9"), std::string::npos) << other.err;

  const RunResult resumed = Run(args + " --threads 1 --resume --out " + Quote(out.string()));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_GE(ReadJson(out / "tavis_demos.json")["resumed_episodes"].get<int>(), 4);
  EXPECT_FALSE(fs::exists(out / "INCOMPLETE"));
  EXPECT_FALSE(fs::exists(out / ".tavis_spool"));
  std::map<std::string, std::string> whole, again;
  for (const auto& [path, text] : Snapshot(root_ / "whole")) {
    if (path.find("tavis_demos.json") == std::string::npos) whole[path.substr((root_ / "whole").string().size())] = text;
  }
  for (const auto& [path, text] : Snapshot(out)) {
    if (path.find("tavis_demos.json") == std::string::npos) again[path.substr(out.string().size())] = text;
  }
  EXPECT_EQ(whole.size(), again.size());
  for (const auto& [path, text] : whole) EXPECT_TRUE(again.count(path) && again[path] == text) << path << " differs";
}

}  // namespace
}  // namespace tavis::tools
