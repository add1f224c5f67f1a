// Everything that changes during a batch, stored field-major across envs (structure of
// arrays). Shapes are given in comments; rows are envs. Allocated once by the VecEnv.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/random.h"
#include "kinematics/pose.h"

namespace tavis::engine {

// Why an episode ended without success.
enum class EpisodeEnd : uint8_t { kRunning = 0, kSuccess, kTimeOut, kPhysicsBlowUp, kInvalidAction };
const char* ToString(EpisodeEnd end);

constexpr int kObjectPoseSize = 7;      // x, y, z, qw, qx, qy, qz (world)
constexpr int kObjectVelocitySize = 6;  // linear xyz, angular xyz (world)
constexpr int kMaxTaskVars = 8;

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
  std::vector<double> task_vars;        // (num_envs x kMaxTaskVars) task-defined (target index...)
  std::vector<int> control_step;        // (num_envs) control ticks since the episode's reset
  std::vector<int64_t> episode;         // (num_envs) episode index in the slot, -1 when idle
  std::vector<EpisodeEnd> end;          // (num_envs) kRunning until the episode ends
  std::vector<RandomStream> task_rng;   // (num_envs) the episode's task stream

  void Allocate(int envs, int joints, int objects);

  double* q_row(int env) { return &q[static_cast<size_t>(env) * num_joints]; }
  const double* q_row(int env) const { return &q[static_cast<size_t>(env) * num_joints]; }
  double* q_target_row(int env) { return &q_target[static_cast<size_t>(env) * num_joints]; }
  double* object_pose_row(int env, int object) {
    return &object_pose[(static_cast<size_t>(env) * num_objects + object) * kObjectPoseSize];
  }
  const double* object_pose_row(int env, int object) const {
    return &object_pose[(static_cast<size_t>(env) * num_objects + object) * kObjectPoseSize];
  }
  const double* object_velocity_row(int env, int object) const {
    return &object_velocity[(static_cast<size_t>(env) * num_objects + object) * kObjectVelocitySize];
  }
  float* object_rgb_row(int env, int object) {
    return &object_rgb[(static_cast<size_t>(env) * num_objects + object) * 3];
  }
  const float* object_rgb_row(int env, int object) const {
    return &object_rgb[(static_cast<size_t>(env) * num_objects + object) * 3];
  }
  double* task_vars_row(int env) { return &task_vars[static_cast<size_t>(env) * kMaxTaskVars]; }
  const double* task_vars_row(int env) const { return &task_vars[static_cast<size_t>(env) * kMaxTaskVars]; }
  uint8_t& object_enabled_at(int env, int object) {
    return object_enabled[static_cast<size_t>(env) * num_objects + object];
  }
  uint8_t object_enabled_at(int env, int object) const {
    return object_enabled[static_cast<size_t>(env) * num_objects + object];
  }

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
};

}  // namespace tavis::engine
