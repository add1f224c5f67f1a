// Which folders tavis may replace or write into, the lock on them, and replacing one without
// losing it: the rules `tavis eval`, `demos`, `sweep` and `sweep merge` share.
#include "batch/output/output_folder.h"
#include "tests/support/test_folder.h"
#include "tests/support/thrown_message.h"

#include <gtest/gtest.h>
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
  for (const char* name :
       {"cell.json", "episodes.jsonl", "summary.json", "actions/episode_0.csv", "summary.json.partial"})
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

}  // namespace
}  // namespace tavis::batch::output
