// Per-instance surface model: smooth normals of the tessellated primitives, evaluated from the
// exact shape, and the procedural labels. Everything is in the shape's local frame.
#pragma once

#include <cmath>
#include <cstdint>

#include <Eigen/Core>

#include "render/internal/shape_mesh.h"
#include "render/scene_layout.h"

namespace tavis::render::internal {

struct SurfaceModel {
  ShapeKind kind = ShapeKind::kBox;
  Eigen::Vector3f half_extents = Eigen::Vector3f::Zero();  // bounding box half sizes
  float capsule_half_length = 0.0f;                        // half distance between sphere centres
  float checker_cell = 0.0f;
  uint32_t side_begin = 0;  // cylinder side triangles
  uint32_t side_end = 0;
  Appearance appearance;
  int32_t object_id = kBackgroundObjectId;
};

SurfaceModel MakeSurfaceModel(const InstanceSpec& instance, const ShapeMesh& mesh);

inline Eigen::Vector3f NormalizedOrUp(const Eigen::Vector3f& v) {
  const float length = v.norm();
  return length > 1e-12f ? Eigen::Vector3f(v / length) : Eigen::Vector3f::UnitZ();
}

// Outward unit normal of the exact shape at local point p on triangle `primitive` of its mesh.
inline Eigen::Vector3f LocalNormal(const SurfaceModel& surface, const Eigen::Vector3f& p, uint32_t primitive) {
  switch (surface.kind) {
    case ShapeKind::kBox: {
      const uint32_t face = primitive / 2;
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[kBoxFaceAxis[face]] = kBoxFaceSign[face];
      return n;
    }
    case ShapeKind::kCylinder:
      if (primitive >= surface.side_begin && primitive < surface.side_end) {
        return NormalizedOrUp(Eigen::Vector3f(p.x(), p.y(), 0.0f));
      }
      return Eigen::Vector3f(0.0f, 0.0f, p.z() >= 0.0f ? 1.0f : -1.0f);
    case ShapeKind::kCapsule: {
      const float h = surface.capsule_half_length;
      const float centre_z = std::fmax(-h, std::fmin(h, p.z()));
      return NormalizedOrUp(Eigen::Vector3f(p.x(), p.y(), p.z() - centre_z));
    }
    case ShapeKind::kSphere: return NormalizedOrUp(p);
    case ShapeKind::kPlane: return Eigen::Vector3f::UnitZ();
  }
  return Eigen::Vector3f::UnitZ();
}

// Whether RoundNormalLanes covers the shape: capsules and spheres, whose smooth normal does not
// depend on the triangle hit.
inline bool HasRoundNormalLanes(const SurfaceModel& surface) {
  return surface.kind == ShapeKind::kCapsule || surface.kind == ShapeKind::kSphere;
}

// LocalNormal for K points of one capsule or sphere (HasRoundNormalLanes) given as arrays
// p[axis][k]: n[axis][k], the same floats per lane (Eigen sums three terms as x + (y + z)).
template <int K>
void RoundNormalLanes(const SurfaceModel& surface, const float (*p)[K], float (*n)[K]) {
  const bool capsule = surface.kind == ShapeKind::kCapsule;
  const float h = surface.capsule_half_length;
  for (int k = 0; k < K; ++k) {
    const float x = p[0][k], y = p[1][k];
    const float z = capsule ? p[2][k] - std::fmax(-h, std::fmin(h, p[2][k])) : p[2][k];
    const float length = std::sqrt(x * x + (y * y + z * z));
    const bool usable = length > 1e-12f;
    n[0][k] = usable ? x / length : 0.0f;
    n[1][k] = usable ? y / length : 0.0f;
    n[2][k] = usable ? z / length : 1.0f;
  }
}

// Position across a side face in [-1, 1]: the angle about z (over pi) on round shapes, the
// horizontal face coordinate on boxes.
inline float AcrossSide(const SurfaceModel& surface, const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  if (surface.kind != ShapeKind::kBox) return std::atan2(p.y(), p.x()) * 0.318309886f;
  return std::fabs(n.x()) > 0.5f ? p.y() / surface.half_extents.y() : p.x() / surface.half_extents.x();
}

inline bool InsideLabel(const SurfaceModel& surface, const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  const LabelPattern label = surface.appearance.label;
  if (label == LabelPattern::kChecker) {
    const float c = surface.checker_cell;
    const int parity = static_cast<int>(std::floor(p.x() / c) + std::floor(p.y() / c) + std::floor(p.z() / c));
    return (parity & 1) != 0;
  }
  const bool cap = std::fabs(n.z()) > 0.7f;
  if (label == LabelPattern::kCaps) return cap;
  if (cap || surface.kind == ShapeKind::kPlane) return false;
  const float height = p.z() / surface.half_extents.z();
  switch (label) {
    case LabelPattern::kBand: return std::fabs(height) < 0.3f;
    case LabelPattern::kStripes: {
      const int stripe = static_cast<int>(std::floor((AcrossSide(surface, p, n) + 1.0f) * 4.0f));
      return (stripe & 1) != 0;
    }
    case LabelPattern::kFrontPanel: {
      const float across_limit = surface.kind == ShapeKind::kBox ? 0.6f : 0.25f;
      return std::fabs(height) < 0.5f && std::fabs(AcrossSide(surface, p, n)) < across_limit;
    }
    default: return false;
  }
}

// Whether Reflectance is `base_rgb` everywhere on the surface, so that a flat face has one colour
// (FlatShades). A surface whose colour varies over it must answer false.
inline bool HasConstantReflectance(const SurfaceModel& surface) {
  return surface.appearance.label == LabelPattern::kNone;
}

// Diffuse reflectance at p: the label colour inside the label, else `base_rgb`.
inline Eigen::Vector3f Reflectance(const SurfaceModel& surface, const Eigen::Vector3f& base_rgb,
                                   const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  if (surface.appearance.label == LabelPattern::kNone) return base_rgb;
  return InsideLabel(surface, p, n) ? surface.appearance.label_rgb : base_rgb;
}

}  // namespace tavis::render::internal
