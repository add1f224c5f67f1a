#include "render/internal/shape_mesh.h"

#include <cmath>
#include <utility>

namespace tavis::render::internal {
namespace {

constexpr double kPi = 3.14159265358979323846;

uint32_t AddVertex(ShapeMesh* mesh, double x, double y, double z) {
  const uint32_t index = mesh->vertex_count();
  mesh->vertices.push_back(static_cast<float>(x));
  mesh->vertices.push_back(static_cast<float>(y));
  mesh->vertices.push_back(static_cast<float>(z));
  return index;
}

void AddTriangle(ShapeMesh* mesh, uint32_t a, uint32_t b, uint32_t c) {
  mesh->indices.push_back(a);
  mesh->indices.push_back(b);
  mesh->indices.push_back(c);
}

ShapeMesh BoxMesh(const Vec3& extents) {
  ShapeMesh mesh;
  const Vec3 half = 0.5 * extents;
  for (int face = 0; face < 6; ++face) {
    const int axis = kBoxFaceAxis[face];
    const int u_axis = (axis + 1) % 3;
    const int v_axis = (axis + 2) % 3;
    // Corners in order around the face (Embree intersects both sides, winding is irrelevant).
    const double corner_u[4] = {-1, 1, 1, -1};
    const double corner_v[4] = {-1, -1, 1, 1};
    uint32_t corners[4];
    for (int k = 0; k < 4; ++k) {
      Vec3 p;
      p[axis] = static_cast<double>(kBoxFaceSign[face]) * half[axis];
      p[u_axis] = corner_u[k] * half[u_axis];
      p[v_axis] = corner_v[k] * half[v_axis];
      corners[k] = AddVertex(&mesh, p.x(), p.y(), p.z());
    }
    AddTriangle(&mesh, corners[0], corners[1], corners[2]);
    AddTriangle(&mesh, corners[0], corners[2], corners[3]);
  }
  return mesh;
}

// Surface of revolution about z from a profile of (radius, z) points listed bottom to top;
// a zero radius is a pole (one vertex).
struct ProfilePoint {
  double radius;
  double z;
};

ShapeMesh RevolutionMesh(const std::vector<ProfilePoint>& profile) {
  ShapeMesh mesh;
  std::vector<uint32_t> ring_start;
  for (const ProfilePoint& point : profile) {
    ring_start.push_back(mesh.vertex_count());
    if (point.radius == 0.0) {
      AddVertex(&mesh, 0.0, 0.0, point.z);
      continue;
    }
    for (int i = 0; i < kRoundSegments; ++i) {
      const double angle = 2.0 * kPi * i / kRoundSegments;
      AddVertex(&mesh, point.radius * std::cos(angle), point.radius * std::sin(angle), point.z);
    }
  }
  auto ring = [&](std::size_t k, int i) { return ring_start[k] + static_cast<uint32_t>(i % kRoundSegments); };
  for (std::size_t k = 0; k + 1 < profile.size(); ++k) {
    const bool lower_pole = profile[k].radius == 0.0;
    const bool upper_pole = profile[k + 1].radius == 0.0;
    for (int i = 0; i < kRoundSegments; ++i) {
      if (lower_pole) {
        AddTriangle(&mesh, ring_start[k], ring(k + 1, i + 1), ring(k + 1, i));
      } else if (upper_pole) {
        AddTriangle(&mesh, ring(k, i), ring(k, i + 1), ring_start[k + 1]);
      } else {
        AddTriangle(&mesh, ring(k, i), ring(k, i + 1), ring(k + 1, i + 1));
        AddTriangle(&mesh, ring(k, i), ring(k + 1, i + 1), ring(k + 1, i));
      }
    }
  }
  return mesh;
}

// Profile of a sphere of `radius` split at the equator, the halves centred at z = -/+ half_length.
std::vector<ProfilePoint> CapsuleProfile(double radius, double half_length) {
  std::vector<ProfilePoint> profile;
  for (int j = 0; j <= kHemisphereRings; ++j) {
    const double latitude = -0.5 * kPi + 0.5 * kPi * j / kHemisphereRings;
    profile.push_back({j == 0 ? 0.0 : radius * std::cos(latitude), -half_length + radius * std::sin(latitude)});
  }
  // With no straight section the equator ring would be listed twice; skip the duplicate.
  for (int j = half_length > 0.0 ? 0 : 1; j <= kHemisphereRings; ++j) {
    const double latitude = 0.5 * kPi * j / kHemisphereRings;
    profile.push_back(
        {j == kHemisphereRings ? 0.0 : radius * std::cos(latitude), half_length + radius * std::sin(latitude)});
  }
  return profile;
}

ShapeMesh CylinderMesh(double radius, double height) {
  const double h = 0.5 * height;
  ShapeMesh mesh = RevolutionMesh({{0.0, -h}, {radius, -h}, {radius, h}, {0.0, h}});
  mesh.side_begin = kRoundSegments;    // after the bottom cap's fan
  mesh.side_end = 3 * kRoundSegments;  // before the top cap's fan
  return mesh;
}

ShapeMesh PlaneMesh() {
  ShapeMesh mesh;
  const double s = kPlaneHalfSize;
  const uint32_t a = AddVertex(&mesh, -s, -s, 0.0);
  const uint32_t b = AddVertex(&mesh, s, -s, 0.0);
  const uint32_t c = AddVertex(&mesh, s, s, 0.0);
  const uint32_t d = AddVertex(&mesh, -s, s, 0.0);
  AddTriangle(&mesh, a, b, c);
  AddTriangle(&mesh, a, c, d);
  return mesh;
}

}  // namespace

ShapeMesh TessellateShape(const ShapeGeometry& shape) {
  switch (shape.kind) {
    case ShapeKind::kBox: return BoxMesh(shape.size);
    case ShapeKind::kCylinder: return CylinderMesh(shape.size.x(), shape.size.z());
    case ShapeKind::kCapsule: return RevolutionMesh(CapsuleProfile(shape.size.x(), 0.5 * shape.size.z()));
    case ShapeKind::kSphere: return RevolutionMesh(CapsuleProfile(shape.size.x(), 0.0));
    case ShapeKind::kPlane: return PlaneMesh();
  }
  return {};
}

}  // namespace tavis::render::internal
