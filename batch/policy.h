// Batched policies: given the batch's current state (and, later, images), an action per env.
// Act is called per env inside the parallel step, so implementations keep per-env memory.
#pragma once

#include <memory>
#include <string>

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "kinematics/action.h"

namespace tavis::batch {

class Policy {
 public:
  virtual ~Policy() = default;
  virtual std::string name() const = 0;
  // Control ticks (60 Hz) an action is held for: 1 for privileged experts acting at the control
  // rate, 3 for learned policies at the 20 Hz policy rate.
  virtual int control_ticks_per_action() const = 0;
  virtual void Reset(const engine::WorldModel& model, const engine::BatchState& state, int env) = 0;
  virtual void Act(const engine::WorldModel& model, const engine::BatchState& state, int env,
                   kinematics::Action& action) = 0;
};

}  // namespace tavis::batch
