// The proprioceptive part of the observation contract (reference 8), per env, in float32 as the
// reference's tensors: observation.state in the reference's robot_joint_pos layout as far as it is
// known (RobotModel::observation_state, docs/observation.md), and each hand's end-effector pose:
// position in the canonical (action) frame, orientation (w, x, y, z) in the world frame. Under the
// fixed camera protocol the neck entries of the state are zero, as the reference feeds them.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "batch/camera_protocol.h"
#include "engine/batch_state.h"
#include "kinematics/robot_model.h"

namespace tavis::batch {

class ProprioceptionBatch {
 public:
  ProprioceptionBatch(const kinematics::RobotModel& robot, int num_envs);

  void SetCameraProtocol(CameraProtocol protocol) { protocol_ = protocol; }
  int state_size() const { return state_size_; }
  // The state entries of the neck's roll, pitch and yaw joints (-1 if the layout lacks one).
  const std::array<int, kinematics::kNeckDof>& neck_entries() const { return neck_entries_; }

  // Fills the rows of the envs with envs[env] != 0 from the batch state.
  void Update(const engine::BatchState& state, const std::vector<uint8_t>& envs);
  // The same for one env; calls for distinct envs may run concurrently.
  void UpdateEnv(const engine::BatchState& state, int env);

  const float* state(int env) const { return &state_[static_cast<std::size_t>(env) * state_size_]; }
  const float* eef_position(int env, kinematics::Side side) const { return &eef_position_[Hand(env, side) * 3]; }
  const float* eef_quaternion(int env, kinematics::Side side) const { return &eef_quaternion_[Hand(env, side) * 4]; }

 private:
  static std::size_t Hand(int env, kinematics::Side side) {
    return static_cast<std::size_t>(env) * 2 + static_cast<std::size_t>(kinematics::Index(side));
  }

  const kinematics::RobotModel& robot_;
  int state_size_ = 0;
  std::array<int, kinematics::kNeckDof> neck_entries_{};
  CameraProtocol protocol_ = CameraProtocol::kHead;
  std::vector<float> state_;           // (num_envs x state_size)
  std::vector<float> eef_position_;    // (num_envs x 2 x 3) left, right
  std::vector<float> eef_quaternion_;  // (num_envs x 2 x 4) left, right; w, x, y, z
};

}  // namespace tavis::batch
