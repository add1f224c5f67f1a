// A test policy: the built-in hold policy with an alteration applied to the action of every env
// that acts (a NaN at one tick, a head that looks around).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "batch/builtin_policies.h"
#include "batch/vec_env.h"

namespace tavis::testing {

class AlteredHoldPolicy : public batch::Policy {
 public:
  using Alteration = std::function<void(const batch::Observation& observation, int env, kinematics::Action& action)>;

  AlteredHoldPolicy(const batch::VecEnv& vec_env, std::string name, int control_ticks_per_action, Alteration alter)
      : hold_(batch::MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), vec_env.num_envs())),
        name_(std::move(name)),
        control_ticks_per_action_(control_ticks_per_action),
        alter_(std::move(alter)) {}

  std::string name() const override { return name_; }
  int control_ticks_per_action() const override { return control_ticks_per_action_; }
  void Reset(const batch::Observation& observation, const std::vector<uint8_t>& started) override {
    hold_->Reset(observation, started);
  }
  void Act(const batch::Observation& observation, const std::vector<uint8_t>& acting,
           batch::ActionBatch& actions) override {
    hold_->Act(observation, acting, actions);
    for (int env = 0; env < observation.state.num_envs; ++env) {
      if (acting[env]) alter_(observation, env, actions[env]);
    }
  }

 private:
  std::unique_ptr<batch::Policy> hold_;
  std::string name_;
  int control_ticks_per_action_;
  Alteration alter_;
};

}  // namespace tavis::testing
