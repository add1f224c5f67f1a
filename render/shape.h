// Primitive shapes the renderer can draw, each in its own local frame.
#pragma once

#include <cstdint>
#include <string>

#include "kinematics/pose.h"
#include "kinematics/shape.h"

namespace tavis::render {

enum class ShapeKind : uint8_t {
  kBox,       // size = full extents (x, y, z), centred at the origin
  kCylinder,  // size = (radius, radius, height); axis local z, centred at the origin
  kCapsule,   // size = (radius, radius, distance between the two sphere centres); axis local z, centred
  kSphere,    // size = (radius, radius, radius)
  kPlane,     // the infinite plane z = 0 of its frame, seen from both sides; size unused (zero)
};

struct ShapeGeometry {
  ShapeKind kind = ShapeKind::kBox;
  Vec3 size = Vec3::Zero();

  // Identical shapes share one acceleration structure; equality is exact on purpose.
  bool operator==(const ShapeGeometry& other) const { return kind == other.kind && size == other.size; }
};

ShapeGeometry MakeBox(const Vec3& extents);
ShapeGeometry MakeCylinder(double radius, double height);
ShapeGeometry MakeCapsule(double radius, double segment_length);
ShapeGeometry MakeSphere(double radius);
ShapeGeometry MakePlane();

// The same primitive as the engine's collision shape (same size convention).
ShapeGeometry ToShapeGeometry(const Shape& shape);

const char* ShapeKindName(ShapeKind kind);

// Throws std::invalid_argument naming `what` and the offending value when the size does not fit
// the kind (non-finite, non-positive radius or extent, cylinder/capsule radii that differ).
void ValidateShape(const ShapeGeometry& shape, const std::string& what);

}  // namespace tavis::render
