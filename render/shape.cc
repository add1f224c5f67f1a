#include "render/shape.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace tavis::render {

ShapeGeometry MakeBox(const Vec3& extents) { return {ShapeKind::kBox, extents}; }

ShapeGeometry MakeCylinder(double radius, double height) {
  return {ShapeKind::kCylinder, Vec3(radius, radius, height)};
}

ShapeGeometry MakeCapsule(double radius, double segment_length) {
  return {ShapeKind::kCapsule, Vec3(radius, radius, segment_length)};
}

ShapeGeometry MakeSphere(double radius) { return {ShapeKind::kSphere, Vec3(radius, radius, radius)}; }

ShapeGeometry MakePlane() { return {ShapeKind::kPlane, Vec3::Zero()}; }

const char* ShapeKindName(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::kBox: return "box";
    case ShapeKind::kCylinder: return "cylinder";
    case ShapeKind::kCapsule: return "capsule";
    case ShapeKind::kSphere: return "sphere";
    case ShapeKind::kPlane: return "plane";
  }
  return "unknown";
}

void ValidateShape(const ShapeGeometry& shape, const std::string& what) {
  const Vec3& s = shape.size;
  auto fail = [&](const char* reason) {
    std::ostringstream message;
    message << what << ": " << ShapeKindName(shape.kind) << " size (" << s.x() << ", " << s.y() << ", " << s.z() << ") "
            << reason;
    throw std::invalid_argument(message.str());
  };
  if (!s.allFinite()) fail("is not finite");
  switch (shape.kind) {
    case ShapeKind::kBox:
      if ((s.array() <= 0.0).any()) fail("must have positive extents");
      break;
    case ShapeKind::kCylinder:
      if (s.x() <= 0.0 || s.z() <= 0.0) fail("must have a positive radius and height");
      if (s.x() != s.y()) fail("must have equal x and y radii");
      break;
    case ShapeKind::kCapsule:
      if (s.x() <= 0.0 || s.z() < 0.0) fail("must have a positive radius and a non-negative length");
      if (s.x() != s.y()) fail("must have equal x and y radii");
      break;
    case ShapeKind::kSphere:
      if (s.x() <= 0.0) fail("must have a positive radius");
      if (s.x() != s.y() || s.x() != s.z()) fail("must repeat the radius in x, y and z");
      break;
    case ShapeKind::kPlane:
      if (!s.isZero()) fail("must be zero (a plane has no size)");
      break;
  }
}

}  // namespace tavis::render
