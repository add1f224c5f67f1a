// Joint-space planning for scripted experts. The controller's damped-least-squares IK only
// tracks targets near the arm's current configuration; across the workspace it can stall at a
// joint limit. The expert therefore solves for the goal configuration offline (several seeds,
// joint limits respected) and commands the hand poses of a straight joint-space path to it,
// which the controller can follow.
#pragma once

#include <optional>
#include <vector>

#include "kinematics/inverse_kinematics.h"

namespace tavis::scenarios::expert {

class ArmObstacles;

// A full joint vector whose arm joints put the IK link at `target` (base frame) within 2 mm and
// 0.03 rad, trying `q_start` first, then deterministic spreads of seeds; nullopt if none does.
// With `obstacles`, only configurations whose arm is clear of them count, and with
// `clear_path_from` too only those reached from it by a clear straight joint-space path.
std::optional<std::vector<double>> SolveArmConfiguration(const kinematics::RobotModel& robot, kinematics::Side side,
                                                         const std::vector<double>& q_start,
                                                         const kinematics::PoseTarget& target,
                                                         const ArmObstacles* obstacles = nullptr,
                                                         const std::vector<double>* clear_path_from = nullptr);

// True if the controller, stepping its IK once per tick along the straight hand path (position
// line, orientation slerp) from q_start's hand pose to `goal` in `ticks` ticks, stays within
// 1 cm of the path and ends within tolerance of the goal (kinematic rehearsal, limits held);
// with `obstacles`, also keeps the arm clear of them at every tick.
bool CanTrackStraightPath(const kinematics::RobotModel& robot, kinematics::Side side,
                          const std::vector<double>& q_start, const kinematics::PoseTarget& goal, int ticks,
                          const ArmObstacles* obstacles = nullptr);

// IK link pose (canonical frame) for joint vector q. Allocates nothing: experts call it every tick.
RigidTransform HandPoseCanonical(const kinematics::RobotModel& robot, kinematics::Side side, const double* q);

}  // namespace tavis::scenarios::expert
