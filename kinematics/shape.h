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

// Half extents of the shape's bounding box in its own frame.
inline Vec3 BoundingHalfSize(const Shape& shape) {
  switch (shape.kind) {
    case ShapeKind::kCylinder: return Vec3(shape.Radius(), shape.Radius(), 0.5 * shape.Length());
    case ShapeKind::kCapsule: return Vec3(shape.Radius(), shape.Radius(), 0.5 * shape.Length() + shape.Radius());
    case ShapeKind::kSphere: return Vec3::Constant(shape.Radius());
    case ShapeKind::kBox: break;
  }
  return 0.5 * shape.size;
}

}  // namespace tavis
