// N envs of one task stepped together. A control tick is a short pipeline of stages, each a
// function over an env range run by tbb::parallel_for: apply actions (validate, IK, neck and
// gripper targets), physics substeps, neck servo, task evaluation; with cameras enabled, Observe
// adds the render stage for the envs at a policy tick. Episodes are keyed by their
// index: an episode's randomness comes from (seed, episode), so results do not depend on the
// thread count, on the number of env slots, or on which slot ran which episode.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "batch/policy.h"
#include "batch/scene_render.h"
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

  // Camera observations: builds the render scene once (images at settings.width x height, in
  // the order of settings.cameras); the scenario's black_cameras start blocked in every env.
  // Without it nothing is ever rendered.
  void EnableCameras(const CameraSettings& settings);
  const SceneRender* cameras() const { return cameras_.get(); }
  // Blocks or unblocks one camera of one env: a blocked camera's image is all zero. `camera`
  // indexes settings.cameras. Requires EnableCameras.
  void SetCameraBlocked(int env, int camera, bool blocked);

  // Stage: render. If a running env at a policy tick (control_step a multiple of
  // controls_per_policy) has no current images, renders every running env at a policy tick;
  // returns the state and the images (null without cameras). Only the images of envs at a
  // policy tick are valid.
  Observation Observe();
  // Env-camera images rendered so far, for throughput counters and tests.
  int64_t rendered_images() const { return rendered_images_; }

  // ODE solver messages (degenerate contact sets) in the env's current episode.
  int solver_messages(int env) const { return worlds_[env]->solver_messages(); }

  // For an env ended by kInvalidAction: the first bad action entry and its value.
  int invalid_action_index(int env) const { return state_.invalid_action[env].entry; }
  double invalid_action_value(int env) const { return state_.invalid_action[env].value; }

 private:
  void StepEnv(int env, const kinematics::Action& action);

  engine::WorldModel model_;
  const scenarios::ScenarioDef& scenario_;
  scenarios::Split split_;
  uint64_t seed_;
  engine::BatchState state_;
  std::vector<std::unique_ptr<engine::PhysicsWorld>> worlds_;
  std::unique_ptr<SceneRender> cameras_;
  std::vector<uint8_t> images_current_;  // (num_envs) rendered since the env's last change
  std::vector<uint8_t> render_env_;      // (num_envs) this tick's render flags
  int64_t rendered_images_ = 0;
};

}  // namespace tavis::batch
