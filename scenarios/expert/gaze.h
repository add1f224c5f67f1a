// Where to point the head: the neck angles that put a world point on the head camera's
// optical axis.
#pragma once

#include <array>

#include "kinematics/robot_model.h"

namespace tavis::scenarios::expert {

enum class NeckLimits { kRespect, kIgnore };

// Neck (roll, pitch, yaw) with roll 0 that centres `target_world` in the head camera, within
// the neck's joint limits, or with kIgnore as a teleoperator's head turns to it (the robot
// clamps the command at its limits). `q` supplies the other joints (they do not affect the head).
// Allocates nothing: the expert re-aims during its steady motions.
std::array<double, 3> FixationNeckAngles(const kinematics::RobotModel& robot, const double* q, const Vec3& target_world,
                                         NeckLimits limits = NeckLimits::kRespect);

// Angle (rad) between the head camera's optical axis and the direction to `target_world`.
double GazeError(const kinematics::RobotModel& robot, const double* q, const Vec3& target_world);

// The smallest GazeError the neck's joint limits allow for `target_world` (0 where the head can
// centre it; Reachy2's neck pitches 0.35 rad at most, so its head cannot centre a card on the
// table), with the other joints at q.
double ClosestGazeError(const kinematics::RobotModel& robot, const double* q, const Vec3& target_world);

}  // namespace tavis::scenarios::expert
