// Triangle meshes of the primitive shapes, in the shape's local frame.
#pragma once

#include <cstdint>
#include <vector>

#include "render/shape.h"

namespace tavis::render::internal {

// Segments around round shapes: a 5 cm radius seen from 15 cm by a 640-px wrist camera spans
// ~210 px, and 64 segments keep its silhouette within 0.25 px of a circle.
inline constexpr int kRoundSegments = 64;
// Latitude steps per hemisphere of spheres and capsules.
inline constexpr int kHemisphereRings = 16;
// Half size of the square that stands in for the infinite plane (far beyond every far plane).
inline constexpr float kPlaneHalfSize = 200.0f;

// Box triangles come in face pairs in this order: +x, -x, +y, -y, +z, -z.
inline constexpr int kBoxFaceAxis[6] = {0, 0, 1, 1, 2, 2};
inline constexpr float kBoxFaceSign[6] = {1.0f, -1.0f, 1.0f, -1.0f, 1.0f, -1.0f};

struct ShapeMesh {
  std::vector<float> vertices;    // x, y, z per vertex
  std::vector<uint32_t> indices;  // three vertex indices per triangle
  // Triangles [side_begin, side_end) form a cylinder's curved side; the rest are its caps.
  uint32_t side_begin = 0;
  uint32_t side_end = 0;

  uint32_t vertex_count() const { return static_cast<uint32_t>(vertices.size() / 3); }
  uint32_t triangle_count() const { return static_cast<uint32_t>(indices.size() / 3); }
};

ShapeMesh TessellateShape(const ShapeGeometry& shape);

}  // namespace tavis::render::internal
