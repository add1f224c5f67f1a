#include "batch/vec_env.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "batch/builtin_policies.h"
#include "configs/robot_config.h"
#include "scenarios/registry.h"

namespace tavis::batch {
namespace {

constexpr const char* kTask = "clutter-pick-cube";

engine::WorldModel Model(const std::string& robot_name, double episode_length_s) {
  const kinematics::RobotModel robot =
      configs::LoadRobotModel(configs::RobotConfigPath(TAVIS_CONFIG_DIR, robot_name));
  engine::WorldModel model = BuildWorldModel(robot, scenarios::FindScenario(kTask));
  model.physics.episode_length_s = episode_length_s;
  return model;
}

// The "hold" policy's action for every env after its reset: arms at the reset pose, grippers open.
std::vector<kinematics::Action> HoldActions(const VecEnv& env) {
  std::unique_ptr<Policy> hold = MakeBuiltinPolicy("hold", env.scenario(), env.model(), env.num_envs());
  std::vector<kinematics::Action> actions(env.num_envs());
  for (int slot = 0; slot < env.num_envs(); ++slot) {
    hold->Reset(env.model(), env.state(), slot);
    hold->Act(env.model(), Observation{env.state()}, slot, actions[slot]);
  }
  return actions;
}

TEST(VecEnv, NonFiniteActionEndsOnlyThatEpisodeAndReportsTheEntry) {
  VecEnv env(Model("gr1t2", 2.0), scenarios::FindScenario(kTask), scenarios::Split::kId, 3, 7);
  for (int slot = 0; slot < 3; ++slot) env.ResetEnv(slot, slot);
  std::vector<kinematics::Action> actions = HoldActions(env);
  actions[0][kinematics::action::kNeckPitch] = std::numeric_limits<double>::quiet_NaN();
  actions[2][kinematics::action::kGripper[1]] = -std::numeric_limits<double>::infinity();
  actions[2][kinematics::action::kArmPosition[0] + 1] = std::numeric_limits<double>::infinity();

  ASSERT_NO_THROW(env.Step(actions));
  const engine::BatchState& state = env.state();
  EXPECT_EQ(state.end[0], engine::EpisodeEnd::kInvalidAction);
  EXPECT_EQ(env.invalid_action_index(0), kinematics::action::kNeckPitch);
  EXPECT_TRUE(std::isnan(env.invalid_action_value(0)));
  EXPECT_EQ(state.control_step[0], 0) << "an invalid action must not be simulated";

  EXPECT_EQ(state.end[1], engine::EpisodeEnd::kRunning);
  EXPECT_EQ(state.control_step[1], 1);

  // The first bad entry is reported, not the last one.
  EXPECT_EQ(state.end[2], engine::EpisodeEnd::kInvalidAction);
  EXPECT_EQ(env.invalid_action_index(2), kinematics::action::kArmPosition[0] + 1);
  EXPECT_EQ(env.invalid_action_value(2), std::numeric_limits<double>::infinity());

  // Ended episodes are not stepped again, even with a good action.
  actions = HoldActions(env);
  ASSERT_NO_THROW(env.Step(actions));
  EXPECT_EQ(state.end[0], engine::EpisodeEnd::kInvalidAction);
  EXPECT_EQ(state.control_step[0], 0);
  EXPECT_EQ(state.control_step[1], 2);

  // A reset clears the invalid-action report.
  env.ResetEnv(0, 3);
  EXPECT_EQ(state.end[0], engine::EpisodeEnd::kRunning);
  EXPECT_EQ(env.invalid_action_index(0), -1);
}

TEST(VecEnv, HoldKeepsEpisodesRunningUntilTheTimeOut) {
  for (const char* robot_name : {"gr1t2", "reachy2"}) {
    SCOPED_TRACE(robot_name);
    VecEnv env(Model(robot_name, 2.0), scenarios::FindScenario(kTask), scenarios::Split::kId, 2, 11);
    const int max_ticks = env.model().physics.max_control_steps();
    ASSERT_EQ(max_ticks, 120);
    const engine::BatchState& state = env.state();
    const int joints = state.num_joints;
    for (int slot = 0; slot < 2; ++slot) env.ResetEnv(slot, slot);
    const std::vector<double> q_reset(state.q.begin(), state.q.end());
    const std::vector<kinematics::Action> actions = HoldActions(env);

    double max_arm_drift = 0.0;
    for (int tick = 1; tick <= max_ticks; ++tick) {
      ASSERT_NO_THROW(env.Step(actions));
      for (int slot = 0; slot < 2; ++slot) {
        ASSERT_EQ(state.control_step[slot], tick) << "slot " << slot;
        const engine::EpisodeEnd expected = tick < max_ticks ? engine::EpisodeEnd::kRunning : engine::EpisodeEnd::kTimeOut;
        ASSERT_EQ(state.end[slot], expected) << "slot " << slot << ", tick " << tick << ": "
                                             << engine::ToString(state.end[slot]);
        for (int j = 0; j < joints; ++j) {
          const double q = state.q_row(slot)[j];
          ASSERT_TRUE(std::isfinite(q)) << "slot " << slot << ", joint " << j << ", tick " << tick;
        }
        for (kinematics::Side side : kinematics::kSides) {
          for (int joint : env.model().robot.arm(side).joints) {
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
    env.Step(actions);
    EXPECT_EQ(state.control_step[0], max_ticks);
    EXPECT_EQ(state.q, q_end);
  }
}

}  // namespace
}  // namespace tavis::batch
