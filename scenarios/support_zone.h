// Places on a horizontal surface where an object may stand: the distractors perturbation axis's
// places for extra objects and the runtime axis's places for the moved target
// (ScenarioDef::distractor_zones, ScenarioDef::target_zones; docs/perturbations.md).
#pragma once

#include "kinematics/pose.h"

namespace tavis::scenarios {

// A rectangle lying on a support surface: an object stands in it when its whole footprint does.
struct SupportZone {
  Vec3 centre = Vec3::Zero();  // world; z is the surface's height
  double yaw = 0.0;            // rad: the rectangle's own x axis turned from the world's x about the vertical
  double half_x = 0.0;         // m: half extents along the rectangle's own x and y
  double half_y = 0.0;
};

// An axis-aligned zone [x_low, x_high] x [y_low, y_high] on the surface at height z.
inline SupportZone AlignedZone(double x_low, double x_high, double y_low, double y_high, double z) {
  return {Vec3(0.5 * (x_low + x_high), 0.5 * (y_low + y_high), z), 0.0, 0.5 * (x_high - x_low), 0.5 * (y_high - y_low)};
}

}  // namespace tavis::scenarios
