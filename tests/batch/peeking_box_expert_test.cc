// The peeking-box expert looks into both sides of the box with the wrist cameras before it
// reaches in through the open side, and takes the object out.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "batch/vec_env.h"
#include "scenarios/expert/arm_planner.h"
#include "scenarios/registry.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch {
namespace {

TEST(PeekingBoxExpert, PeeksIntoBothSidesThenLiftsTheObjectOut) {
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario("peeking-box");
  const kinematics::RobotModel robot = tavis::testing::LoadRobot("gr1t2");
  VecEnv vec_env(BuildWorldModel(robot, scenario), scenario, scenarios::Split::kId, 1, 0);
  std::unique_ptr<scenarios::Expert> expert =
      scenario.make_expert(vec_env.model(), 1, scenarios::expert::ExpertMode::kGazeFirst);
  constexpr int kEpisode = 1;  // an episode the expert solves
  vec_env.ResetEnv(0, kEpisode);
  expert->Reset(vec_env.model(), vec_env.state(), 0);
  // A wrist peeks when its pads hang at the object's height just outside its own side of the
  // box (beyond the side walls at 0.078), level with the box's middle; at the reset pose they
  // are higher and nearer the robot.
  const int back_wall = vec_env.model().ObjectIndex("box_wall_back");
  const int front_wall = vec_env.model().ObjectIndex("box_wall_front");
  std::vector<kinematics::Action> actions(1);
  bool closed = false;
  std::array<bool, 2> peeked{false, false};
  for (int tick = 0; tick < 1200 && vec_env.state().end[0] == engine::EpisodeEnd::kRunning; ++tick) {
    expert->Act(vec_env.model(), vec_env.state(), 0, actions[0]);
    for (const int gripper : kinematics::action::kGripper) closed = closed || actions[0][gripper] > 0.0;
    const Vec3 box =
        0.5 * (vec_env.state().ObjectPosition(0, back_wall) + vec_env.state().ObjectPosition(0, front_wall));
    for (const kinematics::Side side : kinematics::kSides) {
      RigidTransform X_ik = scenarios::expert::HandPoseCanonical(robot, side, vec_env.state().q_row(0));
      X_ik.translation() = robot.CanonicalToBase(X_ik.translation()) + robot.root_world;
      const Vec3 pads = X_ik * robot.gripper.pad_center;
      const double outward = side == kinematics::Side::kLeft ? 1.0 : -1.0;
      const double beside = outward * (pads.y() - box.y());
      if (!closed && beside > 0.12 && beside < 0.35 && std::abs(pads.x() - box.x()) < 0.1 && pads.z() < 1.15) {
        peeked[static_cast<std::size_t>(kinematics::Index(side))] = true;
      }
    }
    vec_env.Step(actions);
  }
  EXPECT_TRUE(peeked[0]) << "the left hand never went to the left side of the box";
  EXPECT_TRUE(peeked[1]) << "the right hand never went to the right side of the box";
  EXPECT_EQ(vec_env.state().end[0], engine::EpisodeEnd::kSuccess);
}

}  // namespace
}  // namespace tavis::batch
