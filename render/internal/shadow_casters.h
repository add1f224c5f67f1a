// Answers most shadow rays of one env without tracing them, exactly as Embree would.
//
// Every shadow ray of the distant light runs along the same direction L. For each visible
// instance this keeps, once per render, its bounds across and along L (to pick the instances
// that could block any ray of a tile) and its pose, so that a ray can be tested against the
// instance's exact shape with two margins: a ray that misses the shape grown by kPad misses its
// mesh (the meshes lie inside their shapes), and a ray that passes through the shape's inner
// core (shrunk by the tessellation error and kPad) crosses its closed mesh, so Embree reports it
// blocked. Only rays between the two (grazing an edge or a silhouette) still need Embree, so the
// images are the same as with every ray traced. Planes (the floor) block only rays that start on
// their side facing away from the light; such rays are left to Embree. A ray leaving a box
// outwards needs no special case: it starts 1 mm off the face, outside the grown box.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <Eigen/Core>

#include "render/internal/env_scenes.h"
#include "render/internal/surface_shading.h"

namespace tavis::render::internal {

enum class ShadowTest : uint8_t { kMiss, kHit, kUnknown };

// A caster's bounds in the light frame (u, v across the light, w along it): a ray from a point
// (u, v, w) can meet the caster only if u0 <= u <= u1, v0 <= v <= v1 and w <= w1.
struct LightBounds {
  float u0, u1, v0, v1, w1;
  int32_t caster;

  bool MayReach(const Eigen::Vector3f& uvw) const {
    return uvw.x() >= u0 && uvw.x() <= u1 && uvw.y() >= v0 && uvw.y() <= v1 && uvw.z() <= w1;
  }

  // MayReach for the four points (u[j], v[j], w[j]), j < 4, as bit j of the result (a NaN
  // coordinate never reaches). One SIMD test for four pixels instead of a branch per bound.
  int MayReach4(const float* u, const float* v, const float* w) const {
#if defined(__SSE2__)
    const __m128 pu = _mm_loadu_ps(u);
    const __m128 pv = _mm_loadu_ps(v);
    const __m128 inside_u = _mm_and_ps(_mm_cmpge_ps(pu, _mm_set1_ps(u0)), _mm_cmple_ps(pu, _mm_set1_ps(u1)));
    const __m128 inside_v = _mm_and_ps(_mm_cmpge_ps(pv, _mm_set1_ps(v0)), _mm_cmple_ps(pv, _mm_set1_ps(v1)));
    const __m128 below_w = _mm_cmple_ps(_mm_loadu_ps(w), _mm_set1_ps(w1));
    return _mm_movemask_ps(_mm_and_ps(_mm_and_ps(inside_u, inside_v), below_w));
#else
    int bits = 0;
    for (int j = 0; j < 4; ++j) bits |= MayReach(Eigen::Vector3f(u[j], v[j], w[j])) ? 1 << j : 0;
    return bits;
#endif
  }
};

// Whether the ray o + s d, s >= 0, meets the box |x_i| <= half_i (strictly inside when `strict`);
// inv_d holds the reciprocals of d's components.
inline bool RayMeetsBox(const Eigen::Vector3f& o, const Eigen::Vector3f& inv_d, const Eigen::Vector3f& half,
                        bool strict) {
  float t_min = 0.0f;
  float t_max = std::numeric_limits<float>::max();
  for (int i = 0; i < 3; ++i) {
    const float t1 = (-half[i] - o[i]) * inv_d[i];
    const float t2 = (half[i] - o[i]) * inv_d[i];
    t_min = std::max(t_min, std::min(t1, t2));
    t_max = std::min(t_max, std::max(t1, t2));
  }
  return strict ? t_min < t_max : t_min <= t_max;
}

class ShadowCasters {
 public:
  ShadowCasters() = default;
  // Sizes every buffer for `n_instances` so that Build does not allocate.
  ShadowCasters(const Eigen::Vector3f& to_light, int n_instances);

  // Takes the instances with visible[i] != 0 at their frames for this render.
  void Build(const InstanceFrame* frames, const SurfaceModel* surfaces, const uint8_t* visible);

  // Writes the casters that could block a shadow ray from any point of the axis-aligned box
  // [low, high] into `out` and returns their number, or -1 if more than `capacity` could.
  int Candidates(const Eigen::Vector3f& low, const Eigen::Vector3f& high, LightBounds* out, int capacity) const;

  // World point -> (u, v, w) in the light frame.
  Eigen::Vector3f ToLight(const Eigen::Vector3f& p) const { return {p.dot(axis_u_), p.dot(axis_v_), p.dot(axis_w_)}; }

  // The shadow ray from `origin` against caster `caster` (an index from Candidates). Inline up to
  // the bounding-box test, which most rays fail.
  ShadowTest Test(int32_t caster, const Eigen::Vector3f& origin) const {
    const Caster& c = casters_[static_cast<std::size_t>(caster)];
    if (c.kind == ShapeKind::kPlane) return TestPlane(c, origin);
    const Eigen::Vector3f local = ToLocal(c, origin);
    if (!RayMeetsBox(local, c.inv_light_local, c.outer, false)) return ShadowTest::kMiss;
    return TestCore(c, local);
  }

  bool IsPlane(int32_t caster) const { return casters_[static_cast<std::size_t>(caster)].kind == ShapeKind::kPlane; }

  // Test's bounding-box step for four origins (x[j], y[j], z[j]) of a caster that is not a plane:
  // bit j set where the ray may meet the caster, so that TestPastBox must decide it; a clear bit
  // is a miss. The same test as Test's, four rays in one SIMD pass (the float operations may
  // round differently from the scalar ones, which the box's margin kPad absorbs).
  int MeetsBox4(int32_t caster, const float* x, const float* y, const float* z) const;

  // Test for an origin whose ray MeetsBox4 did not rule out.
  ShadowTest TestPastBox(int32_t caster, const Eigen::Vector3f& origin) const {
    const Caster& c = casters_[static_cast<std::size_t>(caster)];
    return TestCore(c, ToLocal(c, origin));
  }

 private:
  struct Caster {
    ShapeKind kind;
    int32_t instance;
    Eigen::Vector3f axes[3];  // local axes in world coordinates
    Eigen::Vector3f centre;
    Eigen::Vector3f outer;  // box, cylinder: half sizes grown by the margin
    Eigen::Vector3f inner;  // box, cylinder: half sizes of the core every ray through which is blocked
    float segment = 0.0f;   // capsule, sphere: half length of the axis segment (0 for a sphere)
    float outer_radius2 = 0.0f;
    float inner_radius2 = 0.0f;
    Eigen::Vector3f light_local;      // L in local coordinates
    Eigen::Vector3f inv_light_local;  // its reciprocals (finite: tiny components are nudged)
    LightBounds bounds;
    // Planes: the normal and the plane's offset along it.
    float normal_dot_light = 0.0f;
  };

  static Eigen::Vector3f ToLocal(const Caster& c, const Eigen::Vector3f& origin) {
    const Eigen::Vector3f offset = origin - c.centre;
    return {offset.dot(c.axes[0]), offset.dot(c.axes[1]), offset.dot(c.axes[2])};
  }
  static ShadowTest TestPlane(const Caster& c, const Eigen::Vector3f& origin);
  // The tests after the bounding box: the box or cylinder core, the capsule or sphere radii.
  static ShadowTest TestCore(const Caster& c, const Eigen::Vector3f& local);
  static bool OutsideFacingLight(const Caster& c, const Eigen::Vector3f& centre, const Eigen::Vector3f& half,
                                 const Eigen::Vector3f* world_axes);

  Eigen::Vector3f axis_u_ = Eigen::Vector3f::UnitX();
  Eigen::Vector3f axis_v_ = Eigen::Vector3f::UnitY();
  Eigen::Vector3f axis_w_ = Eigen::Vector3f::UnitZ();
  int n_instances_ = 0;
  std::vector<Caster> casters_;  // the visible instances
};

}  // namespace tavis::render::internal
