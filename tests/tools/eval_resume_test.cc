// `tavis eval` keeps what it has done: records stream to episodes.jsonl as episodes end, so a cell
// killed mid-way keeps its complete episodes, refuses to be overwritten by accident, and --resume
// finishes it with records byte-identical to an uninterrupted run.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include "tool_runner.h"

namespace tavis::tools {
namespace {

using EvalResume = TavisCommandTest;

class EvalInterrupted : public EvalResume, public ::testing::WithParamInterface<int> {};

TEST_P(EvalInterrupted, KeepsCompleteEpisodesAndResumesToTheSameRecords) {
  const std::string cell = "eval --task clutter-pick-cube --episodes 10 --envs 2 --quiet --seed 4";
  const fs::path whole = root_ / "whole";
  ASSERT_EQ(Run(cell + " --out " + Quote(whole.string())).exit_code, 0);

  const fs::path out = root_ / "cell";
  ASSERT_TRUE(KillWhenLinesAppear(cell + " --out " + Quote(out.string()), out / "episodes.jsonl", 3, GetParam()))
      << "the cell finished before it could be interrupted";
  const std::vector<std::string> kept = Lines(ReadText(out / "episodes.jsonl"));
  const std::vector<std::string> expected = Lines(ReadText(whole / "episodes.jsonl"));
  ASSERT_GE(kept.size(), 3U);
  ASSERT_LT(kept.size(), expected.size());
  for (std::size_t i = 0; i < kept.size(); ++i) EXPECT_EQ(kept[i], expected[i]) << "line " << i;
  EXPECT_FALSE(fs::exists(out / "summary.json")) << "an interrupted cell must not look complete";

  const RunResult again = Run(cell + " --out " + Quote(out.string()));
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.err.find("--resume"), std::string::npos) << again.err;
  const RunResult other = Run("eval --task clutter-pick-cube --episodes 10 --envs 2 --quiet --seed 5 --resume --out " +
                              Quote(out.string()));
  EXPECT_EQ(other.exit_code, 1);
  EXPECT_NE(other.err.find("seed 4 -> 5"), std::string::npos) << other.err;

  const RunResult resumed = Run(cell + " --resume --out " + Quote(out.string()));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(ReadText(out / "episodes.jsonl"), ReadText(whole / "episodes.jsonl"));
  EXPECT_NE(ReadText(out / "summary.json").find("\"resumed_episodes\": " + std::to_string(kept.size())),
            std::string::npos);
  const RunResult complete = Run(cell + " --resume --out " + Quote(out.string()));
  EXPECT_EQ(complete.exit_code, 1);
  EXPECT_NE(complete.err.find("is complete"), std::string::npos) << complete.err;
}

INSTANTIATE_TEST_SUITE_P(Signals, EvalInterrupted, ::testing::Values(SIGINT, SIGKILL),
                         [](const ::testing::TestParamInfo<int>& signal) {
                           return signal.param == SIGINT ? "SIGINT" : "SIGKILL";
                         });

// A damaged cell.json is named as such, with what is wrong and without nlohmann's exception id;
// the records are kept.
TEST_F(EvalResume, DamagedCellFileIsNamedAndTheRecordsAreKept) {
  const std::string cell =
      "eval --task clutter-pick-cube --episodes 2 --envs 2 --quiet --seed 4 --out " + Quote((root_ / "cell").string());
  ASSERT_EQ(Run(cell).exit_code, 0);
  fs::remove(root_ / "cell" / "summary.json");
  const std::string records = ReadText(root_ / "cell" / "episodes.jsonl");
  const std::string settings = ReadText(root_ / "cell" / "cell.json");
  std::ofstream(root_ / "cell" / "cell.json") << settings.substr(0, settings.size() / 2);
  const RunResult resumed = Run(cell + " --resume");
  EXPECT_EQ(resumed.exit_code, 1);
  EXPECT_NE(
      resumed.err.find((root_ / "cell" / "cell.json").string() + ": damaged cell file, not valid JSON: parse error"),
      std::string::npos)
      << resumed.err;
  EXPECT_EQ(resumed.err.find("json.exception"), std::string::npos) << resumed.err;
  EXPECT_EQ(ReadText(root_ / "cell" / "episodes.jsonl"), records);
}

TEST_F(EvalResume, OverwriteReplacesAnotherRunsResults) {
  const fs::path out = root_ / "cell";
  const std::string cell = "eval --task clutter-pick-cube --episodes 2 --envs 2 --quiet --out " + Quote(out.string());
  ASSERT_EQ(Run(cell + " --seed 0").exit_code, 0);
  fs::remove(out / "summary.json");
  ASSERT_EQ(Run(cell + " --seed 1").exit_code, 1) << "a second run must not mix its records into the first's";
  ASSERT_EQ(Run(cell + " --seed 1 --overwrite").exit_code, 0);
  EXPECT_NE(ReadText(out / "episodes.jsonl").find("\"seed\":1"), std::string::npos);
  EXPECT_EQ(ReadText(out / "episodes.jsonl").find("\"seed\":0"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

// A resume that leaves out a setting the cell was started with (here --perturb, recorded only when
// given) is another run: refused naming the setting, and nothing is written (it once finished a
// runtime:move cell with unperturbed episodes while cell.json still named the level).
TEST_F(EvalResume, ResumeThatLeavesOutThePerturbationIsRefusedNamingIt) {
  const fs::path out = root_ / "cell";
  const std::string cell = "eval --task clutter-pick-cube --episodes 2 --envs 2 --quiet --out " + Quote(out.string());
  ASSERT_EQ(Run(cell + " --perturb runtime:move").exit_code, 0);
  fs::remove(out / "summary.json");  // as an interrupted cell has none
  const auto before = Snapshot(out);
  const RunResult resumed = Run(cell + " --resume");
  EXPECT_EQ(resumed.exit_code, 1);
  EXPECT_NE(resumed.err.find("with other settings: perturbations [{\"axis\":\"runtime\",\"level\":\"move\""),
            std::string::npos)
      << resumed.err;
  EXPECT_NE(resumed.err.find("}] -> unset"), std::string::npos) << resumed.err;
  EXPECT_EQ(Snapshot(out), before) << "a refused resume wrote into the cell";
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}

// The same for --episode I (recorded as episode_start when not 0): a resume without it once filled
// an `--episode 7` cell with episode 0.
TEST_F(EvalResume, ResumeThatLeavesOutTheEpisodeIsRefusedNamingIt) {
  const fs::path out = root_ / "cell";
  const std::string cell = "eval --task clutter-pick-cube --envs 1 --quiet --out " + Quote(out.string());
  ASSERT_EQ(Run(cell + " --episode 7").exit_code, 0);
  fs::remove(out / "summary.json");
  std::ofstream(out / "episodes.jsonl", std::ios::trunc).close();  // interrupted before its one episode
  const auto before = Snapshot(out);
  const RunResult resumed = Run(cell + " --episodes 1 --resume");
  EXPECT_EQ(resumed.exit_code, 1);
  EXPECT_NE(resumed.err.find("with other settings: episode_start 7 -> unset"), std::string::npos) << resumed.err;
  EXPECT_EQ(Snapshot(out), before) << "a refused resume wrote into the cell";
  // With the episode it resumes, and the record is episode 7's.
  const RunResult same = Run(cell + " --episode 7 --resume");
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_NE(ReadText(out / "episodes.jsonl").find("\"episode\":7,"), std::string::npos)
      << ReadText(out / "episodes.jsonl");
}

}  // namespace
}  // namespace tavis::tools
