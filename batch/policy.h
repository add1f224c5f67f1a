// Batched policies: given an observation of the batch (its state and, for policies that ask for
// cameras, the rendered images), an action per env. Act is called per env inside the parallel
// step, so implementations keep per-env memory.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "kinematics/action.h"
#include "render/image_batch.h"

namespace tavis::batch {

// What a policy sees at a control tick. Images are rendered only on policy ticks (control_step a
// multiple of PhysicsSettings::controls_per_policy(), 20 Hz) and only for the envs at one, so an
// env's images are current exactly when its control_step is a multiple of that.
struct Observation {
  const engine::BatchState& state;  // proprioception, and the privileged state experts use
  // The policy's cameras() in that order (ImageBatch camera i = cameras()[i]), at the configured
  // resolution; null when the policy asked for none.
  const render::ImageBatch* images = nullptr;
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
  virtual void Reset(const engine::WorldModel& model, const engine::BatchState& state, int env) = 0;
  virtual void Act(const engine::WorldModel& model, const Observation& observation, int env,
                   kinematics::Action& action) = 0;
};

}  // namespace tavis::batch
