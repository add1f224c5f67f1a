// Policies built into the simulator: the task's scripted expert, a hold-still baseline and the
// replay of a recorded action trajectory.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "batch/policy.h"
#include "batch/policy_kinds.h"
#include "scenarios/scenario.h"

namespace tavis::batch {

// Names accepted by MakeBuiltinPolicy, for --help texts and errors.
const char* BuiltinPolicyNames();
// Throws std::invalid_argument naming an unknown policy (checked before any work is done).
void CheckBuiltinPolicyName(const std::string& name);

// The scenario's privileged scripted expert at the control rate. expert() exposes the scripted
// expert itself, e.g. where it is looking (the visibility audit).
//
// With decide_every = k > 1 the expert still plans on every control tick, but the action it
// commands changes only on ticks that are multiples of k and is held in between: a 60 Hz plan
// sampled and held at 60/k Hz. With k = 3 its demonstrations act as a 20 Hz policy acts, so a
// dataset's action rows, served back at 20 Hz, reproduce its episodes tick for tick.
class ExpertPolicy : public PerEnvPolicy {
 public:
  // Throws std::invalid_argument if the task has no scripted expert or decide_every < 1.
  ExpertPolicy(const scenarios::ScenarioDef& scenario, const engine::WorldModel& model, int num_envs,
               scenarios::expert::ExpertMode mode = scenarios::expert::ExpertMode::kGazeFirst, int decide_every = 1);
  std::string name() const override { return PolicyName(PolicyKind::kExpert); }
  int control_ticks_per_action() const override { return 1; }
  bool GaveUp(int env) const override { return expert_->gave_up(env); }
  const scenarios::Expert& expert() const { return *expert_; }

 private:
  void ResetEnv(const Observation& observation, int env) override;
  void ActEnv(const Observation& observation, int env, kinematics::Action& action) override;

  std::unique_ptr<scenarios::Expert> expert_;
  int decide_every_ = 1;
  std::vector<kinematics::Action> held_;  // (num_envs) the action commanded since the last decision
};

// "expert": ExpertPolicy, its head leading as `expert_mode` says.
// "hold": keeps the arms at their reset pose, head still, grippers open (a lower reference).
// "replay": plays the rows of `actions_file` (T x 19 CSV, one row per 20 Hz policy step, as
// `tavis galt` reads them) in every episode, holding the last row; given a folder (a served
// cell's DIR/actions), episode i plays its own episode_<i>.csv (a missing one stops the run,
// naming it).
// Throws std::invalid_argument naming an unknown policy, std::runtime_error naming the file and
// line of a malformed or non-finite action.
std::unique_ptr<Policy> MakeBuiltinPolicy(
    const std::string& name, const scenarios::ScenarioDef& scenario, const engine::WorldModel& model, int num_envs,
    const std::string& actions_file = "",
    scenarios::expert::ExpertMode expert_mode = scenarios::expert::ExpertMode::kGazeFirst);

}  // namespace tavis::batch
