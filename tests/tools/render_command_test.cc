// `tavis render`: the four views at reset and after N expert ticks, and a labelled contact sheet.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "render/image_io.h"
#include "tool_runner.h"

namespace tavis::tools {
namespace {

using RenderCommand = TavisCommandTest;

// True when some pixel differs between the two images.
bool Differ(const render::RgbImage& a, const render::RgbImage& b) { return a.pixels != b.pixels; }

TEST_F(RenderCommand, WritesFourViewsTwiceAndAContactSheet) {
  const fs::path dir = root_ / "views";
  const RunResult run =
      Run("render --robot reachy2 --seed 2 --width 64 --height 48 --steps 30 --out " + Quote(dir.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("clutter-pick-cube reachy2 id seed 2 episode 0: tick 30"), std::string::npos) << run.out;

  std::set<std::string> expected = {"contact_sheet.png"};
  for (const char* camera : {"head", "fixed", "left_wrist", "right_wrist"}) {
    for (const char* prefix : {"reset_", "tick30_"}) expected.insert(std::string(prefix) + camera + ".png");
  }
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename().string());
  EXPECT_EQ(names, expected);
  for (const std::string& name : expected) {
    EXPECT_NE(run.out.find((dir / name).string()), std::string::npos) << name << " not reported in " << run.out;
  }

  for (const char* camera : {"head", "fixed", "left_wrist", "right_wrist"}) {
    SCOPED_TRACE(camera);
    const render::RgbImage reset = render::ReadPng((dir / (std::string("reset_") + camera + ".png")).string());
    const render::RgbImage later = render::ReadPng((dir / (std::string("tick30_") + camera + ".png")).string());
    EXPECT_EQ(reset.width, 64);
    EXPECT_EQ(reset.height, 48);
    EXPECT_EQ(later.width, 64);
    EXPECT_EQ(later.height, 48);
  }
  // Half a second in, the expert is turning the head toward the cube: its view has changed.
  EXPECT_TRUE(
      Differ(render::ReadPng((dir / "reset_head.png").string()), render::ReadPng((dir / "tick30_head.png").string())));
  // The sheet tiles the four views in two columns and two rows, with margins.
  const render::RgbImage sheet = render::ReadPng((dir / "contact_sheet.png").string());
  EXPECT_GT(sheet.width, 2 * 64);
  EXPECT_LT(sheet.width, 2 * 64 + 40);
  EXPECT_GT(sheet.height, 2 * 48);
  EXPECT_LT(sheet.height, 2 * 48 + 40);
}

TEST_F(RenderCommand, BlockedTaskWritesABlackHead) {
  const fs::path dir = root_ / "blocked";
  const RunResult run =
      Run("render --task blocked-clutter-pick-cube --width 48 --height 36 --steps 3 --out " + Quote(dir.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  auto black = [](const render::RgbImage& image) {
    return std::all_of(image.pixels.begin(), image.pixels.end(), [](uint8_t c) { return c == 0; });
  };
  EXPECT_TRUE(black(render::ReadPng((dir / "reset_head.png").string())));
  EXPECT_TRUE(black(render::ReadPng((dir / "tick3_head.png").string())));
  EXPECT_FALSE(black(render::ReadPng((dir / "tick3_fixed.png").string())));
  EXPECT_FALSE(black(render::ReadPng((dir / "tick3_left_wrist.png").string())));
}

TEST_F(RenderCommand, SameArgumentsGiveIdenticalFiles) {
  const std::string args = "render --width 40 --height 30 --steps 9 --seed 1 --episode 3 --out ";
  ASSERT_EQ(Run(args + Quote((root_ / "a").string())).exit_code, 0);
  ASSERT_EQ(Run(args + Quote((root_ / "b").string())).exit_code, 0);
  for (const auto& entry : fs::directory_iterator(root_ / "a")) {
    SCOPED_TRACE(entry.path().filename().string());
    EXPECT_EQ(ReadText(entry.path()), ReadText(root_ / "b" / entry.path().filename()));
  }
}

TEST_F(RenderCommand, BadInputExitsOneNamingTheValueAndWritesNothing) {
  const fs::path dir = root_ / "never";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--task nope", "nope"},
      {"--robot robby", "robby"},
      {"--split sideways", "sideways"},
      {"--width 0", "--width: must be an integer from 1 to 8192, got '0'"},
      {"--height -5", "--height: must be an integer from 1 to 8192, got '-5'"},
      {"--steps -1", "--steps: must be an integer from 0 to 1000000, got '-1'"},
      {"--seed -2", "--seed must be an integer from 0 to 18446744073709551615, got -2"},
      {"--episode -1", "--episode: must be an integer from 0 to 1000000000, got '-1'"},
      {"--width banana", "banana"},
  };
  for (const auto& [args, needle] : cases) {
    SCOPED_TRACE(args);
    const RunResult run = Run("render " + args + " --out " + Quote(dir.string()));
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_NE(run.err.find(needle), std::string::npos) << "stderr: " << run.err;
    EXPECT_FALSE(fs::exists(dir));
  }
  const RunResult no_out = Run("render --steps 3");
  EXPECT_EQ(no_out.exit_code, 1);
  EXPECT_NE(no_out.err.find("--out"), std::string::npos) << no_out.err;
}

TEST_F(RenderCommand, HelpExitsZeroAndListsOptions) {
  const RunResult run = Run("render --help");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  for (const char* option : {"--task", "--robot", "--split", "--seed", "--episode", "--out", "--width", "--height",
                             "--steps", "contact_sheet.png"}) {
    EXPECT_NE(run.out.find(option), std::string::npos) << option << " missing in:\n" << run.out;
  }
}

}  // namespace
}  // namespace tavis::tools
