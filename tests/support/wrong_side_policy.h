// A test policy that reaches the wrong side: the task's scripted expert, shown a world in which
// the episode's target is the enabled object on the other side of the robot (y of the opposite
// sign). It picks that object, so it never comes near the real target. Lock-step (not a
// PerEnvPolicy): it copies the whole batch state while no env steps.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "batch/policy.h"
#include "batch/vec_env.h"

namespace tavis::testing {

class WrongSidePolicy : public batch::Policy {
 public:
  explicit WrongSidePolicy(const batch::VecEnv& vec_env)
      : expert_(vec_env.scenario().make_expert(vec_env.model(), vec_env.num_envs(),
                                               scenarios::expert::ExpertMode::kGazeFirst)) {}

  std::string name() const override { return "wrong-side"; }
  int control_ticks_per_action() const override { return 1; }
  void Reset(const batch::Observation& observation, const std::vector<uint8_t>& started) override {
    const engine::BatchState& swapped = Swapped(observation);
    for (int env = 0; env < swapped.num_envs; ++env) {
      if (started[env]) expert_->Reset(observation.model, swapped, env);
    }
  }
  void Act(const batch::Observation& observation, const std::vector<uint8_t>& acting,
           batch::ActionBatch& actions) override {
    const engine::BatchState& swapped = Swapped(observation);
    for (int env = 0; env < swapped.num_envs; ++env) {
      if (acting[env]) expert_->Act(observation.model, swapped, env, actions[env]);
    }
  }

  // The object each env's policy went for at its last Reset or Act (-1: none found).
  const std::vector<int>& wrong_targets() const { return wrong_targets_; }

 private:
  // The state with each running env's target replaced by the enabled dynamic object on the
  // other side (y sign) from the real one.
  const engine::BatchState& Swapped(const batch::Observation& observation) {
    swapped_ = observation.state;
    wrong_targets_.assign(static_cast<std::size_t>(swapped_.num_envs), -1);
    for (int env = 0; env < swapped_.num_envs; ++env) {
      if (swapped_.episode[env] < 0) continue;
      const int target = swapped_.target(env);
      const double target_y = swapped_.ObjectPosition(env, target).y();
      for (int object = 0; object < swapped_.num_objects; ++object) {
        const bool dynamic =
            observation.model.objects[static_cast<std::size_t>(object)].motion == engine::ObjectMotion::kDynamic;
        if (object == target || !dynamic || !swapped_.object_enabled_at(env, object)) continue;
        if (swapped_.ObjectPosition(env, object).y() * target_y < 0.0) {
          swapped_.task[env].target = object;
          wrong_targets_[static_cast<std::size_t>(env)] = object;
          break;
        }
      }
    }
    return swapped_;
  }

  std::unique_ptr<scenarios::Expert> expert_;
  engine::BatchState swapped_;
  std::vector<int> wrong_targets_;
};

}  // namespace tavis::testing
