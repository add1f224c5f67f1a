// Whether an arm keeps clear of the fixed obstacles of a scene: the monitor of occluded-reach,
// the cabinet of multi-shelf-scan, the walls of peeking-box's box. The expert's planner uses it
// to prefer arm configurations and paths that do not push through them (the physics would stop
// the arm there, and the hand would never reach its grasp).
#pragma once

#include <vector>

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "kinematics/robot_model.h"
#include "scenarios/expert/grasp_clearance.h"

namespace tavis::scenarios::expert {

// True if the two boxes come closer than `margin` (separating-axis test on the boxes grown by it).
bool BoxesOverlap(const OrientedBox& a, const OrientedBox& b, double margin);

class ArmObstacles {
 public:
  // The colliding static parts and the env's enabled colliding kinematic objects. The table
  // only counts for the arm's links: the hand works just above it, and the grasp planner keeps
  // the pads off it, but a forearm resting on it stops the hand short of its grasp.
  ArmObstacles(const engine::WorldModel& model, const engine::BatchState& state, int env, double margin);

  // No obstacle besides the table.
  bool empty() const { return obstacles_.empty(); }
  // True if every collision shape of `side`'s arm, the gripper housing and both open pads, with
  // the link poses X_BL (kinematics::ComputeLinkPoses), stay `margin` outside every obstacle
  // (the arm's links also outside the table). Shapes are taken as their bounding boxes.
  bool ArmIsClear(const kinematics::RobotModel& robot, kinematics::Side side, const RigidTransform* X_BL) const;
  // The same along the straight joint-space path from q_from to q_to (full joint vectors),
  // sampled every 0.05 rad of the largest joint motion.
  bool JointPathIsClear(const kinematics::RobotModel& robot, kinematics::Side side, const std::vector<double>& q_from,
                        const std::vector<double>& q_to) const;
  // True if a box given in the world frame (a held object's way out) stays `margin` outside
  // every obstacle; the table does not count.
  bool BoxIsClear(const OrientedBox& box_world) const;

 private:
  std::vector<OrientedBox> obstacles_;  // base frame
  std::vector<OrientedBox> link_only_;  // the table, base frame
  double margin_ = 0.0;
  Vec3 root_world_ = Vec3::Zero();  // the base frame's origin in the world
};

}  // namespace tavis::scenarios::expert
