// Primitive shapes shared by collision (engine) and drawing (render): one kind list for both.
#pragma once

#include <cstdint>
#include <limits>

#include "kinematics/pose.h"

namespace tavis {

enum class ShapeKind : uint8_t {
  kBox,
  kCylinder,
  kCapsule,
  kSphere,
  // The infinite plane z = 0 of its frame, seen from both sides (size zero): the floor the
  // renderer draws. Robot links, objects and static parts are always solids; the engine's floor
  // is ODE's own plane (engine/internal/world_building.cc).
  kPlane,
};

// size: box = full extents (x, y, z); cylinder = (radius, radius, height); capsule = (radius,
// radius, length between the cap centres); sphere = (radius, radius, radius); plane = zero.
// Cylinders and capsules run along the local z axis, centred at the origin.
struct Shape {
  ShapeKind kind = ShapeKind::kBox;
  Vec3 size = Vec3::Zero();

  double Radius() const { return size.x(); }
  double Length() const { return size.z(); }

  // Identical shapes share one acceleration structure in the renderer; equality is exact on purpose.
  bool operator==(const Shape& other) const { return kind == other.kind && size == other.size; }
};

// Half extents of the shape's bounding box in its own frame.
inline Vec3 BoundingHalfSize(const Shape& shape) {
  switch (shape.kind) {
    case ShapeKind::kCylinder: return Vec3(shape.Radius(), shape.Radius(), 0.5 * shape.Length());
    case ShapeKind::kCapsule: return Vec3(shape.Radius(), shape.Radius(), 0.5 * shape.Length() + shape.Radius());
    case ShapeKind::kSphere: return Vec3::Constant(shape.Radius());
    case ShapeKind::kPlane: return Vec3::Constant(std::numeric_limits<double>::infinity());
    case ShapeKind::kBox: break;
  }
  return 0.5 * shape.size;
}

}  // namespace tavis
