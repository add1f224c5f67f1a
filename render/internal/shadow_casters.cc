#include "render/internal/shadow_casters.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tavis::render::internal {
namespace {

// Margin of every test, in metres: far above the float rounding of the meshes, the instance
// transforms and Embree's intersections (about 1e-7 relative at the scenes' metre scale), far
// below what a pixel shows.
constexpr float kPad = 1e-4f;
// Round meshes (64 segments, 16 rings per hemisphere; shape_mesh.h) contain their shape scaled
// by cos^2(pi / 64) = 0.9976 about its axis: a ray within this fraction of the radius crosses it.
constexpr float kInscribedFraction = 0.99f;
constexpr float kHalfSqrt2 = 0.70710678f;

Eigen::Vector3f Column(const InstanceFrame& frame, int column) {
  return {frame.xfm[3 * column], frame.xfm[3 * column + 1], frame.xfm[3 * column + 2]};
}

// Half width of a box with these axes and half sizes seen along `axis`.
float ProjectedRadius(const Eigen::Vector3f* axes, const Eigen::Vector3f& half, const Eigen::Vector3f& axis) {
  return std::fabs(axes[0].dot(axis)) * half.x() + std::fabs(axes[1].dot(axis)) * half.y() +
         std::fabs(axes[2].dot(axis)) * half.z();
}

float Squared(float x) { return x * x; }

// Squared distance from the ray o + s d (s >= 0, |d| = 1) to the segment |z| <= a on the z axis:
// the least of the interior critical point and the minima along the edges s = 0, z = -a, z = a.
float RaySegmentDistance2(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float a) {
  const float o_dot_d = o.dot(d);
  auto at = [&](float s, float z) {
    const Eigen::Vector3f p = o + s * d;
    return Squared(p.x()) + Squared(p.y()) + Squared(p.z() - z);
  };
  float best = at(0.0f, std::clamp(o.z(), -a, a));
  best = std::min(best, at(std::max(0.0f, -a * d.z() - o_dot_d), -a));
  best = std::min(best, at(std::max(0.0f, a * d.z() - o_dot_d), a));
  const float denominator = 1.0f - d.z() * d.z();
  if (a > 0.0f && denominator > 1e-6f) {
    const float s = (d.z() * o.z() - o_dot_d) / denominator;
    const float z = o.z() + s * d.z();
    if (s >= 0.0f && std::fabs(z) <= a) best = std::min(best, at(s, z));
  }
  return best;
}

}  // namespace

// Whether the box (centre, half) lies beyond a face plane of the caster's bounding box whose
// outward normal does not point away from the light: rays from it then stay beyond that plane.
// This is what drops a box (the table) from the tiles of its own lit faces.
bool ShadowCasters::OutsideFacingLight(const Caster& c, const Eigen::Vector3f& centre, const Eigen::Vector3f& half,
                                       const Eigen::Vector3f* world_axes) {
  const Eigen::Vector3f offset = centre - c.centre;
  for (int k = 0; k < 3; ++k) {
    const float along = offset.dot(c.axes[k]);
    const float spread = ProjectedRadius(world_axes, half, c.axes[k]);
    if (c.light_local[k] >= 0.0f && along - spread >= c.outer[k]) return true;
    if (c.light_local[k] <= 0.0f && -along - spread >= c.outer[k]) return true;
  }
  return false;
}

ShadowCasters::ShadowCasters(const Eigen::Vector3f& to_light, int n_instances)
    : axis_w_(to_light.normalized()), n_instances_(n_instances) {
  // Any unit vector across the light, then the third axis of a right-handed frame.
  const Eigen::Vector3f helper = std::fabs(axis_w_.x()) < 0.9f ? Eigen::Vector3f::UnitX() : Eigen::Vector3f::UnitY();
  axis_u_ = axis_w_.cross(helper).normalized();
  axis_v_ = axis_w_.cross(axis_u_);
  casters_.reserve(static_cast<std::size_t>(n_instances));
}

void ShadowCasters::Build(const InstanceFrame* frames, const SurfaceModel* surfaces, const uint8_t* visible) {
  casters_.clear();
  for (int i = 0; i < n_instances_; ++i) {
    if (visible[i] == 0) continue;
    const SurfaceModel& surface = surfaces[i];
    Caster c;
    c.kind = surface.kind;
    c.instance = i;
    for (int k = 0; k < 3; ++k) c.axes[k] = Column(frames[i], k);
    c.centre = Column(frames[i], 3);
    c.normal_dot_light = c.axes[2].dot(axis_w_);
    for (int k = 0; k < 3; ++k) {
      float d = c.axes[k].dot(axis_w_);
      c.light_local[k] = d;
      // A zero component would make 0 * inf in the slab test; 1e-12 changes no answer here.
      if (std::fabs(d) < 1e-12f) d = std::copysign(1e-12f, d);
      c.inv_light_local[k] = 1.0f / d;
    }
    const Eigen::Vector3f& half = surface.half_extents;
    c.outer = half + Eigen::Vector3f::Constant(kPad);
    c.inner = half - Eigen::Vector3f::Constant(kPad);
    const float radius = half.x();
    if (surface.kind == ShapeKind::kCylinder) {
      const float core = kInscribedFraction * kHalfSqrt2 * radius - kPad;
      c.inner = Eigen::Vector3f(core, core, half.z() - kPad);
    } else if (surface.kind == ShapeKind::kCapsule || surface.kind == ShapeKind::kSphere) {
      c.segment = surface.capsule_half_length;
      c.outer_radius2 = Squared(radius + kPad);
      c.inner_radius2 = Squared(std::max(0.0f, kInscribedFraction * radius - kPad));
    }
    const Eigen::Vector3f& bound = c.outer;
    const Eigen::Vector3f centre = ToLight(c.centre);
    const Eigen::Vector3f reach(ProjectedRadius(c.axes, bound, axis_u_), ProjectedRadius(c.axes, bound, axis_v_),
                                ProjectedRadius(c.axes, bound, axis_w_));
    c.bounds = {centre.x() - reach.x(), centre.x() + reach.x(), centre.y() - reach.y(),
                centre.y() + reach.y(), centre.z() + reach.z(), static_cast<int32_t>(casters_.size())};
    casters_.push_back(c);
  }
}

int ShadowCasters::Candidates(const Eigen::Vector3f& low, const Eigen::Vector3f& high, LightBounds* out,
                              int capacity) const {
  const Eigen::Vector3f centre = 0.5f * (low + high);
  const Eigen::Vector3f half = 0.5f * (high - low) + Eigen::Vector3f::Constant(kPad);
  const Eigen::Vector3f world_axes[3] = {Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitY(), Eigen::Vector3f::UnitZ()};
  const float u = centre.dot(axis_u_), u_radius = ProjectedRadius(world_axes, half, axis_u_);
  const float v = centre.dot(axis_v_), v_radius = ProjectedRadius(world_axes, half, axis_v_);
  const float w_low = centre.dot(axis_w_) - ProjectedRadius(world_axes, half, axis_w_);
  int count = 0;
  for (std::size_t k = 0; k < casters_.size(); ++k) {
    const Caster& c = casters_[k];
    if (c.kind == ShapeKind::kPlane) {
      // Some point of the box lies on the plane's far side from the light, or near the plane:
      // the plane stands for a caster that every ray may reach.
      const float towards_light = c.normal_dot_light >= 0.0f ? 1.0f : -1.0f;
      const float nearest =
          towards_light * (centre - c.centre).dot(c.axes[2]) - ProjectedRadius(world_axes, half, c.axes[2]);
      if (c.normal_dot_light != 0.0f && nearest > kPad) continue;
      if (count == capacity) return -1;
      const float inf = std::numeric_limits<float>::infinity();
      out[count++] = {-inf, inf, -inf, inf, inf, static_cast<int32_t>(k)};
      continue;
    }
    const LightBounds& b = c.bounds;
    if (b.u0 > u + u_radius || b.u1 < u - u_radius || b.v0 > v + v_radius || b.v1 < v - v_radius || b.w1 < w_low) {
      continue;
    }
    if (OutsideFacingLight(c, centre, half, world_axes)) continue;
    if (count == capacity) return -1;
    out[count++] = b;
  }
  return count;
}

int ShadowCasters::MeetsBox4(int32_t caster, const float* x, const float* y, const float* z) const {
  const Caster& c = casters_[static_cast<std::size_t>(caster)];
#if defined(__SSE2__)
  const __m128 dx = _mm_sub_ps(_mm_loadu_ps(x), _mm_set1_ps(c.centre.x()));
  const __m128 dy = _mm_sub_ps(_mm_loadu_ps(y), _mm_set1_ps(c.centre.y()));
  const __m128 dz = _mm_sub_ps(_mm_loadu_ps(z), _mm_set1_ps(c.centre.z()));
  __m128 t_min = _mm_setzero_ps();
  __m128 t_max = _mm_set1_ps(std::numeric_limits<float>::max());
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3f& axis = c.axes[i];
    const __m128 local =
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, _mm_set1_ps(axis.x())), _mm_mul_ps(dy, _mm_set1_ps(axis.y()))),
                   _mm_mul_ps(dz, _mm_set1_ps(axis.z())));
    const __m128 inv = _mm_set1_ps(c.inv_light_local[i]);
    const __m128 half = _mm_set1_ps(c.outer[i]);
    const __m128 t1 = _mm_mul_ps(_mm_sub_ps(_mm_sub_ps(_mm_setzero_ps(), half), local), inv);
    const __m128 t2 = _mm_mul_ps(_mm_sub_ps(half, local), inv);
    t_min = _mm_max_ps(_mm_min_ps(t2, t1), t_min);  // std::max(t_min, std::min(t1, t2))
    t_max = _mm_min_ps(_mm_max_ps(t2, t1), t_max);  // std::min(t_max, std::max(t1, t2))
  }
  return _mm_movemask_ps(_mm_cmple_ps(t_min, t_max));
#else
  int bits = 0;
  for (int j = 0; j < 4; ++j) {
    const Eigen::Vector3f local = ToLocal(c, Eigen::Vector3f(x[j], y[j], z[j]));
    bits |= RayMeetsBox(local, c.inv_light_local, c.outer, false) ? 1 << j : 0;
  }
  return bits;
#endif
}

ShadowTest ShadowCasters::TestPlane(const Caster& c, const Eigen::Vector3f& origin) {
  const float side = (origin - c.centre).dot(c.axes[2]);
  return side * c.normal_dot_light > kPad * std::fabs(c.normal_dot_light) ? ShadowTest::kMiss : ShadowTest::kUnknown;
}

ShadowTest ShadowCasters::TestCore(const Caster& c, const Eigen::Vector3f& local) {
  if (c.kind == ShapeKind::kBox || c.kind == ShapeKind::kCylinder) {
    const bool has_core = c.inner.minCoeff() > 0.0f;
    return has_core && RayMeetsBox(local, c.inv_light_local, c.inner, true) ? ShadowTest::kHit : ShadowTest::kUnknown;
  }
  const float distance2 = RaySegmentDistance2(local, c.light_local, c.segment);
  if (distance2 > c.outer_radius2) return ShadowTest::kMiss;
  return distance2 < c.inner_radius2 ? ShadowTest::kHit : ShadowTest::kUnknown;
}

}  // namespace tavis::render::internal
