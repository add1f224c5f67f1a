// Which folders tavis may replace or write into, the lock on them, and replacing one without
// losing it: the rules `tavis eval`, `demos`, `sweep` and `sweep merge` share.
#include "batch/output/output_folder.h"
#include "batch/output/atomic_file.h"
#include "tests/support/test_folder.h"
#include "tests/support/thrown_message.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace tavis::batch::output {
namespace {

namespace fs = std::filesystem;

using OutputFolder = testing::TestFolder;

// The message of the std::invalid_argument `call` throws ("" when none).
template <typename Call>
std::string Refusal(Call call) {
  return testing::ThrownMessage<std::invalid_argument>(call);
}

TEST_F(OutputFolder, CellWithOnlyItsOwnFilesIsOwnAndAUsersFileMakesItForeign) {
  const fs::path cell = root_ / "cell";
  for (const char* name : {"cell.json", "episodes.jsonl", "episode_times.jsonl", "summary.json",
                           "actions/episode_0.csv", "summary.json.partial"})
    testing::WriteTextFile(cell / name, "x");
  EXPECT_TRUE(IsOwnOutput(cell, OutputKind::kEvalCell));
  EXPECT_FALSE(IsOwnOutput(cell, OutputKind::kSweep)) << "an eval cell is no sweep";
  EXPECT_FALSE(IsOwnOutput(cell, OutputKind::kDataset));
  testing::WriteTextFile(cell / "thesis.txt", "x");
  EXPECT_FALSE(IsOwnOutput(cell, OutputKind::kEvalCell));
  EXPECT_EQ(ForeignEntries(cell, OutputKind::kEvalCell), std::vector<std::string>{"thesis.txt"});
  const std::string refusal = Refusal([&] { RequireEmptyOrOwn(cell, OutputKind::kEvalCell, "move it"); });
  EXPECT_NE(refusal.find("thesis.txt"), std::string::npos) << refusal;
}

TEST_F(OutputFolder, FolderWithoutMarkerOrSignatureIsNotOwnEvenIfItsNamesMatch) {
  const fs::path dir = root_ / "look-alike";
  testing::WriteTextFile(dir / "summary.json", "x");  // a name tavis writes, but no cell.json and no marker
  EXPECT_FALSE(IsOwnOutput(dir, OutputKind::kEvalCell));
  WriteOutputMarker(dir, OutputKind::kEvalCell);
  EXPECT_TRUE(IsOwnOutput(dir, OutputKind::kEvalCell));
  EXPECT_FALSE(IsOwnOutput(dir, OutputKind::kSweep)) << "the marker names its kind";
}

TEST_F(OutputFolder, OnlyMarkerAndLockCountAsHoldingNoResults) {
  EXPECT_TRUE(HoldsNoResults(root_ / "absent"));
  const fs::path dir = root_ / "dir";
  fs::create_directories(dir);
  testing::WriteTextFile(dir / output::kOutputLockFile, "x");
  testing::WriteTextFile(dir / output::kOutputMarkerFile, "x");
  EXPECT_TRUE(HoldsNoResults(dir));
  testing::WriteTextFile(dir / ".hidden", "x");
  EXPECT_FALSE(HoldsNoResults(dir));
  testing::WriteTextFile(root_ / "file", "x");
  EXPECT_FALSE(HoldsNoResults(root_ / "file"));
}

TEST_F(OutputFolder, UnusablePathsAreRefusedNamingWhy) {
  const fs::path cwd = fs::current_path();
  fs::create_directories(root_ / "work");
  fs::current_path(root_ / "work");
  EXPECT_NE(Refusal([] { RequireUsableOutputPath(""); }).find("empty string"), std::string::npos);
  for (const char* path : {".", "..", "/", "./", "../work"}) {
    EXPECT_NE(Refusal([&] { RequireUsableOutputPath(path); }).find("working directory"), std::string::npos) << path;
  }
  testing::WriteTextFile(root_ / "work" / "plain", "x");
  EXPECT_NE(Refusal([] { RequireUsableOutputPath("plain"); }).find("is a file"), std::string::npos);
  EXPECT_EQ(Refusal([] { RequireUsableOutputPath("results/cell"); }), "");
  const char* home = std::getenv("HOME");
  const std::string saved = home != nullptr ? home : "";
  setenv("HOME", (root_ / "home").c_str(), 1);
  EXPECT_NE(Refusal([&] { RequireUsableOutputPath(root_ / "home"); }).find("home folder"), std::string::npos);
  EXPECT_NE(Refusal([&] { RequireUsableOutputPath(root_ / "home" / "."); }).find("home folder"), std::string::npos);
  if (home != nullptr) setenv("HOME", saved.c_str(), 1);
  fs::current_path(cwd);
}

TEST_F(OutputFolder, SecondLockIsRefusedNamingTheHolderUntilTheFirstIsReleased) {
  const fs::path dir = root_ / "out";
  OutputLock first = CreateAndLockOutput(dir, "eval");
  EXPECT_NE(testing::ReadTextFile(dir / output::kOutputLockFile).find("tavis eval (pid " + std::to_string(getpid())),
            std::string::npos);
  const std::string refusal = Refusal([&] { OutputLock second(dir, "sweep"); });
  EXPECT_NE(refusal.find("is being written by tavis eval (pid " + std::to_string(getpid())), std::string::npos)
      << refusal;
  first.Release();
  EXPECT_EQ(testing::ReadTextFile(dir / output::kOutputLockFile), "") << "a released lock names no holder";
  OutputLock again(dir, "sweep");
  EXPECT_TRUE(again.held());
}

TEST_F(OutputFolder, LockLeftByADeadProcessIsTakenOver) {
  const fs::path dir = root_ / "out";
  fs::create_directories(dir);
  testing::WriteTextFile(dir / output::kOutputLockFile,
                         "tavis eval (pid 999999 on elsewhere, since 2020-01-01T00:00:00Z)\n");
  OutputLock lock(dir, "demos");
  EXPECT_NE(testing::ReadTextFile(dir / output::kOutputLockFile).find("tavis demos"), std::string::npos);
}

TEST_F(OutputFolder, ReplacementKeepsTheOldFolderUntilSwappedAndLeavesNothingWhenAbandoned) {
  const fs::path dir = root_ / "cell";
  testing::WriteTextFile(dir / "cell.json", "old");
  {
    OutputReplacement abandoned(dir, "eval");
    ASSERT_TRUE(fs::is_directory(abandoned.staging()));
    EXPECT_EQ(abandoned.staging().parent_path(), dir.parent_path());
    testing::WriteTextFile(abandoned.staging() / "cell.json", "new");
  }
  EXPECT_EQ(testing::ReadTextFile(dir / "cell.json"), "old");
  EXPECT_EQ(std::distance(fs::directory_iterator(root_), fs::directory_iterator()), 1) << "staging left behind";
  {
    OutputReplacement replacement(dir, "eval");
    testing::WriteTextFile(replacement.staging() / "cell.json", "new");
    EXPECT_EQ(testing::ReadTextFile(dir / "cell.json"), "old");
    replacement.SwapIn();
    EXPECT_EQ(testing::ReadTextFile(dir / "cell.json"), "new");
    // The new folder is locked from the swap on.
    EXPECT_NE(Refusal([&] { OutputLock other(dir, "eval"); }).find("is being written"), std::string::npos);
  }
  EXPECT_EQ(testing::ReadTextFile(dir / "cell.json"), "new");
  EXPECT_EQ(std::distance(fs::directory_iterator(root_), fs::directory_iterator()), 1) << "old folder left behind";
}

// #46 item 7: --overwrite deleted a user's files inside tavis's own sub-folders (videos/,
// actions/, a dataset's meta/ and data/): only the top level was looked at.
TEST_F(OutputFolder, AForeignFileAtAnyDepthMakesTheFolderForeign) {
  const fs::path cell = root_ / "cell";
  for (const char* name : {"cell.json", "episodes.jsonl", "actions/episode_0.csv", "actions/episode_1.csv.partial",
                           "videos/episode_0.mp4", "videos/episode_1.mp4.partial", "videos/episode_2/frame_00000.png",
                           "videos/episode_3.partial/frame_00001.png", ".tavis_output"})
    testing::WriteTextFile(cell / name, "x");
  EXPECT_EQ(ForeignEntries(cell, OutputKind::kEvalCell), std::vector<std::string>{});
  testing::WriteTextFile(cell / "videos" / "talk.mp4", "a user's");
  testing::WriteTextFile(cell / "actions" / "mine" / "plan.txt", "a user's");
  EXPECT_EQ(ForeignEntries(cell, OutputKind::kEvalCell),
            (std::vector<std::string>{"actions/mine/", "videos/talk.mp4"}));
  EXPECT_FALSE(IsOwnOutput(cell, OutputKind::kEvalCell));
  const std::string refusal = Refusal([&] { RequireEmptyOrOwn(cell, OutputKind::kEvalCell, "move it"); });
  EXPECT_NE(refusal.find("videos/talk.mp4"), std::string::npos) << refusal;

  const fs::path dataset = root_ / "dataset";
  for (const char* name : {"tavis_demos.json", "meta/info.json", "meta/stats.json", "meta/tasks.parquet",
                           "meta/episodes/chunk-000/file-000.parquet", "data/chunk-000/file-000.parquet",
                           "videos/observation.images.head/chunk-000/file-000.mp4",
                           ".tavis_spool/episode_000000/episode.json", ".tavis_spool/episode_000000/head.packets"})
    testing::WriteTextFile(dataset / name, "x");
  EXPECT_TRUE(IsOwnOutput(dataset, OutputKind::kDataset));
  testing::WriteTextFile(dataset / "meta" / "README.md", "a user's");
  testing::WriteTextFile(dataset / "data" / "chunk-000" / "notes.csv", "a user's");
  EXPECT_EQ(ForeignEntries(dataset, OutputKind::kDataset),
            (std::vector<std::string>{"data/chunk-000/notes.csv", "meta/README.md"}));

  const fs::path sweep = root_ / "sweep";
  for (const char* name : {"manifest.json", "cells/a/cell.json", "cells/a/policy.json", "cells/a/videos/episode_0.mp4",
                           "cells/a/.tavis_lock", "tables/success.md", "figures/funnel.svg", "report.html"})
    testing::WriteTextFile(sweep / name, "x");
  EXPECT_TRUE(IsOwnOutput(sweep, OutputKind::kSweep));
  testing::WriteTextFile(sweep / "cells" / "a" / "videos" / "notes.txt", "a user's");
  EXPECT_EQ(ForeignEntries(sweep, OutputKind::kSweep), std::vector<std::string>{"cells/a/videos/notes.txt"});
}

// A link is never tavis's, wherever it points: --overwrite refuses it instead of removing it.
TEST_F(OutputFolder, ALinkInsideIsForeign) {
  const fs::path cell = root_ / "cell";
  testing::WriteTextFile(cell / "cell.json", "x");
  fs::create_directories(root_ / "elsewhere");
  fs::create_directory_symlink(root_ / "elsewhere", cell / "videos");
  EXPECT_EQ(ForeignEntries(cell, OutputKind::kEvalCell), std::vector<std::string>{"videos"});
}

// #46 item 3: a planted link at a file tavis writes sent its bytes to the file it points to.
TEST_F(OutputFolder, NoFileIsWrittenThroughALinkPlantedAtItsName) {
  const fs::path outside = root_ / "outside.txt";
  testing::WriteTextFile(outside, "precious");
  const fs::path dir = root_ / "cell";
  fs::create_directories(dir);
  fs::create_symlink(outside, dir / "summary.json.partial");
  WriteFileAtomically(dir / "summary.json", "new");
  EXPECT_EQ(testing::ReadTextFile(outside), "precious");
  EXPECT_EQ(testing::ReadTextFile(dir / "summary.json"), "new");
  EXPECT_FALSE(fs::is_symlink(dir / "summary.json"));

  fs::create_symlink(outside, dir / kOutputLockFile);
  const std::string refusal = Refusal([&] { OutputLock lock(dir, "eval"); });
  EXPECT_NE(refusal.find((dir / kOutputLockFile).string() + " is a symbolic link"), std::string::npos) << refusal;
  EXPECT_EQ(testing::ReadTextFile(outside), "precious") << "the lock's note went through the link";

  fs::create_directory_symlink(root_, dir / "actions");
  EXPECT_NE(Refusal([&] { MakeOwnFolder(dir / "actions"); }).find("is a symbolic link"), std::string::npos);
  MakeOwnFolder(dir / "videos");
  EXPECT_TRUE(fs::is_directory(dir / "videos"));
}

// A write that fails names the file and the system's reason.
TEST_F(OutputFolder, AFailedWriteNamesTheFileAndTheReason) {
  const fs::path missing = root_ / "no" / "summary.json";
  EXPECT_EQ(testing::ThrownMessage<std::runtime_error>([&] { WriteFileAtomically(missing, "x"); }),
            "cannot write " + missing.string() + ".partial: No such file or directory");
}

// #46 item 11: a killed --overwrite left its ".NAME.tavis-new-PID" copy forever.
TEST_F(OutputFolder, StagingCopiesOfDeadProcessesAreRemovedOnTheNextRun) {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);  // a process number nobody has now
  const fs::path dead = root_ / (".cell.tavis-new-" + std::to_string(child));
  const fs::path alive = root_ / (".cell.tavis-new-" + std::to_string(getppid()));
  const fs::path old = root_ / (".cell.tavis-old-" + std::to_string(child));
  const fs::path other = root_ / (".cellar.tavis-new-" + std::to_string(child));
  const fs::path users = root_ / ".cell.tavis-new-mine";
  for (const fs::path& dir : {dead, alive, old, other, users}) testing::WriteTextFile(dir / "cell.json", "x");
  testing::WriteTextFile(root_ / "cell" / "cell.json", "x");
  const OutputLock lock = CreateAndLockOutput(root_ / "cell", "eval");
  EXPECT_FALSE(fs::exists(dead));
  for (const fs::path& kept : {alive, old, other, users}) EXPECT_TRUE(fs::exists(kept)) << kept;
}

TEST_F(OutputFolder, InsideIsTheSameFolderOrBelowIt) {
  EXPECT_TRUE(IsSameOrInside(root_ / "a" / "b", root_ / "a"));
  EXPECT_TRUE(IsSameOrInside(root_ / "a" / "", root_ / "a"));
  EXPECT_TRUE(IsSameOrInside(root_ / "a" / "b" / ".." / "c", root_ / "a"));
  EXPECT_FALSE(IsSameOrInside(root_ / "a", root_ / "a" / "b"));
  EXPECT_FALSE(IsSameOrInside(root_ / "ab", root_ / "a"));
}

}  // namespace
}  // namespace tavis::batch::output
