// `cmake --install` into a prefix that is then moved: the installed program finds its configs
// next to itself, not in the source tree it was built from, and runs a cell.
#include <filesystem>
#include <string>

#include "tool_runner.h"

namespace tavis::tools {
namespace {

using InstallTest = TavisCommandTest;

TEST_F(InstallTest, MovedPrefixRunsACellWithItsOwnConfigs) {
  const fs::path staged = root_ / "staged";
  const std::string install = Quote(TAVIS_CMAKE_COMMAND) + " --install " + Quote(TAVIS_BUILD_DIR) + " --prefix " +
                              Quote(staged.string()) + " > " + Quote((root_ / "install.log").string()) + " 2>&1";
  ASSERT_EQ(std::system(install.c_str()), 0) << ReadText(root_ / "install.log");
  const fs::path prefix = root_ / "moved";
  fs::rename(staged, prefix);
  const fs::path tavis = prefix / "bin" / "tavis";
  ASSERT_TRUE(fs::exists(prefix / "share" / "tavis" / "configs" / "robots" / "gr1t2.yaml"));

  const fs::path cell = root_ / "cell";
  const std::string command = Quote(tavis.string()) + " eval --episodes 2 --envs 2 --quiet --out " +
                              Quote(cell.string()) + " > " + Quote((root_ / "eval.log").string()) + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << ReadText(root_ / "eval.log");
  EXPECT_TRUE(fs::exists(cell / "summary.json"));
  EXPECT_EQ(Lines(ReadText(cell / "episodes.jsonl")).size(), 2u);

  // The default --config-dir it reports is the moved prefix's.
  const std::string help = Quote(tavis.string()) + " eval --help > " + Quote((root_ / "help.txt").string());
  ASSERT_EQ(std::system(help.c_str()), 0);
  EXPECT_NE(ReadText(root_ / "help.txt").find((prefix / "share" / "tavis" / "configs").string()), std::string::npos)
      << ReadText(root_ / "help.txt");
}

}  // namespace
}  // namespace tavis::tools
