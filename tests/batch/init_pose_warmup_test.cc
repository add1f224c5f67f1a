#include "batch/init_pose_warmup.h"

#include <gtest/gtest.h>

#include <cmath>

#include "batch/vec_env.h"
#include "kinematics/forward_kinematics.h"
#include "scenarios/registry.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch {
namespace {

kinematics::RobotModel Robot(const char* name) { return tavis::testing::LoadRobot(name); }

TEST(InitPoseWarmup, ActionHasTheReferenceNoiseAroundTheRestPose) {
  const kinematics::RobotModel robot = Robot("gr1t2");
  double sum = 0.0, sum_sq = 0.0, pitch_sq = 0.0;
  constexpr int kDraws = 4000;
  for (int i = 0; i < kDraws; ++i) {
    engine::RandomStream rng(1, engine::RandomStreamId::kInitPose, static_cast<uint64_t>(i));
    const kinematics::Action a = InitPoseWarmupAction(robot, rng);
    const double dx = a[kinematics::action::kArmPosition[0]] - 0.3;
    sum += dx;
    sum_sq += dx * dx;
    pitch_sq += a[kinematics::action::kNeckPitch] * a[kinematics::action::kNeckPitch];
    EXPECT_EQ(a[kinematics::action::kNeckRoll], 0.0);
    EXPECT_EQ(a[kinematics::action::kGripper[0]], -1.0);
    EXPECT_EQ(a[kinematics::action::kGripper[1]], -1.0);
    EXPECT_NEAR(a[kinematics::action::kArmQuaternion[1]], 0.6400948, 1e-6);  // right rest w
  }
  EXPECT_NEAR(sum / kDraws, 0.0, 0.01);
  EXPECT_NEAR(std::sqrt(sum_sq / kDraws), kInitPosePositionNoise, 0.005);
  EXPECT_NEAR(std::sqrt(pitch_sq / kDraws), kInitPoseNeckNoise, 0.01);
}

TEST(InitPoseWarmup, ResetRunsTheWarmupThatCountsTowardTheEpisode) {
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario("clutter-pick-cube");
  const kinematics::RobotModel robot = Robot("gr1t2");
  VecEnv perturbed(BuildWorldModel(robot, scenario), scenario, scenarios::Split::kOodInitPose, 2, 4);
  VecEnv plain(BuildWorldModel(robot, scenario), scenario, scenarios::Split::kId, 1, 4);
  perturbed.ResetEnv(0, 0);
  perturbed.ResetEnv(1, 1);
  plain.ResetEnv(0, 0);
  EXPECT_EQ(perturbed.state().control_step[0], 30);  // ten 20 Hz steps
  EXPECT_EQ(plain.state().control_step[0], 0);
  // The arms and neck moved away from the default pose, differently per episode.
  double moved = 0.0, differ = 0.0;
  for (int j = 0; j < robot.num_joints(); ++j) {
    moved = std::max(moved, std::abs(perturbed.state().q_row(0)[j] - plain.state().q_row(0)[j]));
    differ = std::max(differ, std::abs(perturbed.state().q_row(0)[j] - perturbed.state().q_row(1)[j]));
  }
  EXPECT_GT(moved, 0.05);
  EXPECT_GT(differ, 0.01);
  // The same episode and seed gives the same warm-up.
  VecEnv again(BuildWorldModel(robot, scenario), scenario, scenarios::Split::kOodInitPose, 1, 4);
  again.ResetEnv(0, 1);
  for (int j = 0; j < robot.num_joints(); ++j) EXPECT_EQ(again.state().q_row(0)[j], perturbed.state().q_row(1)[j]);
}

}  // namespace
}  // namespace tavis::batch
