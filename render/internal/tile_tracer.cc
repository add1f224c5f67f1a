#include "render/internal/tile_tracer.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace tavis::render::internal {
namespace {

// Shadow rays start this far off the surface so they do not hit the facet they leave from
// (the smooth normal and the tessellated facet differ slightly on round shapes).
constexpr float kShadowRayOffset = 1e-3f;

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

RTCIntersectContext MakeContext(RTCIntersectContextFlags flags) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = flags;
  return context;
}

template <typename Ray>
void SetRay(Ray* rays, int k, const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near,
            float t_far) {
  rays->org_x[k] = origin.x();
  rays->org_y[k] = origin.y();
  rays->org_z[k] = origin.z();
  rays->dir_x[k] = direction.x();
  rays->dir_y[k] = direction.y();
  rays->dir_z[k] = direction.z();
  rays->tnear[k] = t_near;
  rays->tfar[k] = t_far;
  rays->time[k] = 0.0f;
  rays->mask[k] = ~0u;
  rays->id[k] = static_cast<unsigned int>(k);
  rays->flags[k] = 0;
}

// Primary rays of the block whose top-left pixel is (block_x, block_y); lanes outside the tile
// are invalid. Returns the number of valid lanes.
template <int K>
int SetPrimaryRays(const CameraRaster& raster, const CameraFrame& camera, const TileRect& rect, int block_x,
                   int block_y, int* valid, typename Packet<K>::RayHit* packet) {
  constexpr int kBlockWidth = Packet<K>::kBlockWidth;
  int count = 0;
  for (int k = 0; k < K; ++k) {
    const int column = block_x + k % kBlockWidth;
    const int row = block_y + k / kBlockWidth;
    const bool inside = column < rect.x1 && row < rect.y1;
    valid[k] = inside ? -1 : 0;
    count += inside ? 1 : 0;
    const float a = (raster.cx - (static_cast<float>(column) + 0.5f)) * raster.inv_fx;
    const float b = (raster.cy - (static_cast<float>(row) + 0.5f)) * raster.inv_fx;
    SetRay(&packet->ray, k, camera.origin, camera.forward + a * camera.left + b * camera.up, raster.near_m,
           raster.far_m);
    packet->hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    packet->hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
  }
  return count;
}

enum class LaneKind : uint8_t { kOutside, kMiss, kEmissive, kDiffuse };

template <int K>
TileCounts ShadeTileK(const EnvView& env, const CameraRaster& raster, const CameraFrame& camera, const TileRect& rect,
                      const Shading& shading, const ImageView& image) {
  using P = Packet<K>;
  constexpr int kBlockHeight = K / P::kBlockWidth;
  const LightingModel& lighting = *shading.lighting;
  const SrgbEncoder& encoder = *shading.encoder;
  RTCIntersectContext primary_context = MakeContext(RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
  // Shadow packets are traced without the coherent hint: with it, rtcOccluded16 of Embree 3.13.5
  // never returned on an AVX-512 AMD CPU (observed on the development machine).
  RTCIntersectContext shadow_context = MakeContext(RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
  alignas(64) int valid[K];
  alignas(64) int shadow_valid[K];
  alignas(64) typename P::RayHit primary;
  alignas(64) typename P::Ray shadow;
  LaneKind kind[K];
  Eigen::Vector3f colour[K];
  Eigen::Vector3f normal[K];
  float cosine[K];
  TileCounts counts;
  // Inactive lanes keep harmless finite rays.
  for (int k = 0; k < K; ++k) SetRay(&shadow, k, camera.origin, lighting.to_light(), 0.0f, 0.0f);

  for (int block_y = rect.y0; block_y < rect.y1; block_y += kBlockHeight) {
    for (int block_x = rect.x0; block_x < rect.x1; block_x += P::kBlockWidth) {
      counts.primary_rays += SetPrimaryRays<K>(raster, camera, rect, block_x, block_y, valid, &primary);
      P::Intersect(valid, env.scene, &primary_context, &primary);

      int shadow_count = 0;
      for (int k = 0; k < K; ++k) {
        shadow_valid[k] = 0;
        if (valid[k] == 0) {
          kind[k] = LaneKind::kOutside;
          continue;
        }
        if (primary.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) {
          kind[k] = LaneKind::kMiss;
          colour[k] = lighting.background();
          continue;
        }
        ++counts.primary_hits;
        const unsigned int instance = primary.hit.instID[0][k];
        const InstanceFrame& frame = env.frames[instance];
        const SurfaceModel& surface = env.surfaces[instance];
        const Eigen::Vector3f direction(primary.ray.dir_x[k], primary.ray.dir_y[k], primary.ray.dir_z[k]);
        const Eigen::Vector3f p = camera.origin + primary.ray.tfar[k] * direction;
        const Eigen::Vector3f base = env.rgb_override != nullptr ? env.rgb_override[instance] : surface.appearance.rgb;
        if (surface.appearance.emissive) {
          kind[k] = LaneKind::kEmissive;
          colour[k] = base;
          continue;
        }
        const Eigen::Vector3f p_local = frame.ToLocal(p);
        const Eigen::Vector3f n_local = LocalNormal(surface, p_local, primary.hit.primID[k]);
        Eigen::Vector3f n = frame.RotateToWorld(n_local);
        if (n.dot(direction) > 0.0f) n = -n;  // seen from behind (a plane from below, a camera inside)
        kind[k] = LaneKind::kDiffuse;
        colour[k] = Reflectance(surface, base, p_local, n_local);
        normal[k] = n;
        cosine[k] = std::max(0.0f, n.dot(lighting.to_light()));
        if (cosine[k] > 0.0f && lighting.shadows()) {
          shadow_valid[k] = -1;
          ++shadow_count;
          SetRay(&shadow, k, p + kShadowRayOffset * n, lighting.to_light(), 0.0f,
                 std::numeric_limits<float>::infinity());
        }
      }
      if (shadow_count > 0) {
        P::Occluded(shadow_valid, env.scene, &shadow_context, &shadow);
        counts.shadow_rays += shadow_count;
      }

      for (int k = 0; k < K; ++k) {
        if (kind[k] == LaneKind::kOutside) continue;
        const int column = block_x + k % P::kBlockWidth;
        const int row = block_y + k / P::kBlockWidth;
        const std::size_t pixel = static_cast<std::size_t>(row) * static_cast<std::size_t>(image.width) +
                                  static_cast<std::size_t>(column);
        Eigen::Vector3f linear = colour[k];
        if (kind[k] == LaneKind::kDiffuse) {
          // rtcOccluded sets tfar to -inf for blocked rays.
          const bool blocked = shadow_valid[k] != 0 && shadow.tfar[k] < 0.0f;
          linear = lighting.Shade(colour[k], normal[k], blocked ? 0.0f : cosine[k]);
        }
        uint8_t* rgb = image.rgb + 3 * pixel;
        rgb[0] = encoder.Encode(linear.x());
        rgb[1] = encoder.Encode(linear.y());
        rgb[2] = encoder.Encode(linear.z());
        const bool hit = kind[k] != LaneKind::kMiss;
        if (image.depth != nullptr) image.depth[pixel] = hit ? primary.ray.tfar[k] : 0.0f;
        if (image.object_id != nullptr) {
          image.object_id[pixel] =
              hit ? env.surfaces[primary.hit.instID[0][k]].object_id : kBackgroundObjectId;
        }
      }
    }
  }
  return counts;
}

template <int K>
TileCounts CastPrimaryTileK(const EnvView& env, const CameraRaster& raster, const CameraFrame& camera,
                            const TileRect& rect) {
  using P = Packet<K>;
  constexpr int kBlockHeight = K / P::kBlockWidth;
  RTCIntersectContext context = MakeContext(RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
  alignas(64) int valid[K];
  alignas(64) typename P::RayHit primary;
  TileCounts counts;
  for (int block_y = rect.y0; block_y < rect.y1; block_y += kBlockHeight) {
    for (int block_x = rect.x0; block_x < rect.x1; block_x += P::kBlockWidth) {
      counts.primary_rays += SetPrimaryRays<K>(raster, camera, rect, block_x, block_y, valid, &primary);
      P::Intersect(valid, env.scene, &context, &primary);
      for (int k = 0; k < K; ++k) {
        if (valid[k] != 0 && primary.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID) ++counts.primary_hits;
      }
    }
  }
  return counts;
}

}  // namespace

int PreferredPacketWidth(RTCDevice device) {
  return rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0 ? 16 : 8;
}

TileCounts ShadeTile(int packet_width, const EnvView& env, const CameraRaster& raster, const CameraFrame& camera,
                     const TileRect& rect, const Shading& shading, const ImageView& image) {
  return packet_width == 16 ? ShadeTileK<16>(env, raster, camera, rect, shading, image)
                            : ShadeTileK<8>(env, raster, camera, rect, shading, image);
}

TileCounts CastPrimaryTile(int packet_width, const EnvView& env, const CameraRaster& raster, const CameraFrame& camera,
                           const TileRect& rect) {
  return packet_width == 16 ? CastPrimaryTileK<16>(env, raster, camera, rect)
                            : CastPrimaryTileK<8>(env, raster, camera, rect);
}

void ClearTile(const TileRect& rect, const ImageView& image) {
  const std::size_t width = static_cast<std::size_t>(rect.x1 - rect.x0);
  for (int row = rect.y0; row < rect.y1; ++row) {
    const std::size_t first = static_cast<std::size_t>(row) * static_cast<std::size_t>(image.width) +
                              static_cast<std::size_t>(rect.x0);
    std::memset(image.rgb + 3 * first, 0, 3 * width);
    if (image.depth != nullptr) std::fill_n(image.depth + first, width, 0.0f);
    if (image.object_id != nullptr) std::fill_n(image.object_id + first, width, kBackgroundObjectId);
  }
}

}  // namespace tavis::render::internal
