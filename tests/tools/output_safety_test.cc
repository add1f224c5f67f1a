// Results are never lost, through the real program: --overwrite replaces only a folder tavis
// wrote (never a user's files, the working directory, a plain file or the home folder) and keeps
// the old result when the new run fails; one writer per output folder (the second is refused
// naming the first, a dead writer's lock is taken over); sweeps and merges write only into their
// own folders; a resume with a changed robot file is refused naming the change.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "batch/output/output_folder.h"
#include "tool_runner.h"

namespace tavis::tools {
namespace {

const std::string kCell = "eval --task clutter-pick-cube --episodes 2 --envs 2 --quiet";
const std::string kDemos = "demos --quiet --episodes 1 --envs 1 --fps 20 --image-size 64x48 --cameras head";

class OutputSafety : public TavisCommandTest {
 protected:
  // Runs `tavis ARGS` from inside `dir`, with `env` ("NAME=value ...") before it.
  RunResult RunIn(const fs::path& dir, const std::string& args, const std::string& env = "") const {
    const fs::path out = root_.string() + ".stdout";
    const fs::path err = root_.string() + ".stderr";
    const std::string command = "cd " + Quote(dir.string()) + " && " + env + " " + Quote(TAVIS_BINARY) + " " + args +
                                " >" + Quote(out.string()) + " 2>" + Quote(err.string());
    const int status = std::system(command.c_str());
    RunResult result;
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    result.out = ReadText(out);
    result.err = ReadText(err);
    fs::remove(out);
    fs::remove(err);
    return result;
  }

  // Every file and folder under root_ (names only).
  std::set<std::string> Paths() const {
    std::set<std::string> paths;
    for (const auto& entry : fs::recursive_directory_iterator(root_)) paths.insert(entry.path().string());
    return paths;
  }

  // Expects `run` refused (exit 1) naming `named`, with nothing under root_ changed.
  void ExpectRefusedKeepingEverything(const RunResult& run, const std::string& named,
                                      const std::map<std::string, std::string>& files,
                                      const std::set<std::string>& paths, const std::string& what) {
    EXPECT_EQ(run.exit_code, 1) << what << "\n" << run.out << run.err;
    EXPECT_NE(run.err.find(named), std::string::npos) << what << ": wanted '" << named << "' in: " << run.err;
    EXPECT_EQ(Snapshot(root_), files) << what << ": changed files";
    EXPECT_EQ(Paths(), paths) << what << ": created or removed files";
  }
};

// Defect 1: `--out mydata --overwrite` deleted the user's mydata/thesis.txt.
TEST_F(OutputSafety, OverwriteRefusesAFolderHoldingAForeignFileAndKeepsIt) {
  const fs::path mine = root_ / "mydata";
  fs::create_directories(mine / "notes");
  std::ofstream(mine / "thesis.txt") << "three years of work";
  std::ofstream(mine / "notes" / "a.txt") << "a";
  const auto files = Snapshot(root_);
  const auto paths = Paths();
  ExpectRefusedKeepingEverything(RunIn(root_, kCell + " --overwrite --out mydata"), "thesis.txt", files, paths, "eval");
  ExpectRefusedKeepingEverything(RunIn(root_, kDemos + " --overwrite --out mydata"), "thesis.txt", files, paths,
                                 "demos");

  // A real cell with a user's file added is not tavis's alone either.
  const fs::path cell = root_ / "cell";
  ASSERT_EQ(Run(kCell + " --seed 0 --out " + Quote(cell.string())).exit_code, 0);
  std::ofstream(cell / "analysis.ipynb") << "{}";
  const auto with_cell = Snapshot(root_);
  const auto with_cell_paths = Paths();
  ExpectRefusedKeepingEverything(Run(kCell + " --seed 1 --overwrite --out " + Quote(cell.string())), "analysis.ipynb",
                                 with_cell, with_cell_paths, "eval over a cell with a user's file");
}

// Defect 1: `--out .` emptied the working directory, `--out ..` its parent.
TEST_F(OutputSafety, OverwriteRefusesTheWorkingDirectoryItsParentsAndTheHomeFolder) {
  const fs::path work = root_ / "scratch" / "work";
  fs::create_directories(work);
  std::ofstream(work / "a.txt") << "a";
  std::ofstream(root_ / "scratch" / "b.txt") << "b";
  const auto files = Snapshot(root_);
  const auto paths = Paths();
  for (const std::string& command : std::vector<std::string>{kCell, kDemos}) {
    for (const std::string& out : std::vector<std::string>{".", "..", "../..", "/", work.string()}) {
      ExpectRefusedKeepingEverything(RunIn(work, command + " --overwrite --out " + Quote(out)), "working directory",
                                     files, paths, command + " --out " + out);
    }
    ExpectRefusedKeepingEverything(
        RunIn(root_, command + " --overwrite --out scratch", "HOME=" + Quote((root_ / "scratch").string())),
        "home folder", files, paths, command + " --out $HOME");
  }
}

// Defect 1: a plain file named by --out was called "results" and deleted.
TEST_F(OutputSafety, OverwriteRefusesAPlainFile) {
  std::ofstream(root_ / "results") << "not a folder";
  const auto files = Snapshot(root_);
  const auto paths = Paths();
  ExpectRefusedKeepingEverything(RunIn(root_, kCell + " --overwrite --out results"), "is a file", files, paths, "eval");
  ExpectRefusedKeepingEverything(RunIn(root_, kDemos + " --overwrite --out results"), "is a file", files, paths,
                                 "demos");
  ExpectRefusedKeepingEverything(RunIn(root_, kCell + " --resume --out results"), "is a file", files, paths,
                                 "eval --resume");
}

// Defect 2: `eval --overwrite` deleted the old cell before a check that failed (an unreachable
// server): the old cell must survive, and no staging folder is left beside it.
TEST_F(OutputSafety, OverwriteThatFailsBeforeItsFirstEpisodeKeepsTheOldCell) {
  const fs::path cell = root_ / "cell";
  ASSERT_EQ(Run(kCell + " --seed 0 --out " + Quote(cell.string())).exit_code, 0);
  const auto files = Snapshot(root_);
  const auto paths = Paths();
  const RunResult failed =
      Run("eval --task clutter-pick-cube --episodes 2 --envs 2 --quiet --policy openpi --server ws://127.0.0.1:9 "
          "--server-timeout 0.2 --overwrite --out " +
          Quote(cell.string()));
  ExpectRefusedKeepingEverything(failed, "127.0.0.1:9", files, paths, "overwrite with an unreachable server");

  const RunResult replaced = Run(kCell + " --seed 1 --overwrite --out " + Quote(cell.string()));
  ASSERT_EQ(replaced.exit_code, 0) << replaced.err;
  EXPECT_NE(ReadText(cell / "episodes.jsonl").find("\"seed\":1"), std::string::npos);
  EXPECT_EQ(ReadText(cell / "episodes.jsonl").find("\"seed\":0"), std::string::npos)
      << "old records mixed into the new cell";
  for (const auto& entry : fs::directory_iterator(root_)) {
    EXPECT_EQ(entry.path().filename().string().find(".tavis-"), std::string::npos) << "left behind: " << entry.path();
  }
}

// Defect 3: two `eval --resume` of one cell both ran, 171 records for 96 episodes. Here the
// first writer is a real `tavis eval` still running: the second is refused naming it, and the
// first's cell is whole.
TEST_F(OutputSafety, SecondWriterOfARunningCellIsRefusedAndTheFirstCompletesWhole) {
  const fs::path cell = root_ / "cell";
  const std::string first =
      "eval --task clutter-pick-cube --episodes 40 --envs 1 --threads 1 --quiet --seed 2 --out " + Quote(cell.string());
  const pid_t child = fork();
  if (child == 0) {
    execl("/bin/sh", "sh", "-c", ("exec " + Quote(TAVIS_BINARY) + " " + first + " >/dev/null 2>&1").c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (ReadText(cell / "cell.json").empty() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const RunResult second =
      Run("eval --task clutter-pick-cube --episodes 40 --envs 1 --threads 1 --quiet --seed 2 --resume --out " +
          Quote(cell.string()));
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_EQ(second.exit_code, 1) << second.err;
  EXPECT_NE(second.err.find("is being written by tavis eval (pid " + std::to_string(child)), std::string::npos)
      << second.err;
  const std::vector<std::string> lines = Lines(ReadText(cell / "episodes.jsonl"));
  ASSERT_EQ(lines.size(), 40u);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    EXPECT_NE(lines[i].find("\"episode\":" + std::to_string(i) + ","), std::string::npos)
        << "line " << i << ": " << lines[i];
  }
}

// Defect 3, with the first writer held here (deterministic): refused naming this process; a
// killed writer's lock (its process is dead) is taken over, and the resumed cell equals an
// uninterrupted run.
TEST_F(OutputSafety, LockedCellIsRefusedAndAKilledWritersLockIsTakenOver) {
  const std::string cell_args = "eval --task clutter-pick-cube --episodes 8 --envs 2 --quiet --seed 4";
  const fs::path whole = root_ / "whole";
  ASSERT_EQ(Run(cell_args + " --out " + Quote(whole.string())).exit_code, 0);
  const fs::path cell = root_ / "cell";
  ASSERT_TRUE(KillWhenLinesAppear(cell_args + " --out " + Quote(cell.string()), cell / "episodes.jsonl", 2, SIGKILL));
  const std::string kept = ReadText(cell / "episodes.jsonl");
  {
    const batch::output::OutputLock holder(cell, "eval");
    const RunResult refused = Run(cell_args + " --resume --out " + Quote(cell.string()));
    EXPECT_EQ(refused.exit_code, 1);
    EXPECT_NE(refused.err.find("pid " + std::to_string(getpid())), std::string::npos) << refused.err;
    EXPECT_EQ(ReadText(cell / "episodes.jsonl"), kept);
  }
  const RunResult resumed = Run(cell_args + " --resume --out " + Quote(cell.string()));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(ReadText(cell / "episodes.jsonl"), ReadText(whole / "episodes.jsonl"));
}

// Defect 3: two `demos` into one folder left a dataset whose videos do not open.
TEST_F(OutputSafety, LockedDatasetIsRefusedAndThenWrittenAsAnUnlockedOne) {
  const fs::path reference = root_ / "reference";
  ASSERT_EQ(Run(kDemos + " --out " + Quote(reference.string())).exit_code, 0);
  const fs::path dataset = root_ / "dataset";
  fs::create_directories(dataset);
  {
    const batch::output::OutputLock holder(dataset, "demos");
    const RunResult refused = Run(kDemos + " --out " + Quote(dataset.string()));
    EXPECT_EQ(refused.exit_code, 1);
    EXPECT_NE(refused.err.find("is being written by tavis demos (pid " + std::to_string(getpid())), std::string::npos)
        << refused.err;
    EXPECT_TRUE(batch::output::HoldsNoResults(dataset));
  }
  const RunResult written = Run(kDemos + " --out " + Quote(dataset.string()));
  ASSERT_EQ(written.exit_code, 0) << written.err;
  for (const char* part : {"meta/info.json", "meta/stats.json", "data/chunk-000/file-000.parquet"}) {
    EXPECT_EQ(ReadText(dataset / part), ReadText(reference / part)) << part;
  }
}

class SweepSafety : public OutputSafety {
 protected:
  void SetUp() override {
    OutputSafety::SetUp();
    spec_ = root_ / "small.yaml";
    std::ofstream(spec_) << "tasks: [clutter-pick-cube]\nrobots: [gr1t2]\nsplits: [id]\ncameras: [head]\nseeds: [3]\n"
                            "episodes: 3\nenvs: 2\npolicy:\n  name: expert\n";
  }
  RunResult Sweep(const fs::path& out) const {
    return Run("sweep " + Quote(spec_.string()) + " --out " + Quote(out.string()) + " --quiet");
  }
  fs::path spec_;
};

// Defect 3: two sweeps in one folder duplicated records in every cell.
TEST_F(SweepSafety, LockedSweepIsRefusedAndThenRunsLikeAnUnlockedOne) {
  const fs::path reference = root_ / "reference";
  ASSERT_EQ(Sweep(reference).exit_code, 0);
  const fs::path sweep = root_ / "sweep";
  fs::create_directories(sweep);
  {
    const batch::output::OutputLock holder(sweep, "sweep");
    const RunResult refused = Sweep(sweep);
    EXPECT_EQ(refused.exit_code, 1);
    EXPECT_NE(refused.err.find("is being written by tavis sweep (pid " + std::to_string(getpid())), std::string::npos)
        << refused.err;
  }
  ASSERT_EQ(Sweep(sweep).exit_code, 0);
  const std::string cell = "cells/clutter-pick-cube_gr1t2_id_head_expert_s3/episodes.jsonl";
  EXPECT_EQ(ReadText(sweep / cell), ReadText(reference / cell));
  EXPECT_EQ(Lines(ReadText(sweep / cell)).size(), 3u);
}

// Defect 4: a sweep into an eval cell overwrote its summary.json; `merge --out ""` wrote into the
// working directory.
TEST_F(SweepSafety, SweepAndMergeRefuseFoldersThatAreNotTheirs) {
  const fs::path cell = root_ / "cell";
  ASSERT_EQ(Run(kCell + " --seed 0 --out " + Quote(cell.string())).exit_code, 0);
  fs::create_directories(root_ / "mine");
  std::ofstream(root_ / "mine" / "thesis.txt") << "mine";
  const auto files = Snapshot(root_);
  const auto paths = Paths();
  ExpectRefusedKeepingEverything(Sweep(cell), "cell.json", files, paths, "sweep into an eval cell");
  ExpectRefusedKeepingEverything(Sweep(root_ / "mine"), "thesis.txt", files, paths, "sweep beside a user's file");
  ExpectRefusedKeepingEverything(RunIn(root_, "sweep merge --out '' cell"), "empty string", files, paths,
                                 "merge --out ''");
  ExpectRefusedKeepingEverything(RunIn(root_, "sweep merge --out . cell"), "working directory", files, paths,
                                 "merge --out .");
}

// Defect 5: a resume with a changed robot file (arm velocity limit 5.0 -> 4.0) was accepted,
// mixing episodes of two robots in one cell.
TEST_F(OutputSafety, ResumeWithAChangedRobotFileIsRefusedNamingTheChange) {
  const fs::path configs = root_ / "configs";
  fs::copy(TAVIS_CONFIG_DIR, configs, fs::copy_options::recursive);
  const std::string cell_args =
      "eval --task clutter-pick-cube --episodes 8 --envs 2 --quiet --seed 4 --config-dir " + Quote(configs.string());
  const fs::path cell = root_ / "cell";
  ASSERT_TRUE(KillWhenLinesAppear(cell_args + " --out " + Quote(cell.string()), cell / "episodes.jsonl", 2, SIGKILL));
  const std::string kept = ReadText(cell / "episodes.jsonl");

  const fs::path robot = configs / "robots" / "gr1t2.yaml";
  std::string text = ReadText(robot);
  const std::string from = "arm: {velocity_limit: 5.0,";
  ASSERT_NE(text.find(from), std::string::npos) << "the robot file changed its layout";
  text.replace(text.find(from), from.size(), "arm: {velocity_limit: 4.0,");
  std::ofstream(robot) << text;
  const RunResult refused = Run(cell_args + " --resume --out " + Quote(cell.string()));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("velocity_limit \"5.0\" -> \"4.0\""), std::string::npos) << refused.err;
  EXPECT_EQ(ReadText(cell / "episodes.jsonl"), kept);
}

// #46 item 7: --overwrite deleted a user's files inside tavis's own sub-folders: a cell's videos/,
// a dataset's meta/. Each is refused naming the file, and nothing is deleted.
TEST_F(OutputSafety, OverwriteRefusesAUsersFileInsideTavissOwnSubFolders) {
  const fs::path cell = root_ / "cell";
  ASSERT_EQ(Run(kCell + " --videos 1 --video-size 64x48 --out " + Quote(cell.string())).exit_code, 0);
  ASSERT_TRUE(fs::exists(cell / "videos" / "episode_0.mp4"));
  std::ofstream(cell / "videos" / "talk.mp4") << "a user's video";
  const fs::path dataset = root_ / "dataset";
  ASSERT_EQ(Run(kDemos + " --out " + Quote(dataset.string())).exit_code, 0);
  std::ofstream(dataset / "meta" / "README.md") << "a user's notes";
  const auto files = Snapshot(root_);
  const auto paths = Paths();
  ExpectRefusedKeepingEverything(Run(kCell + " --seed 1 --overwrite --out " + Quote(cell.string())), "videos/talk.mp4",
                                 files, paths, "eval");
  ExpectRefusedKeepingEverything(Run(kDemos + " --seed 1 --overwrite --out " + Quote(dataset.string())),
                                 "meta/README.md", files, paths, "demos");
}

// #46 item 11: a killed --overwrite left its hidden ".NAME.tavis-new-PID" copy forever. The next
// run of the same --out removes it (only that pattern, of a process that is gone) and says so.
TEST_F(OutputSafety, AKilledOverwritesStagingCopyIsRemovedByTheNextRun) {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);  // a process number nobody has now
  const fs::path stale = root_ / (".cell.tavis-new-" + std::to_string(child));
  fs::create_directories(stale);
  std::ofstream(stale / "cell.json") << "{}";
  const RunResult run = Run(kCell + " --out " + Quote((root_ / "cell").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_NE(run.err.find("removed " + stale.string()), std::string::npos) << run.err;
}

// #46 item 11: `--record` inside `--out` left a folder that blocked the cell and the --overwrite it
// suggested. Either inside the other is refused naming both, before anything is written.
TEST_F(OutputSafety, RecordInsideOutOrOutInsideRecordIsRefusedBeforeAnythingIsWritten) {
  const auto files = Snapshot(root_);
  const auto paths = Paths();
  const std::string cell = (root_ / "cell").string();
  const RunResult inside = Run(kCell + " --out " + Quote(cell) + " --record " + Quote(cell + "/rollouts"));
  ExpectRefusedKeepingEverything(inside, "--record " + cell + "/rollouts is inside the cell's --out " + cell, files,
                                 paths, "--record inside --out");
  const std::string dataset = (root_ / "rollouts").string();
  const RunResult around = Run(kCell + " --out " + Quote(dataset + "/cell") + " --record " + Quote(dataset));
  ExpectRefusedKeepingEverything(around, "--out " + dataset + "/cell is inside --record " + dataset, files, paths,
                                 "--out inside --record");
}

}  // namespace
}  // namespace tavis::tools
