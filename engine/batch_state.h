// Everything that changes during a batch, stored field-major across envs (structure of
// arrays). Shapes are given in comments; rows are envs. Allocated once by the VecEnv; every
// per-env array has a row accessor, and indices are checked by the invariant tier.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/random.h"
#include "kinematics/invariant.h"
#include "kinematics/pose.h"

namespace tavis::engine {

// Why an episode ended. kStopped: the driver ended it early because its sinks had what they
// needed (the visibility audit); such an episode has no outcome. kGaveUp: the policy said it had
// nothing left to try (the scripted expert out of grasp attempts), a failure like a time-out.
enum class EpisodeEnd : uint8_t { kRunning = 0, kSuccess, kTimeOut, kPhysicsBlowUp, kInvalidAction, kStopped, kGaveUp };
const char* ToString(EpisodeEnd end);
// The end named `text` (as ToString writes it); false for another text.
bool ParseEpisodeEnd(const std::string& text, EpisodeEnd* end);

constexpr int kObjectPoseSize = 7;      // x, y, z, qw, qx, qy, qz (world)
constexpr int kObjectVelocitySize = 6;  // linear xyz, angular xyz (world)
constexpr int kGrippersPerEnv = 2;      // left, right (kinematics::Index(side))

// The per-episode variables every task has and the runtime reads: its target, the phrasing of its
// prompt, and what the runtime perturbation axis did to the target. A task's reset writes them
// from the episode's random draws; its own variables live in its TaskStateBlock.
struct TaskVars {
  int target = -1;         // index of the object the episode is about (every task)
  int prompt_variant = 0;  // which phrasing of the prompt (clutter-pick-lift, multi-shelf-scan)
  // The runtime perturbation axis (docs/perturbations.md): the control tick at which the target
  // was moved under the approaching hand, -1 while it has not been; and whether a hand has come
  // near it (moved or, with no free place, not: the axis is done with the episode either way).
  int target_move_tick = -1;
  bool target_move_tried = false;
};

// A task's own per-env variables (as MuJoCo's mjData::userdata): bytes the engine keeps and never
// reads. The task declares their type and its hooks alone read and write them
// (scenarios/task_state.h). One block per env, all in one array allocated with the batch, so a
// step never allocates; a cache line each, so threads stepping neighbouring envs share none. A
// reset zeroes the env's block before the task's reset hook starts its variables there.
inline constexpr std::size_t kTaskStateBytes = 64;
struct alignas(64) TaskStateBlock {
  unsigned char bytes[kTaskStateBytes] = {};
};

// Why an episode ended invalid_action: the policy's action, or the reply it came in, was unusable.
struct InvalidAction {
  int entry = -1;  // index in the 19-D action; -1 when no entry is to blame (a malformed reply)
  double value = 0.0;
  std::string reason;  // "not finite", "IK target coordinate beyond 10 m", a served policy's fault...
};

struct BatchState {
  int num_envs = 0;
  int num_joints = 0;
  int num_objects = 0;

  std::vector<double> q;                // (num_envs x num_joints) measured joint positions
  std::vector<double> q_target;         // (num_envs x num_joints) joint targets (IK, neck action)
  std::vector<double> gripper_command;  // (num_envs x 2) left, right in [-1, 1]
  std::vector<double> gripper_gap;      // (num_envs x 2) measured inner-face gap, m
  std::vector<double> object_pose;      // (num_envs x num_objects x 7)
  std::vector<double> object_velocity;  // (num_envs x num_objects x 6)
  std::vector<uint8_t> object_enabled;  // (num_envs x num_objects) hidden objects are disabled
  // (num_envs x num_objects x 3) linear RGB a task gives an object (the cue card's red or green,
  // the light turning green); negative: the object's palette colour.
  std::vector<float> object_rgb;
  std::vector<TaskVars> task;              // (num_envs) the variables every task has
  std::vector<TaskStateBlock> task_state;  // (num_envs) the task's own variables
  std::vector<int> control_step;           // (num_envs) control ticks since the episode's reset
  // (num_envs) control_step at the policy's first observation: the ticks the reset's warm-up
  // held (ood-init-pose), 0 otherwise. A served request counts its `step` from here.
  std::vector<int> policy_start_tick;
  std::vector<int64_t> episode;               // (num_envs) episode index in the slot, -1 when idle
  std::vector<EpisodeEnd> end;                // (num_envs) kRunning until the episode ends
  std::vector<InvalidAction> invalid_action;  // (num_envs) set when end is kInvalidAction
  std::vector<uint8_t> images_current;        // (num_envs) the env's camera images show its current state
  std::vector<RandomStream> task_rng;         // (num_envs) the episode's task stream

  void Allocate(int envs, int joints, int objects);

  // An env whose slot holds an episode that has not ended.
  bool running(int env) const { return episode[Env(env)] >= 0 && end[Env(env)] == EpisodeEnd::kRunning; }

  double* q_row(int env) { return &q[Env(env) * num_joints]; }
  const double* q_row(int env) const { return &q[Env(env) * num_joints]; }
  double* q_target_row(int env) { return &q_target[Env(env) * num_joints]; }
  const double* q_target_row(int env) const { return &q_target[Env(env) * num_joints]; }
  double* gripper_command_row(int env) { return &gripper_command[Env(env) * kGrippersPerEnv]; }
  const double* gripper_command_row(int env) const { return &gripper_command[Env(env) * kGrippersPerEnv]; }
  double* gripper_gap_row(int env) { return &gripper_gap[Env(env) * kGrippersPerEnv]; }
  const double* gripper_gap_row(int env) const { return &gripper_gap[Env(env) * kGrippersPerEnv]; }
  double* object_pose_row(int env, int object) { return &object_pose[EnvObject(env, object) * kObjectPoseSize]; }
  const double* object_pose_row(int env, int object) const {
    return &object_pose[EnvObject(env, object) * kObjectPoseSize];
  }
  double* object_velocity_row(int env, int object) {
    return &object_velocity[EnvObject(env, object) * kObjectVelocitySize];
  }
  const double* object_velocity_row(int env, int object) const {
    return &object_velocity[EnvObject(env, object) * kObjectVelocitySize];
  }
  float* object_rgb_row(int env, int object) { return &object_rgb[EnvObject(env, object) * 3]; }
  const float* object_rgb_row(int env, int object) const { return &object_rgb[EnvObject(env, object) * 3]; }
  unsigned char* task_state_row(int env) { return task_state[Env(env)].bytes; }
  const unsigned char* task_state_row(int env) const { return task_state[Env(env)].bytes; }
  uint8_t& object_enabled_at(int env, int object) { return object_enabled[EnvObject(env, object)]; }
  uint8_t object_enabled_at(int env, int object) const { return object_enabled[EnvObject(env, object)]; }

  Vec3 ObjectPosition(int env, int object) const {
    const double* p = object_pose_row(env, object);
    return Vec3(p[0], p[1], p[2]);
  }
  Quat ObjectOrientation(int env, int object) const {
    const double* p = object_pose_row(env, object);
    return Quat(p[3], p[4], p[5], p[6]);
  }
  Vec3 ObjectLinearVelocity(int env, int object) const {
    const double* v = object_velocity_row(env, object);
    return Vec3(v[0], v[1], v[2]);
  }
  // The episode's target object (TaskVars::target), checked to be an object of the world.
  int target(int env) const {
    const int object = task[Env(env)].target;
    TAVIS_INVARIANT(object >= 0 && object < num_objects, "the task's reset set a target object");
    return object;
  }

 private:
  size_t Env(int env) const {
    TAVIS_INVARIANT(env >= 0 && env < num_envs, "env index in range");
    return static_cast<size_t>(env);
  }
  size_t EnvObject(int env, int object) const {
    TAVIS_INVARIANT(object >= 0 && object < num_objects, "object index in range");
    return Env(env) * static_cast<size_t>(num_objects) + static_cast<size_t>(object);
  }
};

}  // namespace tavis::engine
