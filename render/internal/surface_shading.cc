#include "render/internal/surface_shading.h"

namespace tavis::render::internal {
namespace {

// A 1 m checker on planes; on solids, cells of half the smallest half-extent.
constexpr float kPlaneCheckerCell = 1.0f;

}  // namespace

SurfaceModel MakeSurfaceModel(const InstanceSpec& instance, const ShapeMesh& mesh) {
  SurfaceModel surface;
  const Vec3& size = instance.geometry.size;
  surface.kind = instance.geometry.kind;
  switch (surface.kind) {
    case ShapeKind::kBox: surface.half_extents = (0.5 * size).cast<float>(); break;
    case ShapeKind::kCylinder: surface.half_extents = Eigen::Vector3f(size.x(), size.x(), 0.5 * size.z()); break;
    case ShapeKind::kCapsule:
      surface.capsule_half_length = static_cast<float>(0.5 * size.z());
      surface.half_extents = Eigen::Vector3f(size.x(), size.x(), 0.5 * size.z() + size.x());
      break;
    case ShapeKind::kSphere: surface.half_extents = Eigen::Vector3f::Constant(static_cast<float>(size.x())); break;
    case ShapeKind::kPlane: break;
  }
  surface.checker_cell = surface.kind == ShapeKind::kPlane ? kPlaneCheckerCell : 0.5f * surface.half_extents.minCoeff();
  surface.side_begin = mesh.side_begin;
  surface.side_end = mesh.side_end;
  surface.appearance = instance.appearance;
  surface.object_id = instance.object_id;
  return surface;
}

}  // namespace tavis::render::internal
