// Every task on every robot: reset, 50 control ticks of its expert (or of the hold policy where a
// task has no expert yet), nothing non-finite, the success rule evaluated every tick.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "batch/builtin_policies.h"
#include "batch/vec_env.h"
#include "scenarios/registry.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch {
namespace {

std::vector<std::string> TaskNames() {
  std::vector<std::string> names;
  for (const scenarios::ScenarioDef& scenario : scenarios::AllScenarios()) names.push_back(scenario.name);
  return names;
}

class TaskSmoke : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {};

TEST_P(TaskSmoke, FiftyTicksStayFiniteAndAreEvaluated) {
  const auto& [task, robot_name] = GetParam();
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario(task);
  const kinematics::RobotModel robot = tavis::testing::LoadRobot(robot_name);
  for (const scenarios::Split split :
       {scenarios::Split::kId, scenarios::Split::kOodSpatial, scenarios::Split::kOodInitPose}) {
    SCOPED_TRACE(scenarios::ToString(split));
    VecEnv vec_env(BuildWorldModel(robot, scenario), scenario, split, 1, 3);
    vec_env.ResetEnv(0, 2);
    const std::string policy_name = scenario.make_expert != nullptr ? "expert" : "hold";
    std::unique_ptr<Policy> policy = MakeBuiltinPolicy(policy_name, scenario, vec_env.model(), 1);
    const std::vector<const char*> prompts = {scenario.prompt(vec_env.state(), 0)};
    const Observation observation{vec_env.model(), vec_env.state(), nullptr, prompts};
    const std::vector<uint8_t> only_env = {1};
    policy->Reset(observation, only_env);
    EXPECT_FALSE(std::string(prompts[0]).empty());
    std::vector<kinematics::Action> actions(1);
    const int start = vec_env.state().control_step[0];
    for (int tick = 0; tick < 50; ++tick) {
      policy->Act(observation, only_env, actions);
      for (double value : actions[0]) ASSERT_TRUE(std::isfinite(value)) << "tick " << tick;
      vec_env.Step(actions);
      ASSERT_EQ(vec_env.state().end[0], engine::EpisodeEnd::kRunning)
          << "tick " << tick << ": " << engine::ToString(vec_env.state().end[0]);
    }
    EXPECT_EQ(vec_env.state().control_step[0], start + 50);
    for (double q : vec_env.state().q) EXPECT_TRUE(std::isfinite(q));
    for (double p : vec_env.state().object_pose) EXPECT_TRUE(std::isfinite(p));
    // Nothing is lifted in the first 50 ticks, so the success rule, evaluated, says no.
    EXPECT_FALSE(scenario.Succeeded(vec_env.state(), 0));
  }
}

INSTANTIATE_TEST_SUITE_P(AllTasks, TaskSmoke,
                         ::testing::Combine(::testing::ValuesIn(TaskNames()), ::testing::Values("gr1t2", "reachy2")),
                         [](const auto& test_param) {
                           std::string name = std::get<0>(test_param.param) + "_" + std::get<1>(test_param.param);
                           for (char& c : name) {
                             if (c == '-') c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace tavis::batch
