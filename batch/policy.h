// Batched policies. At a control tick the episode driver hands the policy the observation of the
// whole batch and the envs that act now; the policy fills their actions at once (a served policy
// sends one request for all of them, a per-env policy runs them in parallel). An env that does
// not act holds its previous action.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "batch/proprioception.h"
#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "kinematics/action.h"
#include "render/image_batch.h"

namespace tavis::batch {

// What a policy sees of the batch at a control tick: the observation contract (docs/observation.md:
// cameras, observation.state, end-effector poses, prompt, step index). Images are
// rendered only on policy ticks (control_step a multiple of PhysicsSettings::controls_per_policy(),
// 20 Hz) and only for the envs at one, so an env's images are current exactly when its
// control_step is a multiple of that.
struct Observation {
  const engine::WorldModel& model;
  const engine::BatchState& state;  // proprioception, the step index, and the privileged state experts use
  // The policy's cameras() in that order (ImageBatch camera i = cameras()[i]), at the configured
  // resolution; null when the policy asked for none.
  const render::ImageBatch* images = nullptr;
  // (num_envs) each env's instruction for its episode (the task's prompt), null for idle slots.
  const std::vector<const char*>& prompts;
  // observation.state and the end-effector poses; current, like the images, for the envs at a
  // policy tick that act now. Null when not computed (policies driven outside the episode driver).
  const ProprioceptionBatch* proprioception = nullptr;
};

using ActionBatch = std::vector<kinematics::Action>;  // (num_envs)

// An env a policy could not act for at this tick (a served reply with the wrong shape or dtype).
// The driver ends that env's episode as invalid_action with the reason; the other envs go on.
struct PolicyFault {
  int env = 0;
  std::string reason;
};

class Policy {
 public:
  virtual ~Policy() = default;
  virtual std::string name() const = 0;
  // Control ticks (60 Hz) an action is held for: 1 for privileged experts acting at the control
  // rate, 3 for learned policies at the 20 Hz policy rate. A policy with cameras must act on
  // policy ticks only (a multiple of controls_per_policy), where its images are current.
  virtual int control_ticks_per_action() const = 0;
  // Cameras whose RGB the policy consumes, from batch::SceneCameraNames() (head, fixed,
  // left_wrist, right_wrist). None by default: nothing is rendered for such a policy.
  virtual std::vector<std::string> cameras() const { return {}; }
  // New episodes started in the envs with started[env] != 0 (their state is the reset's).
  virtual void Reset(const Observation& observation, const std::vector<uint8_t>& started) = 0;
  // Writes actions[env] for every env with acting[env] != 0; leaves the other entries alone.
  // An env it cannot act for is reported by TakeFaults instead.
  virtual void Act(const Observation& observation, const std::vector<uint8_t>& acting, ActionBatch& actions) = 0;
  // Appends the faults of the last Act to `faults` and forgets them. Policies whose every action
  // is well-formed have none; a non-finite or absurd action needs no fault (the step's own check
  // ends its episode).
  virtual void TakeFaults(std::vector<PolicyFault>& /*faults*/) {}
  // True once the policy has nothing left to try in env's running episode (the scripted expert
  // out of grasp attempts): the driver ends the episode as gave_up after the tick's step rather
  // than hold it to the time-out. Asked after every step; false by default.
  virtual bool GaveUp(int /*env*/) const { return false; }
};

// A policy that decides each env on its own (the built-in ones): the batch calls run the envs
// in parallel.
class PerEnvPolicy : public Policy {
 public:
  void Reset(const Observation& observation, const std::vector<uint8_t>& started) final;
  void Act(const Observation& observation, const std::vector<uint8_t>& acting, ActionBatch& actions) final;
  // What Reset and Act do for one env, on the calling thread. Calls for distinct envs may run
  // concurrently (the episode driver's per-slot schedule).
  void ResetOne(const Observation& observation, int env);
  void ActOne(const Observation& observation, int env, kinematics::Action& action);
  // Per-env timing for profiles of `num_envs` envs: TakeEnvSeconds returns the CPU time ResetEnv
  // and ActEnv spent on the env since the last call and starts again from zero. Off by default.
  void EnableEnvTiming(bool enabled, int num_envs);
  double TakeEnvSeconds(int env);

 protected:
  virtual void ResetEnv(const Observation& observation, int env) = 0;
  virtual void ActEnv(const Observation& observation, int env, kinematics::Action& action) = 0;

 private:
  template <typename Body>
  void Timed(int env, Body&& body);

  bool env_timing_ = false;
  std::vector<int64_t> env_nanoseconds_;
};

}  // namespace tavis::batch
