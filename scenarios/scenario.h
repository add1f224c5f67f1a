// A task: scene layout, split-dependent reset, success rule, prompt and a privileged scripted
// expert. Hooks act on one env; the VecEnv runs them over env ranges in parallel, so they must
// only touch that env's rows of the BatchState.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "kinematics/action.h"
#include "scenarios/split.h"

namespace tavis::scenarios {

// A privileged scripted policy for one task, stepping at the control rate. One instance serves
// a whole batch; per-env memory lives inside it, indexed by env.
class Expert {
 public:
  // Where the expert is looking: the object its head fixates (-1: none, or a scan point), and
  // whether the cameras it reads that object with have come to rest on it (the head settled; in
  // a peek, both wrist cameras at their peek poses). The visibility audit samples this.
  struct Gaze {
    int object = -1;
    bool settled = false;
  };

  virtual ~Expert() = default;
  virtual void Reset(const engine::WorldModel& model, const engine::BatchState& state, int env) = 0;
  virtual void Act(const engine::WorldModel& model, const engine::BatchState& state, int env,
                   kinematics::Action& action) = 0;
  virtual Gaze gaze(const engine::BatchState& state, int env) const = 0;
};

struct ScenarioDef {
  std::string name;   // e.g. "clutter-pick-cube"
  std::string suite;  // "tavis-head" or "tavis-hands"
  // Adds the task's objects and static parts to the world (once per batch).
  void (*layout)(engine::WorldModel& model) = nullptr;
  // Draws a new episode for `env` from its task stream (state.task_rng[env]): object poses,
  // enabled flags and colours, task variables.
  void (*reset)(const engine::WorldModel& model, Split split, engine::BatchState& state, int env) = nullptr;
  // Optional: advances the task's own clock once per control tick, after physics and before
  // evaluate (wait-then-act's light turning green).
  void (*update)(const engine::WorldModel& model, engine::BatchState& state, int env) = nullptr;
  // True on the first control tick the success rule holds.
  bool (*evaluate)(const engine::WorldModel& model, const engine::BatchState& state, int env) = nullptr;
  std::string (*prompt)(const engine::BatchState& state, int env) = nullptr;
  std::unique_ptr<Expert> (*make_expert)(const engine::WorldModel& model, int num_envs) = nullptr;
  // Cameras whose image the policy receives all black (the camera still moves).
  std::vector<std::string> black_cameras;
};

}  // namespace tavis::scenarios
