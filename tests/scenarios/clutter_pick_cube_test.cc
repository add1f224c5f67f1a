#include "scenarios/clutter_pick_cube.h"

#include <gtest/gtest.h>

#include "scenarios/expert/gaze.h"
#include "scenarios/registry.h"
#include "tests/support/robot_loading.h"

namespace tavis::scenarios {
namespace {

engine::WorldModel World() {
  engine::WorldModel model;
  model.robot = tavis::testing::LoadRobot("gr1t2");
  FindScenario("clutter-pick-cube").layout(model);
  return model;
}

TEST(ClutterPickCube, ResetHidesExactlyOneYcbObjectAndTargetsTheCube) {
  const engine::WorldModel model = World();
  const ScenarioDef& scenario = FindScenario("clutter-pick-cube");
  engine::BatchState state;
  state.Allocate(1, model.robot.num_joints(), model.num_objects());
  for (uint64_t episode = 0; episode < 50; ++episode) {
    state.task_rng[0] = engine::RandomStream(1, engine::RandomStreamId::kTask, episode);
    scenario.reset(model, Split::kId, state, 0);
    int enabled = 0;
    for (int object = 0; object < 5; ++object) enabled += state.object_enabled_at(0, object);
    EXPECT_EQ(enabled, 4);
    EXPECT_EQ(state.object_enabled_at(0, 5), 1);
    EXPECT_EQ(state.target(0), 5);
    const Vec3 cube = state.ObjectPosition(0, 5);
    EXPECT_GE(cube.x(), 0.35);
    EXPECT_LE(cube.x(), 0.45);
    EXPECT_LE(std::abs(cube.y()), 0.25);
  }
}

TEST(ClutterPickCube, SuccessNeedsHeightAndLowSpeed) {
  const engine::WorldModel model = World();
  const ScenarioDef& scenario = FindScenario("clutter-pick-cube");
  engine::BatchState state;
  state.Allocate(1, model.robot.num_joints(), model.num_objects());
  state.task[0].target = 5;  // the red cube, as every reset sets it
  double* pose = state.object_pose_row(0, 5);
  pose[2] = 1.19;
  EXPECT_FALSE(scenario.Succeeded(state, 0));
  pose[2] = 1.21;
  EXPECT_TRUE(scenario.Succeeded(state, 0));
  state.object_velocity[5 * engine::kObjectVelocitySize + 2] = 1.5;
  EXPECT_FALSE(scenario.Succeeded(state, 0));
  EXPECT_STREQ(scenario.prompt(state, 0), "Find the red cube and pick it up.");
}

TEST(Registry, UnknownTaskNamesItAndTheKnownOnes) {
  try {
    FindScenario("clutter-pick-cub");
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown task 'clutter-pick-cub'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("clutter-pick-cube"), std::string::npos);
  }
  EXPECT_THROW(ParseSplit("ood"), std::invalid_argument);
  EXPECT_EQ(ParseSplit("ood_spatial"), Split::kOodSpatial);
}

TEST(Gaze, FixationCentresTheTargetInTheHeadCamera) {
  for (const char* name : {"gr1t2", "reachy2"}) {
    const kinematics::RobotModel robot = tavis::testing::LoadRobot(name);
    std::vector<double> q = robot.DefaultPositions();
    // Reachy2's neck pitches at most 30 degrees down: a far table point stays within reach.
    const Vec3 target = robot.name == "reachy2" ? Vec3(0.75, -0.18, 1.03) : Vec3(0.42, -0.18, 1.03);
    const auto neck = expert::FixationNeckAngles(robot, q.data(), target);
    for (int i = 0; i < 3; ++i) q[robot.neck_joints[i]] = neck[i];
    EXPECT_LT(expert::GazeError(robot, q.data(), target), 0.01) << name;
    EXPECT_GT(expert::GazeError(robot, robot.DefaultPositions().data(), target), 0.3) << name << ": should need a turn";
  }
}

}  // namespace
}  // namespace tavis::scenarios
