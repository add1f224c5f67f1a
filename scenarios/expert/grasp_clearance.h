// Whether an open hand at a planned pose stays clear of the objects around the one it grasps.
// The expert uses it to prefer grasps whose fingers and palm do not land on a neighbour.
#pragma once

#include <array>

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "kinematics/pose.h"
#include "kinematics/robot_model.h"

namespace tavis::scenarios::expert {

// An oriented box: its pose (in whichever frame the caller works) and half extents.
struct OrientedBox {
  RigidTransform X = RigidTransform::Identity();
  Vec3 half_size = Vec3::Zero();
};

// The open gripper's two pads (gap `open_gap`) and its housing, with the IK link at X_ik.
std::array<OrientedBox, 3> OpenHandBoxes(const kinematics::GripperSpec& gripper, const RigidTransform& X_ik,
                                         double open_gap);

// The collision volume of object `object` of `env` as a box, world frame (spheres and capsules
// by their bounding boxes, cylinders as the physics collides them).
OrientedBox ObjectBox(const engine::WorldModel& model, const engine::BatchState& state, int env, int object);

// Half the width of object `object` of `env` along a world direction (unit), from its bounding box.
double HalfExtentAlong(const engine::WorldModel& model, const engine::BatchState& state, int env, int object,
                       const Vec3& direction);

enum class HandParts { kPads, kPadsAndHousing };

// True if both open pads (gap `open_gap`), and with kPadsAndHousing the gripper housing, with the
// IK link at X_W_ik (world frame), stay at least `margin` outside every enabled object of `env`
// except `target`.
// Boxes and cylinders are taken as their bounding boxes (as the physics collides cylinders);
// the test samples each hand box on a 3x3x3 grid of points, which the hand's few-centimetre
// boxes make dense enough against objects of similar size.
bool OpenHandClearsNeighbours(const engine::WorldModel& model, const engine::BatchState& state, int env, int target,
                              const RigidTransform& X_W_ik, double open_gap, double margin, HandParts parts);

}  // namespace tavis::scenarios::expert
