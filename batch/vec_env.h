// N envs of one task stepped together. A control tick is a short pipeline of stages, each a
// function over an env range run by tbb::parallel_for: apply actions (validate, IK, neck and
// gripper targets), physics substeps, neck servo, task evaluation. Episodes are keyed by their
// index: an episode's randomness comes from (seed, episode), so results do not depend on the
// thread count, on the number of env slots, or on which slot ran which episode.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/batch_state.h"
#include "engine/physics_world.h"
#include "engine/world_model.h"
#include "kinematics/action.h"
#include "scenarios/scenario.h"

namespace tavis::batch {

// Builds the world of a task for a robot: the robot model plus the scenario's layout.
engine::WorldModel BuildWorldModel(const kinematics::RobotModel& robot, const scenarios::ScenarioDef& scenario);

class VecEnv {
 public:
  VecEnv(engine::WorldModel model, const scenarios::ScenarioDef& scenario, scenarios::Split split, int num_envs,
         uint64_t seed);
  ~VecEnv();

  int num_envs() const { return state_.num_envs; }
  const engine::WorldModel& model() const { return model_; }
  const engine::BatchState& state() const { return state_; }
  const scenarios::ScenarioDef& scenario() const { return scenario_; }

  // Starts episode `episode` in slot `env`: default robot pose, the task's random layout.
  void ResetEnv(int env, int64_t episode);
  // Marks a slot idle: it is skipped by Step until reset again.
  void Release(int env) { state_.episode[env] = -1; }

  // One control tick for every running env (episode >= 0 and end == kRunning), with
  // actions[env]. Ends episodes on success, time-out, blow-up or an invalid action.
  void Step(const std::vector<kinematics::Action>& actions);

  // ODE solver messages (degenerate contact sets) in the env's current episode.
  int solver_messages(int env) const { return worlds_[env]->solver_messages(); }

  // For an env ended by kInvalidAction: the first bad action entry and its value.
  int invalid_action_index(int env) const { return invalid_index_[env]; }
  double invalid_action_value(int env) const { return invalid_value_[env]; }

 private:
  void StepEnv(int env, const kinematics::Action& action);

  engine::WorldModel model_;
  const scenarios::ScenarioDef& scenario_;
  scenarios::Split split_;
  uint64_t seed_;
  engine::BatchState state_;
  std::vector<std::unique_ptr<engine::PhysicsWorld>> worlds_;
  std::vector<int> invalid_index_;
  std::vector<double> invalid_value_;
};

}  // namespace tavis::batch
