// A test policy: the task's scripted expert with each of its actions altered (grasps 6 cm too low,
// the grippers let go of the lifted target, the neck turned to a distractor before the grasp, the
// lifted target's hand following a script: lifted_target_takeover.h). The alteration sees the env,
// its observation and one byte of per-env memory (cleared when the env's episode starts), which it
// may set, e.g. once it has let go. Lock-step (not a PerEnvPolicy): the expert answers the batch,
// then every acting env's action is altered.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "batch/builtin_policies.h"
#include "batch/vec_env.h"

namespace tavis::testing {

class AlteredExpertPolicy : public batch::Policy {
 public:
  using Alteration =
      std::function<void(const batch::Observation& observation, int env, kinematics::Action& action, uint8_t& memory)>;

  AlteredExpertPolicy(const batch::VecEnv& vec_env, Alteration alter)
      : expert_(batch::MakeBuiltinPolicy("expert", vec_env.scenario(), vec_env.model(), vec_env.num_envs())),
        alter_(std::move(alter)),
        memory_(static_cast<std::size_t>(vec_env.num_envs()), 0) {}

  std::string name() const override { return "altered-expert"; }
  int control_ticks_per_action() const override { return 1; }
  void Reset(const batch::Observation& observation, const std::vector<uint8_t>& started) override {
    for (std::size_t env = 0; env < started.size(); ++env) memory_[env] = started[env] ? 0 : memory_[env];
    expert_->Reset(observation, started);
  }
  void Act(const batch::Observation& observation, const std::vector<uint8_t>& acting,
           batch::ActionBatch& actions) override {
    expert_->Act(observation, acting, actions);
    for (std::size_t env = 0; env < acting.size(); ++env) {
      if (acting[env]) alter_(observation, static_cast<int>(env), actions[env], memory_[env]);
    }
  }
  bool GaveUp(int env) const override { return expert_->GaveUp(env); }

 private:
  std::unique_ptr<batch::Policy> expert_;
  Alteration alter_;
  std::vector<uint8_t> memory_;
};

}  // namespace tavis::testing
