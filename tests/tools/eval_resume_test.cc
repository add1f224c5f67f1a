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

// #46 item 3: --resume cut and appended to a file outside --out through a symlinked episodes.jsonl.
TEST_F(EvalResume, ResumeRefusesARecordFileThatIsALinkAndLeavesWhatItPointsToAlone) {
  const fs::path out = root_ / "cell";
  const std::string cell =
      "eval --task clutter-pick-cube --episodes 3 --envs 2 --quiet --seed 4 --out " + Quote(out.string());
  ASSERT_EQ(Run(cell).exit_code, 0);
  fs::remove(out / "summary.json");
  const fs::path outside = root_ / "outside.txt";
  std::ofstream(outside) << "a user's file, not a record\n";
  fs::remove(out / "episodes.jsonl");
  fs::create_symlink(outside, out / "episodes.jsonl");
  const RunResult resumed = Run(cell + " --resume");
  EXPECT_EQ(resumed.exit_code, 1);
  EXPECT_NE(resumed.err.find((out / "episodes.jsonl").string() + " is a symbolic link"), std::string::npos)
      << resumed.err;
  EXPECT_EQ(ReadText(outside), "a user's file, not a record\n");
}

// #46 item 6: an episode recorded before its video was finished was never filmed on resume, and
// the resume exited 0. A video takes its name once whole; one missing or unfinished is filmed
// again (the episode reruns, to the same record).
class EvalVideoResume : public EvalResume, public ::testing::WithParamInterface<const char*> {};

TEST_P(EvalVideoResume, AnEpisodeWithoutItsFinishedVideoIsFilmedAgain) {
  const std::string format = GetParam();
  const bool mp4 = format == "mp4";
  const std::string cell =
      "eval --task clutter-pick-cube --episodes 4 --envs 2 --quiet --seed 4 --videos 3 "
      "--video-size 64x48 --video-format " +
      format;
  const fs::path whole = root_ / "whole";
  ASSERT_EQ(Run(cell + " --out " + Quote(whole.string())).exit_code, 0);
  const fs::path out = root_ / "cell";
  ASSERT_EQ(Run(cell + " --out " + Quote(out.string())).exit_code, 0);
  // As a kill leaves it: episode 1's video never written, episode 2's cut short under its partial name.
  fs::remove(out / "summary.json");
  const std::string one = mp4 ? "episode_1.mp4" : "episode_1";
  const std::string two = mp4 ? "episode_2.mp4" : "episode_2";
  fs::remove_all(out / "videos" / one);
  fs::rename(out / "videos" / two, out / "videos" / (two + ".partial"));
  const RunResult resumed = Run(cell + " --resume --out " + Quote(out.string()));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("episode 1 of " + out.string() + " has no finished video"), std::string::npos)
      << resumed.err;
  EXPECT_EQ(ReadText(out / "episodes.jsonl"), ReadText(whole / "episodes.jsonl"));
  for (const std::string& name : {std::string(mp4 ? "episode_0.mp4" : "episode_0"), one, two}) {
    const fs::path video = out / "videos" / name;
    ASSERT_TRUE(mp4 ? fs::is_regular_file(video) : fs::is_directory(video)) << name << " is not filmed";
    if (mp4) {
      EXPECT_EQ(ReadText(out / "videos" / name), ReadText(whole / "videos" / name)) << name;
    } else {
      EXPECT_EQ(Snapshot(out / "videos" / name).size(), Snapshot(whole / "videos" / name).size()) << name;
    }
  }
  EXPECT_FALSE(fs::exists(out / "videos" / (two + ".partial")));
}

INSTANTIATE_TEST_SUITE_P(Formats, EvalVideoResume, ::testing::Values("mp4", "png"));

// #46 item 14: Ctrl-C printed nothing about what was kept or how to go on. It now says how many
// episodes are kept where and the command that finishes the cell, which does.
TEST_F(EvalResume, CtrlCSaysWhatWasKeptAndTheCommandThatFinishesTheCell) {
  const std::string cell = "eval --task clutter-pick-cube --episodes 10 --envs 2 --quiet --seed 4";
  const fs::path whole = root_ / "whole";
  ASSERT_EQ(Run(cell + " --out " + Quote(whole.string())).exit_code, 0);
  const fs::path out = root_ / "cell";
  const fs::path err = root_ / "interrupted.txt";
  const pid_t child = fork();
  if (child == 0) {
    const std::string command = "exec " + Quote(TAVIS_BINARY) + " " + cell + " --out " + Quote(out.string()) +
                                " --overwrite >/dev/null 2>" + Quote(err.string());
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (Lines(ReadText(out / "episodes.jsonl")).size() < 3 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  kill(child, SIGINT);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << "ended otherwise: " << status;  // $? 130
  const std::string said = ReadText(err);
  const std::string kept = " kept in " + out.string() + "; to finish the cell: ";
  const std::size_t at = said.find(kept);
  ASSERT_NE(at, std::string::npos) << said;
  EXPECT_EQ(said.rfind("interrupted: ", at), said.find("interrupted: ")) << said;
  std::string command = said.substr(at + kept.size());
  while (!command.empty() && command.back() == '\n') command.pop_back();
  EXPECT_EQ(command, std::string(TAVIS_BINARY) + " " + cell + " --out " + out.string() + " --resume");
  ASSERT_EQ(std::system((command + " >/dev/null 2>&1").c_str()), 0) << command;
  EXPECT_EQ(ReadText(out / "episodes.jsonl"), ReadText(whole / "episodes.jsonl"));
}

}  // namespace
}  // namespace tavis::tools
