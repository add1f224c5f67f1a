#include "scenarios/clutter_pick_lift.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "scenarios/registry.h"
#include "tests/support/robot_loading.h"

namespace tavis::scenarios {
namespace {

TEST(ClutterPickLift, EveryObjectStaysAndThePromptNamesTheTarget) {
  engine::WorldModel model;
  model.robot = tavis::testing::LoadRobot("gr1t2");
  const ScenarioDef& scenario = FindScenario("clutter-pick-lift");
  scenario.layout(model);
  ASSERT_EQ(model.num_objects(), 5);
  // Words naming each object in its phrasings, and in no other object's.
  const std::vector<std::vector<std::string>> kNames = {{"soup"}, {"meat", "spam"}, {"tuna"}, {"gelatin"}, {"pudding"}};
  engine::BatchState state;
  state.Allocate(1, model.robot.num_joints(), model.num_objects());
  std::set<std::string> prompts;
  std::set<int> targets;
  for (uint64_t episode = 0; episode < 200; ++episode) {
    state.task_rng[0] = engine::RandomStream(3, engine::RandomStreamId::kTask, episode);
    scenario.reset(model, Split::kOodSpatial, state, 0);
    for (int object = 0; object < 5; ++object) {
      EXPECT_EQ(state.object_enabled_at(0, object), 1);
      EXPECT_LE(std::abs(state.ObjectPosition(0, object).y()), 0.35);
    }
    const int target = state.target(0);
    ASSERT_GE(target, 0);
    ASSERT_LT(target, 5);
    const std::string prompt = scenario.prompt(state, 0);
    bool named = false;
    for (const std::string& word : kNames[static_cast<std::size_t>(target)])
      named |= prompt.find(word) != std::string::npos;
    EXPECT_TRUE(named) << "target " << target << ": " << prompt;
    prompts.insert(prompt);
    targets.insert(target);
  }
  EXPECT_EQ(targets.size(), 5u);
  EXPECT_EQ(prompts.size(), 15u);
}

TEST(ClutterPickLift, SuccessFollowsTheTargetOnly) {
  engine::WorldModel model;
  FindScenario("clutter-pick-lift").layout(model);
  engine::BatchState state;
  state.Allocate(1, 17, model.num_objects());
  state.task[0].target = 3;
  state.object_pose_row(0, 0)[2] = 1.3;  // a non-target object up high does not count
  state.object_pose_row(0, 3)[2] = 1.0;
  EXPECT_FALSE(FindScenario("clutter-pick-lift").Succeeded(state, 0));
  state.object_pose_row(0, 3)[2] = 1.21;
  EXPECT_TRUE(FindScenario("clutter-pick-lift").Succeeded(state, 0));
}

TEST(BlockedClutterPickCube, IsClutterPickCubeWithABlackHeadImage) {
  const ScenarioDef& blocked = FindScenario("blocked-clutter-pick-cube");
  const ScenarioDef& plain = FindScenario("clutter-pick-cube");
  EXPECT_EQ(blocked.suite, Suite::kTavisHands);
  EXPECT_EQ(blocked.black_cameras, std::vector<std::string>{"head"});
  EXPECT_TRUE(plain.black_cameras.empty());
  EXPECT_EQ(blocked.reset, plain.reset);
  EXPECT_EQ(blocked.success.kind, plain.success.kind);
  EXPECT_EQ(blocked.success.threshold_m, plain.success.threshold_m);
}

}  // namespace
}  // namespace tavis::scenarios
