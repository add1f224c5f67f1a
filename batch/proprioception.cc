#include "batch/proprioception.h"

#include <tbb/parallel_for.h>

#include "kinematics/forward_kinematics.h"
#include "kinematics/robot_buffers.h"

namespace tavis::batch {

ProprioceptionBatch::ProprioceptionBatch(const kinematics::RobotModel& robot, int num_envs)
    : robot_(robot), state_size_(static_cast<int>(robot.observation_state.size())) {
  neck_entries_.fill(-1);
  for (int entry = 0; entry < state_size_; ++entry) {
    const kinematics::StateEntry& spec = robot.observation_state[static_cast<std::size_t>(entry)];
    for (int k = 0; k < kinematics::kNeckDof; ++k) {
      if (spec.kind == kinematics::StateEntry::Kind::kJoint && spec.joint == robot.neck_joints[k])
        neck_entries_[k] = entry;
    }
  }
  const std::size_t envs = static_cast<std::size_t>(num_envs);
  state_.assign(envs * static_cast<std::size_t>(state_size_), 0.0f);
  eef_position_.assign(envs * 2 * 3, 0.0f);
  eef_quaternion_.assign(envs * 2 * 4, 0.0f);
}

void ProprioceptionBatch::Update(const engine::BatchState& state, const std::vector<uint8_t>& envs) {
  tbb::parallel_for(0, static_cast<int>(envs.size()), [&](int env) {
    if (envs[env]) UpdateEnv(state, env);
  });
}

void ProprioceptionBatch::UpdateEnv(const engine::BatchState& state, int env) {
  const double* q = state.q_row(env);
  float* row = &state_[static_cast<std::size_t>(env) * state_size_];
  for (int entry = 0; entry < state_size_; ++entry) {
    const kinematics::StateEntry& spec = robot_.observation_state[static_cast<std::size_t>(entry)];
    switch (spec.kind) {
      case kinematics::StateEntry::Kind::kJoint: row[entry] = static_cast<float>(q[spec.joint]); break;
      case kinematics::StateEntry::Kind::kUnsimulated: row[entry] = static_cast<float>(spec.value); break;
      case kinematics::StateEntry::Kind::kGripperGap:
        row[entry] = static_cast<float>(state.gripper_gap_row(env)[kinematics::Index(spec.side)]);
        break;
    }
  }
  if (UsesFixedView(protocol_)) {
    for (const int entry : neck_entries_) {
      if (entry >= 0) row[entry] = 0.0f;
    }
  }
  LinkPoses X_BL;  // per tick: no allocation
  kinematics::ComputeLinkPoses(robot_, q, X_BL.data());
  for (const kinematics::Side side : kinematics::kSides) {
    const RigidTransform& X_BE = X_BL[static_cast<std::size_t>(robot_.arm(side).ik_link)];
    const Vec3 p_canonical = robot_.BaseToCanonical(X_BE.translation());
    // The base's world orientation is the identity (RobotModel::root_world), so this is the world's.
    const Quat q_world(X_BE.linear());
    float* position = &eef_position_[Hand(env, side) * 3];
    float* quaternion = &eef_quaternion_[Hand(env, side) * 4];
    for (int k = 0; k < 3; ++k) position[k] = static_cast<float>(p_canonical[k]);
    quaternion[0] = static_cast<float>(q_world.w());
    quaternion[1] = static_cast<float>(q_world.x());
    quaternion[2] = static_cast<float>(q_world.y());
    quaternion[3] = static_cast<float>(q_world.z());
  }
}

}  // namespace tavis::batch
