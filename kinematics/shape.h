// Primitive shapes shared by collision (engine) and drawing (render).
#pragma once

#include "kinematics/pose.h"

namespace tavis {

enum class ShapeKind { kBox, kCylinder, kCapsule, kSphere };

// size: box = full extents (x, y, z); cylinder = (radius, radius, height); capsule = (radius,
// radius, length between the cap centres); sphere = (radius, radius, radius). Cylinders and
// capsules run along the local z axis, centred at the origin.
struct Shape {
  ShapeKind kind = ShapeKind::kBox;
  Vec3 size = Vec3::Zero();

  double Radius() const { return size.x(); }
  double Length() const { return size.z(); }
};

}  // namespace tavis
