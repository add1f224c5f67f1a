// `tavis eval --expert-mode` and `tavis demos --expert-mode`, through the real program: a
// head-still expert's cell and dataset record the mode, its neck action never changes, its hands
// start at once, and a bad mode is refused naming it.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/dataset/reader/dataset_actions.h"
#include "kinematics/action.h"
#include "tests/support/robot_loading.h"
#include "tool_runner.h"

namespace tavis::tools {
namespace {

using ExpertModeCommand = TavisCommandTest;

nlohmann::json ReadJson(const fs::path& path) { return nlohmann::json::parse(ReadText(path)); }

bool IsNeckEntry(int entry) {
  return entry == kinematics::action::kNeckRoll || entry == kinematics::action::kNeckPitch ||
         entry == kinematics::action::kNeckYaw;
}

// Frames before the recorded arms or grippers first differ from frame 0.
int StillFramesAtStart(const batch::dataset::reader::EpisodeActions& episode) {
  const int width = batch::dataset::reader::kDatasetActionWidth;
  for (int frame = 1; frame < episode.num_steps; ++frame) {
    for (int entry = 0; entry < width; ++entry) {
      const std::size_t at = static_cast<std::size_t>(frame * width + entry);
      if (!IsNeckEntry(entry) && episode.values[at] != episode.values[static_cast<std::size_t>(entry)]) return frame;
    }
  }
  return episode.num_steps;
}

TEST_F(ExpertModeCommand, HeadStillDemosHoldTheNeckAtItsResetPoseInEveryFrameAndActAtOnce) {
  const std::string episodes = "demos --task conditional-pick --robot gr1t2 --episodes 3 --cameras '' --quiet";
  ASSERT_EQ(Run(episodes + " --out " + Quote((root_ / "gaze_first").string())).exit_code, 0);
  const RunResult run = Run(episodes + " --expert-mode head-still --out " + Quote((root_ / "head_still").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(ReadJson(root_ / "head_still" / "tavis_demos.json")["expert_mode"], "head-still");
  EXPECT_EQ(ReadJson(root_ / "gaze_first" / "tavis_demos.json")["expert_mode"], "gaze-first");

  const kinematics::RobotModel robot = tavis::testing::LoadRobot("gr1t2");
  const std::vector<double> q_reset = robot.DefaultPositions();  // the id split starts here
  const int neck[3] = {kinematics::action::kNeckRoll, kinematics::action::kNeckPitch, kinematics::action::kNeckYaw};
  const batch::dataset::reader::DatasetActions head_still =
      batch::dataset::reader::ReadDatasetActions(root_ / "head_still");
  const batch::dataset::reader::DatasetActions gaze_first =
      batch::dataset::reader::ReadDatasetActions(root_ / "gaze_first");
  ASSERT_EQ(head_still.episodes.size(), 3u);
  ASSERT_EQ(gaze_first.episodes.size(), 3u);
  for (std::size_t e = 0; e < head_still.episodes.size(); ++e) {
    const batch::dataset::reader::EpisodeActions& episode = head_still.episodes[e];
    for (int frame = 0; frame < episode.num_steps; ++frame) {
      for (int i = 0; i < 3; ++i) {
        const double value =
            episode.values[static_cast<std::size_t>(frame * batch::dataset::reader::kDatasetActionWidth + neck[i])];
        // float32 in the dataset
        ASSERT_EQ(value, static_cast<float>(q_reset[static_cast<std::size_t>(robot.neck_joints[i])]))
            << "episode " << e << " frame " << frame << " neck entry " << neck[i];
      }
    }
    // 60 fps: the hands move once the dropped objects rest (about 0.3 s), within half a second,
    // where the gaze-first expert first looks for over a second.
    EXPECT_LE(StillFramesAtStart(episode), 30) << "episode " << e;
    EXPECT_GE(StillFramesAtStart(gaze_first.episodes[e]), 60) << "episode " << e;
    EXPECT_LT(episode.num_steps, gaze_first.episodes[e].num_steps) << "episode " << e;
  }
}

TEST_F(ExpertModeCommand, EvalRecordsTheExpertsModeInTheCellAndItsSummary) {
  const std::string cell = "eval --task wait-then-act --episodes 2 --envs 1 --quiet";
  ASSERT_EQ(Run(cell + " --expert-mode head-still --out " + Quote((root_ / "head_still").string())).exit_code, 0);
  ASSERT_EQ(Run(cell + " --out " + Quote((root_ / "gaze_first").string())).exit_code, 0);
  for (const std::string mode : {"head-still", "gaze-first"}) {
    const fs::path dir = root_ / (mode == "head-still" ? "head_still" : "gaze_first");
    EXPECT_EQ(ReadJson(dir / "cell.json")["expert_mode"], mode);
    EXPECT_EQ(ReadJson(dir / "summary.json")["expert_mode"], mode);
    EXPECT_EQ(ReadJson(dir / "summary.json")["n_successful"], 2) << mode;
  }
  // A resume must not mix the two modes' episodes.
  fs::remove(root_ / "head_still" / "summary.json");
  const RunResult resume = Run(cell + " --resume --out " + Quote((root_ / "head_still").string()));
  EXPECT_NE(resume.exit_code, 0);
  EXPECT_NE(resume.err.find("expert_mode \"head-still\" -> \"gaze-first\""), std::string::npos) << resume.err;
}

TEST_F(ExpertModeCommand, BadModeOrAModeForAnotherPolicyIsRefusedNamingIt) {
  const fs::path out = root_ / "out";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"eval --episodes 1 --expert-mode sideways", "'sideways'"},
      {"eval --episodes 1 --policy hold --expert-mode head-still",
       "--expert-mode applies to --policy expert only, got --policy hold"},
      {"demos --episodes 1 --cameras '' --expert-mode sideways", "'sideways'"},
  };
  for (const auto& [args, needle] : cases) {
    SCOPED_TRACE(args);
    const RunResult run = Run(args + " --quiet --out " + Quote(out.string()));
    EXPECT_NE(run.exit_code, 0);
    EXPECT_NE(run.err.find(needle), std::string::npos) << "stderr: " << run.err;
    EXPECT_FALSE(fs::exists(out)) << "a refused run writes nothing";
  }
}

}  // namespace
}  // namespace tavis::tools
