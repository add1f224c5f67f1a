// Embree ray packets of 8 or 16 rays: the types and calls for each width, and the set-up of the
// fields that stay the same for a whole tile.
#pragma once

#include <type_traits>

#include <embree3/rtcore.h>
#include <Eigen/Core>

namespace tavis::render::internal {

// Packet types and calls for each width (8 or 16); a packet covers a block of pixels 4 wide
// (4 x 2 or 4 x 4) so its rays are coherent.
template <int K>
struct Packet {
  static_assert(K == 8 || K == 16, "Embree packets of 8 or 16 rays");
  using RayHit = std::conditional_t<K == 8, RTCRayHit8, RTCRayHit16>;
  using Ray = std::conditional_t<K == 8, RTCRay8, RTCRay16>;
  static constexpr int kBlockWidth = 4;
  static void Intersect(const int* valid, RTCScene scene, RTCIntersectContext* context, RayHit* rays) {
    if constexpr (K == 8) {
      rtcIntersect8(valid, scene, context, rays);
    } else {
      rtcIntersect16(valid, scene, context, rays);
    }
  }
  static void Occluded(const int* valid, RTCScene scene, RTCIntersectContext* context, Ray* rays) {
    if constexpr (K == 8) {
      rtcOccluded8(valid, scene, context, rays);
    } else {
      rtcOccluded16(valid, scene, context, rays);
    }
  }
};

inline RTCIntersectContext MakeContext(RTCIntersectContextFlags flags) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = flags;
  return context;
}

// Fields that stay the same for every ray of a packet during one tile (Embree writes only tfar and
// the hit): set once per tile instead of once per block.
template <int K, typename Ray>
void SetTileConstants(Ray* rays, const Eigen::Vector3f& origin, float t_near) {
  for (int k = 0; k < K; ++k) {
    rays->org_x[k] = origin.x();
    rays->org_y[k] = origin.y();
    rays->org_z[k] = origin.z();
    rays->tnear[k] = t_near;
    rays->time[k] = 0.0f;
    rays->mask[k] = ~0u;
    rays->id[k] = static_cast<unsigned int>(k);
    rays->flags[k] = 0;
  }
}

}  // namespace tavis::render::internal
