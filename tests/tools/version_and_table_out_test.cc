// `tavis --version` names the git revision the program was built from; `tavis table --out` makes
// the folder of its prefix, and names it when it cannot.
#include <cstdio>
#include <string>

#include "tool_runner.h"

namespace tavis::tools {
namespace {

using VersionAndTableOut = TavisCommandTest;

// `git describe` of the source tree, read by git itself.
std::string GitDescribe() {
  const std::string command = "git -C " + Quote(TAVIS_SOURCE_DIR) + " describe --always --tags 2>/dev/null";
  std::FILE* pipe = popen(command.c_str(), "r");
  std::string text;
  for (int c; pipe != nullptr && (c = std::fgetc(pipe)) != EOF;) text += static_cast<char>(c);
  if (pipe != nullptr) pclose(pipe);
  while (!text.empty() && text.back() == '\n') text.pop_back();
  return text;
}

TEST_F(VersionAndTableOut, VersionNamesTheGitRevision) {
  const RunResult run = Run("--version");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out.rfind("tavis 0.", 0), 0u) << run.out;
  const std::string describe = GitDescribe();
  ASSERT_FALSE(describe.empty()) << "the source tree is not a git checkout";
  // Built from this tree (with or without uncommitted changes since): its revision is named.
  EXPECT_NE(run.out.find("(git " + describe), std::string::npos) << run.out << " vs git describe " << describe;
}

// Two cells in a folder, as `tavis eval` writes them.
void WriteCell(const fs::path& dir, const std::string& task, int successes) {
  fs::create_directories(dir);
  std::ofstream(dir / "summary.json") << R"({"task": ")" << task
                                      << R"(", "robot": "gr1t2", "split": "id", "n_episodes": 4, "n_successful": )"
                                      << successes << "}";
}

TEST_F(VersionAndTableOut, TableCreatesTheFolderOfItsPrefix) {
  WriteCell(root_ / "cells" / "a", "clutter-pick-cube", 3);
  const fs::path prefix = root_ / "not" / "yet" / "there" / "head";
  const RunResult run =
      Run("table --in " + Quote((root_ / "cells").string()) + " --suite tavis-head --out " + Quote(prefix.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string markdown = ReadText(prefix.string() + ".md");
  EXPECT_NE(markdown.find("75.0"), std::string::npos) << markdown;  // 3 of 4
  EXPECT_TRUE(fs::exists(prefix.string() + ".csv"));
}

TEST_F(VersionAndTableOut, TableNamesAFolderItCannotCreate) {
  WriteCell(root_ / "cells" / "a", "clutter-pick-cube", 3);
  std::ofstream(root_ / "a_file") << "not a folder";
  const RunResult run = Run("table --in " + Quote((root_ / "cells").string()) + " --suite tavis-head --out " +
                            Quote((root_ / "a_file" / "tables" / "head").string()));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("cannot create the folder " + (root_ / "a_file" / "tables").string()), std::string::npos)
      << run.err;
  EXPECT_EQ(ReadText(root_ / "a_file"), "not a folder");
}

}  // namespace
}  // namespace tavis::tools
