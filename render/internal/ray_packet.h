// Embree ray packets of 8 or 16 rays: the types and calls for each width, and the set-up of the
// fields that stay the same for a whole tile.
#pragma once

#include <embree3/rtcore.h>
#include <Eigen/Core>

namespace tavis::render::internal {

// Packet types and calls for each width; a packet covers a block of pixels so its rays are coherent.
template <int K>
struct Packet;

template <>
struct Packet<8> {
  using RayHit = RTCRayHit8;
  using Ray = RTCRay8;
  static constexpr int kBlockWidth = 4;  // 4 x 2 pixels
  static void Intersect(const int* valid, RTCScene scene, RTCIntersectContext* context, RayHit* rays) {
    rtcIntersect8(valid, scene, context, rays);
  }
  static void Occluded(const int* valid, RTCScene scene, RTCIntersectContext* context, Ray* rays) {
    rtcOccluded8(valid, scene, context, rays);
  }
};

template <>
struct Packet<16> {
  using RayHit = RTCRayHit16;
  using Ray = RTCRay16;
  static constexpr int kBlockWidth = 4;  // 4 x 4 pixels
  static void Intersect(const int* valid, RTCScene scene, RTCIntersectContext* context, RayHit* rays) {
    rtcIntersect16(valid, scene, context, rays);
  }
  static void Occluded(const int* valid, RTCScene scene, RTCIntersectContext* context, Ray* rays) {
    rtcOccluded16(valid, scene, context, rays);
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
