#include "batch/vec_env.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "batch/builtin_policies.h"
#include "scenarios/registry.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch {
namespace {

constexpr const char* kTask = "clutter-pick-cube";

engine::WorldModel Model(const std::string& robot_name, double episode_length_s) {
  const kinematics::RobotModel robot = tavis::testing::LoadRobot(robot_name);
  engine::WorldModel model = BuildWorldModel(robot, scenarios::FindScenario(kTask));
  model.physics.episode_length_s = episode_length_s;
  return model;
}

// The "hold" policy's action for every env after its reset: arms at the reset pose, grippers open.
std::vector<kinematics::Action> HoldActions(const VecEnv& vec_env) {
  std::unique_ptr<Policy> hold = MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), vec_env.num_envs());
  const std::vector<const char*> prompts(static_cast<std::size_t>(vec_env.num_envs()), nullptr);
  const Observation observation{vec_env.model(), vec_env.state(), nullptr, prompts};
  const std::vector<uint8_t> every_env(static_cast<std::size_t>(vec_env.num_envs()), 1);
  std::vector<kinematics::Action> actions(vec_env.num_envs());
  hold->Reset(observation, every_env);
  hold->Act(observation, every_env, actions);
  return actions;
}

TEST(VecEnv, NonFiniteActionEndsOnlyThatEpisodeAndReportsTheEntry) {
  VecEnv vec_env(Model("gr1t2", 2.0), scenarios::FindScenario(kTask), scenarios::Split::kId, 3, 7);
  for (int slot = 0; slot < 3; ++slot) vec_env.ResetEnv(slot, slot);
  std::vector<kinematics::Action> actions = HoldActions(vec_env);
  actions[0][kinematics::action::kNeckPitch] = std::numeric_limits<double>::quiet_NaN();
  actions[2][kinematics::action::kGripper[1]] = -std::numeric_limits<double>::infinity();
  actions[2][kinematics::action::kArmPosition[0] + 1] = std::numeric_limits<double>::infinity();

  ASSERT_NO_THROW(vec_env.Step(actions));
  const engine::BatchState& state = vec_env.state();
  EXPECT_EQ(state.end[0], engine::EpisodeEnd::kInvalidAction);
  EXPECT_EQ(state.invalid_action[0].entry, kinematics::action::kNeckPitch);
  EXPECT_TRUE(std::isnan(state.invalid_action[0].value));
  EXPECT_EQ(state.control_step[0], 0) << "an invalid action must not be simulated";

  EXPECT_EQ(state.end[1], engine::EpisodeEnd::kRunning);
  EXPECT_EQ(state.control_step[1], 1);

  // The first bad entry is reported, not the last one.
  EXPECT_EQ(state.end[2], engine::EpisodeEnd::kInvalidAction);
  EXPECT_EQ(state.invalid_action[2].entry, kinematics::action::kArmPosition[0] + 1);
  EXPECT_EQ(state.invalid_action[2].value, std::numeric_limits<double>::infinity());

  // Ended episodes are not stepped again, even with a good action.
  actions = HoldActions(vec_env);
  ASSERT_NO_THROW(vec_env.Step(actions));
  EXPECT_EQ(state.end[0], engine::EpisodeEnd::kInvalidAction);
  EXPECT_EQ(state.control_step[0], 0);
  EXPECT_EQ(state.control_step[1], 2);

  // A reset clears the invalid-action report.
  vec_env.ResetEnv(0, 3);
  EXPECT_EQ(state.end[0], engine::EpisodeEnd::kRunning);
  EXPECT_EQ(state.invalid_action[0].entry, -1);
}

// A slot's next episode starts with its grippers commanded open whatever the previous episode
// left: the stage check reads the command at the first tick, so a leftover closed command made
// `target_grasped` depend on which episode the slot ran before (and on thread timing per slot).
TEST(VecEnv, AResetCommandsTheGrippersOpenWhateverThePreviousEpisodeLeft) {
  VecEnv vec_env(Model("reachy2", 2.0), scenarios::FindScenario(kTask), scenarios::Split::kId, 2, 7);
  for (int slot = 0; slot < 2; ++slot) vec_env.ResetEnv(slot, slot);
  std::vector<kinematics::Action> actions = HoldActions(vec_env);
  for (kinematics::Action& action : actions) {
    for (int hand = 0; hand < 2; ++hand) action[kinematics::action::kGripper[hand]] = 1.0;  // close
  }
  vec_env.Step(actions);
  const engine::BatchState& state = vec_env.state();
  ASSERT_EQ(state.gripper_command_row(0)[0], 1.0);
  ASSERT_EQ(state.gripper_command_row(1)[1], 1.0);
  vec_env.ResetEnv(0, 2);
  EXPECT_EQ(state.gripper_command_row(0)[0], -1.0);
  EXPECT_EQ(state.gripper_command_row(0)[1], -1.0);
  EXPECT_EQ(state.gripper_command_row(1)[1], 1.0) << "only the reset slot is touched";
}

TEST(VecEnv, HoldKeepsEpisodesRunningUntilTheTimeOut) {
  for (const char* robot_name : {"gr1t2", "reachy2"}) {
    SCOPED_TRACE(robot_name);
    VecEnv vec_env(Model(robot_name, 2.0), scenarios::FindScenario(kTask), scenarios::Split::kId, 2, 11);
    const int max_ticks = vec_env.model().physics.max_control_steps();
    ASSERT_EQ(max_ticks, 120);
    const engine::BatchState& state = vec_env.state();
    const int joints = state.num_joints;
    for (int slot = 0; slot < 2; ++slot) vec_env.ResetEnv(slot, slot);
    const std::vector<double> q_reset(state.q.begin(), state.q.end());
    const std::vector<kinematics::Action> actions = HoldActions(vec_env);

    double max_arm_drift = 0.0;
    for (int tick = 1; tick <= max_ticks; ++tick) {
      ASSERT_NO_THROW(vec_env.Step(actions));
      for (int slot = 0; slot < 2; ++slot) {
        ASSERT_EQ(state.control_step[slot], tick) << "slot " << slot;
        const engine::EpisodeEnd expected =
            tick < max_ticks ? engine::EpisodeEnd::kRunning : engine::EpisodeEnd::kTimeOut;
        ASSERT_EQ(state.end[slot], expected)
            << "slot " << slot << ", tick " << tick << ": " << engine::ToString(state.end[slot]);
        for (int j = 0; j < joints; ++j) {
          const double q = state.q_row(slot)[j];
          ASSERT_TRUE(std::isfinite(q)) << "slot " << slot << ", joint " << j << ", tick " << tick;
        }
        for (kinematics::Side side : kinematics::kSides) {
          for (int joint : vec_env.model().robot.arm(side).joints) {
            const size_t k = static_cast<size_t>(slot) * joints + joint;
            max_arm_drift = std::max(max_arm_drift, std::abs(state.q[k] - q_reset[k]));
          }
        }
      }
    }
    // Holding the reset pose: the arms stay where they started.
    EXPECT_LT(max_arm_drift, 0.02);

    // Once timed out, further steps change nothing.
    const std::vector<double> q_end(state.q.begin(), state.q.end());
    vec_env.Step(actions);
    EXPECT_EQ(state.control_step[0], max_ticks);
    EXPECT_EQ(state.q, q_end);
  }
}

// Stage timing sees where the tick's time goes and changes nothing of what is simulated.
TEST(VecEnv, StageTimingReportsEachStageAndLeavesTheResultsAlone) {
  std::vector<double> q_by_timing[2];
  for (const bool timed : {false, true}) {
    VecEnv vec_env(Model("gr1t2", 2.0), scenarios::FindScenario(kTask), scenarios::Split::kOodInitPose, 2, 7);
    vec_env.EnableStageTiming(timed);
    for (int slot = 0; slot < 2; ++slot) vec_env.ResetEnv(slot, slot);
    const std::vector<kinematics::Action> actions = HoldActions(vec_env);
    for (int tick = 0; tick < 6; ++tick) vec_env.Step(actions);
    q_by_timing[timed ? 1 : 0] = vec_env.state().q;
    const std::array<double, kNumStages> seconds = vec_env.stage_seconds();
    for (const Stage stage : {Stage::kApplyActions, Stage::kStepPhysics, Stage::kServoNeck, Stage::kUpdateTask,
                              Stage::kEndEpisodes, Stage::kReset}) {
      if (timed) {
        EXPECT_GT(seconds[static_cast<int>(stage)], 0.0) << ToString(stage);
      } else {
        EXPECT_EQ(seconds[static_cast<int>(stage)], 0.0) << ToString(stage);
      }
    }
    EXPECT_EQ(seconds[static_cast<int>(Stage::kRender)], 0.0) << "nothing renders without cameras";
    if (timed) {
      EXPECT_GT(seconds[static_cast<int>(Stage::kStepPhysics)], seconds[static_cast<int>(Stage::kServoNeck)])
          << "ODE's substeps cost more than the kinematic neck";
    }
  }
  EXPECT_EQ(q_by_timing[0], q_by_timing[1]);
}

}  // namespace
}  // namespace tavis::batch
