#include "render/internal/instance_bounds.h"

#include <cmath>

namespace tavis::render::internal {
namespace {

// Margins, far above the float rounding of the meshes, the instance transforms, the ray
// directions and Embree's intersections (about 1e-7 relative at the scenes' metre scale): a box
// grows by kPad metres plus kRelativePad of its size, and every plane test must clear zero by
// kRelativePad of the magnitudes it sums.
constexpr float kPad = 1e-4f;
constexpr float kRelativePad = 1e-4f;

// Whether the ray direction d clearly runs away from a plane whose normal is m, from an origin on
// the side `side` (the signed distance) of it.
bool RunsAway(const Eigen::Vector3f& m, float side, const Eigen::Vector3f& d) {
  return side * m.dot(d) > kRelativePad * std::fabs(side) * m.norm() * d.norm();
}

}  // namespace

InstanceBounds::InstanceBounds(int n_instances) {
  boxes_.resize(static_cast<std::size_t>(n_instances));
  planes_.resize(static_cast<std::size_t>(n_instances));
}

void InstanceBounds::Build(const InstanceFrame* frames, const SurfaceModel* surfaces, const uint8_t* visible) {
  n_boxes_ = 0;
  n_planes_ = 0;
  const int n_instances = static_cast<int>(boxes_.size());
  for (int i = 0; i < n_instances; ++i) {
    if (visible[i] == 0) continue;
    const float* xfm = frames[i].xfm;  // column-major [R | t]
    const Eigen::Vector3f origin(xfm[9], xfm[10], xfm[11]);
    if (surfaces[i].kind == ShapeKind::kPlane) {
      // Local z = 0 with normal z, taken as unbounded: its mesh is a finite part of it.
      planes_[static_cast<std::size_t>(n_planes_++)] = {Eigen::Vector3f(xfm[6], xfm[7], xfm[8]), origin};
      continue;
    }
    // The shapes are centred on their local origin.
    Box& box = boxes_[static_cast<std::size_t>(n_boxes_++)];
    box.centre = origin;
    for (int j = 0; j < 3; ++j) box.axes[j] = Eigen::Vector3f(xfm[3 * j], xfm[3 * j + 1], xfm[3 * j + 2]);
    const Eigen::Vector3f& half = surfaces[i].half_extents;
    for (int j = 0; j < 3; ++j) box.half[j] = half[j] * (1.0f + kRelativePad) + kPad;
  }
}

bool InstanceBounds::Misses(const Box& box, const Pyramid& pyramid, const Eigen::Vector3f* normal,
                            const float* normal_dot_origin) {
  const Eigen::Vector3f& origin = pyramid.origin;
  // The box's half width along a unit or non-unit direction n.
  auto reach_along = [&box](const Eigen::Vector3f& n) {
    float reach = 0.0f;
    for (int j = 0; j < 3; ++j) reach += box.half[j] * std::fabs(n.dot(box.axes[j]));
    return reach;
  };
  const float scale = box.centre.norm() + origin.norm();
  // Entirely nearer than the near depth or farther than the far one.
  const float depth = pyramid.forward.dot(box.centre - origin);
  const float depth_reach = reach_along(pyramid.forward);
  const float depth_pad = kRelativePad * (scale + depth_reach + pyramid.far_m);
  if (depth + depth_reach < pyramid.near_m - depth_pad) return true;
  if (depth - depth_reach > pyramid.far_m + depth_pad) return true;
  // Outside one of the pyramid's side planes: the box's farthest reach along the inward normal
  // stays behind the plane through the origin.
  for (int s = 0; s < 4; ++s) {
    const Eigen::Vector3f& n = normal[s];
    const float reach = reach_along(n);
    const float centre = n.dot(box.centre) - normal_dot_origin[s];
    if (centre + reach < -kRelativePad * (n.norm() * scale + reach)) return true;
  }
  // Beyond one of the box's face planes, every corner ray running away from it.
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3f& a = box.axes[j];
    const float along = a.dot(origin - box.centre);
    if (std::fabs(along) <= box.half[j] + kRelativePad * scale) continue;
    const float side = along > 0.0f ? along - box.half[j] : along + box.half[j];  // signed, from the face
    bool away = true;
    for (int c = 0; c < 4 && away; ++c) away = RunsAway(a, side, pyramid.corner[c]);
    if (away) return true;
  }
  return false;
}

bool InstanceBounds::MissesEverything(const Pyramid& pyramid) const {
  const Eigen::Vector3f* corner = pyramid.corner;
  // A ray meets a plane at depth |side| / approach, where `approach` (linear in the direction, so
  // largest at a corner) is how fast it closes in on the plane: a plane is missed when every corner
  // ray runs away from it or would meet it only beyond the far depth.
  for (int p = 0; p < n_planes_; ++p) {
    const Plane& plane = planes_[static_cast<std::size_t>(p)];
    const float side = plane.normal.dot(pyramid.origin - plane.point);
    const float towards = side >= 0.0f ? -1.0f : 1.0f;
    for (int c = 0; c < 4; ++c) {
      const float approach = towards * plane.normal.dot(corner[c]);
      const float pad = kRelativePad * plane.normal.norm() * corner[c].norm();
      if ((approach + pad) * pyramid.far_m >= std::fabs(side) * (1.0f - kRelativePad)) return false;
    }
  }
  // The pyramid's side planes through the origin, normals pointing inwards.
  const Eigen::Vector3f middle = corner[0] + corner[1] + corner[2] + corner[3];
  Eigen::Vector3f normal[4];
  float normal_dot_origin[4];
  for (int s = 0; s < 4; ++s) {
    normal[s] = corner[s].cross(corner[(s + 1) % 4]);
    if (normal[s].dot(middle) < 0.0f) normal[s] = -normal[s];
    normal_dot_origin[s] = normal[s].dot(pyramid.origin);
  }
  for (int b = 0; b < n_boxes_; ++b) {
    if (!Misses(boxes_[static_cast<std::size_t>(b)], pyramid, normal, normal_dot_origin)) return false;
  }
  return true;
}

}  // namespace tavis::render::internal
