// Follows one episode through its task's stages (stage.h): shown the state at every control tick,
// it keeps the first tick each stage was reached. One instance per env slot; it allocates nothing
// per tick.
#pragma once

#include <array>
#include <vector>

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "scenarios/scenario.h"

namespace tavis::scenarios {

class StageProgress {
 public:
  // Throws std::invalid_argument naming a cue a stage declares that the world does not hold.
  StageProgress(const ScenarioDef& scenario, const engine::WorldModel& model);

  // A new episode in `env`: nothing reached yet.
  void Start();
  // The env's state at control tick state.control_step[env]: stages reached now that were not
  // before are given this tick.
  void Observe(const engine::BatchState& state, int env);

  // Per declared stage (ScenarioDef::stages order): the control tick it was first reached, -1
  // if not (yet).
  const std::vector<int>& first_ticks() const { return first_ticks_; }

 private:
  bool Reached(const StageDef& stage, int cue_object, double best_gaze_error, const engine::BatchState& state,
               int env) const;
  // Distance from a hand's tool centre point to the target's bounding box, per hand.
  std::array<double, 2> HandDistances(const engine::BatchState& state, int env) const;
  // A hand closing on something with its tool centre point within reach_m of the target's box.
  bool Grasping(double reach_m, const engine::BatchState& state, int env) const;

  const ScenarioDef& scenario_;
  const engine::WorldModel& model_;
  std::vector<int> cue_objects_;  // per stage: the cue's object index, -1 for other kinds
  std::vector<int> first_ticks_;
  // Per stage: for a cue, the smallest gaze error the neck's limits allow (rad), found at the
  // episode's first tick; 0 for other kinds.
  std::vector<double> best_gaze_error_;
  double furthest_back_ = 0.0;  // the target's lowest z (lift) or largest x (pull-out) so far
  bool seen_target_ = false;
};

}  // namespace tavis::scenarios
