// Primitive shapes the renderer can draw, each in its own local frame.
#pragma once

#include <cstdint>
#include <string>

#include "kinematics/pose.h"
#include "kinematics/shape.h"

namespace tavis::render {

// The renderer draws the engine's primitives (kinematics/shape.h, one kind list), planes included.
using ShapeGeometry = Shape;

ShapeGeometry MakeBox(const Vec3& extents);
ShapeGeometry MakeCylinder(double radius, double height);
ShapeGeometry MakeCapsule(double radius, double segment_length);
ShapeGeometry MakeSphere(double radius);
ShapeGeometry MakePlane();

const char* ShapeKindName(ShapeKind kind);

// Throws std::invalid_argument naming `what` and the offending value when the size does not fit
// the kind (non-finite, non-positive radius or extent, cylinder/capsule radii that differ).
void ValidateShape(const ShapeGeometry& shape, const std::string& what);

}  // namespace tavis::render
