#include "render/internal/tile_tracer.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include "render/internal/packet_shading.h"

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

// Lane k of a packet covers pixel (block_x + kLaneColumn[k], block_y + kLaneRow[k]).
template <int K>
struct LaneOffsets {
  float column[K];
  float row[K];
  int column_index[K];
  int row_index[K];
  constexpr LaneOffsets() : column(), row(), column_index(), row_index() {
    for (int k = 0; k < K; ++k) {
      column_index[k] = k % Packet<K>::kBlockWidth;
      row_index[k] = k / Packet<K>::kBlockWidth;
      column[k] = static_cast<float>(column_index[k]);
      row[k] = static_cast<float>(row_index[k]);
    }
  }
};

// Directions of the primary rays of the block whose top-left pixel is (block_x, block_y), in
// structure-of-arrays loops the compiler vectorises; lanes outside the tile are invalid. The
// other ray fields come from SetTileConstants. Returns the number of valid lanes.
template <int K>
int SetPrimaryRays(const CameraRaster& raster, const CameraFrame& camera, const TileRect& rect, int block_x,
                   int block_y, int* valid, typename Packet<K>::RayHit* packet) {
  static constexpr LaneOffsets<K> kLanes;
  const int columns_left = rect.x1 - block_x;
  const int rows_left = rect.y1 - block_y;
  const float x0 = static_cast<float>(block_x);
  const float y0 = static_cast<float>(block_y);
  int count = 0;
  for (int k = 0; k < K; ++k) {
    const bool inside = kLanes.column_index[k] < columns_left && kLanes.row_index[k] < rows_left;
    valid[k] = inside ? -1 : 0;
    count += inside ? 1 : 0;
  }
  for (int k = 0; k < K; ++k) {
    const float a = (raster.cx - ((x0 + kLanes.column[k]) + 0.5f)) * raster.inv_fx;
    const float b = (raster.cy - ((y0 + kLanes.row[k]) + 0.5f)) * raster.inv_fx;
    packet->ray.dir_x[k] = camera.forward.x() + a * camera.left.x() + b * camera.up.x();
    packet->ray.dir_y[k] = camera.forward.y() + a * camera.left.y() + b * camera.up.y();
    packet->ray.dir_z[k] = camera.forward.z() + a * camera.left.z() + b * camera.up.z();
    packet->ray.tfar[k] = raster.far_m;
    packet->hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    packet->hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
  }
  return count;
}

// Writes the pixels of a packet's lanes: sRGB colour, and depth and object id where the image
// has them. The colours' table indices are computed for all lanes at once.
template <int K>
void WriteLanes(const ImageView& image, const SrgbEncoder& encoder, const float (&linear)[3][K], const int32_t* write,
                const std::size_t* pixel, const float* depth, const int32_t* object_id) {
  alignas(64) int32_t index[3][K];
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < K; ++k) index[c][k] = SrgbEncoder::TableIndex(linear[c][k]);
  }
  for (int k = 0; k < K; ++k) {
    if (write[k] == 0) continue;
    uint8_t* rgb = image.rgb + 3 * pixel[k];
    rgb[0] = encoder.Lookup(index[0][k]);
    rgb[1] = encoder.Lookup(index[1][k]);
    rgb[2] = encoder.Lookup(index[2][k]);
    if (image.depth != nullptr) image.depth[pixel[k]] = depth[k];
    if (image.object_id != nullptr) image.object_id[pixel[k]] = object_id[k];
  }
}

// Lit diffuse pixels waiting for their shadow ray, packed into full packets across the blocks of
// a tile: one rtcOccluded call per K waiting pixels rather than one per block. What each pixel
// needs once its shadow ray is known is kept in structure-of-arrays form, lane k for ray k.
template <int K>
class ShadowQueue {
 public:
  explicit ShadowQueue(const Eigen::Vector3f& to_light)
      : context_(MakeContext(RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT)) {
    // Shadow rays all go towards the distant light; only their origins change.
    SetTileConstants<K>(&rays_, Eigen::Vector3f::Zero(), 0.0f);
    for (int k = 0; k < K; ++k) {
      rays_.dir_x[k] = to_light.x();
      rays_.dir_y[k] = to_light.y();
      rays_.dir_z[k] = to_light.z();
    }
  }

  bool full() const { return size_ == K; }

  // Queues lane k of a shaded packet: its shadow ray leaves p + kShadowRayOffset * n.
  void Push(const HitGeometry<K>& hit, const float (&colour)[3][K], int k, std::size_t pixel, float depth,
            int32_t object_id) {
    rays_.org_x[size_] = hit.p[0][k] + kShadowRayOffset * hit.n[0][k];
    rays_.org_y[size_] = hit.p[1][k] + kShadowRayOffset * hit.n[1][k];
    rays_.org_z[size_] = hit.p[2][k] + kShadowRayOffset * hit.n[2][k];
    for (int c = 0; c < 3; ++c) colour_[c][size_] = colour[c][k];
    nz_[size_] = hit.n[2][k];
    cosine_[size_] = hit.cosine[k];
    pixel_[size_] = pixel;
    depth_[size_] = depth;
    object_id_[size_] = object_id;
    ++size_;
  }

  // Traces the waiting shadow rays, writes their pixels and empties the queue; returns the number
  // of rays traced.
  int Flush(RTCScene scene, const Shading& shading, const ImageView& image) {
    if (size_ == 0) return 0;
    alignas(64) int valid[K];
    for (int k = 0; k < K; ++k) {
      valid[k] = k < size_ ? -1 : 0;
      rays_.tfar[k] = k < size_ ? std::numeric_limits<float>::infinity() : 0.0f;  // inactive lanes stay finite
    }
    Packet<K>::Occluded(valid, scene, &context_, &rays_);
    alignas(64) float direct_cosine[K];
    for (int k = 0; k < K; ++k) {
      // rtcOccluded sets tfar to -inf for blocked rays.
      direct_cosine[k] = Blend(rays_.tfar[k] < 0.0f, 0.0f, cosine_[k]);
    }
    alignas(64) float linear[3][K];
    shading.lighting->ShadeLanes<K>(colour_, nz_, direct_cosine, linear);
    WriteLanes<K>(image, *shading.encoder, linear, valid, pixel_, depth_, object_id_);
    const int traced = size_;
    size_ = 0;
    return traced;
  }

 private:
  // Shadow packets are traced without the coherent hint: with it, rtcOccluded16 of Embree 3.13.5
  // never returned on an AVX-512 AMD CPU (observed on the development machine).
  RTCIntersectContext context_;
  alignas(64) typename Packet<K>::Ray rays_;
  alignas(64) float colour_[3][K] = {};
  alignas(64) float nz_[K] = {};
  alignas(64) float cosine_[K] = {};
  alignas(64) float depth_[K] = {};
  alignas(64) int32_t object_id_[K] = {};
  std::size_t pixel_[K] = {};
  int size_ = 0;
};

// The reflectance a hit on `instance` starts from: the per-env override or the palette colour.
// Every albedo the shading reads comes through here.
inline Eigen::Vector3f BaseReflectance(const EnvView& env, unsigned int instance) {
  return env.rgb_override != nullptr ? env.rgb_override[instance] : env.surfaces[instance].appearance.rgb;
}

template <int K>
TileCounts ShadeTileK(const EnvView& env, const CameraRaster& raster, const CameraFrame& camera, const TileRect& rect,
                      const Shading& shading, const ImageView& image) {
  using P = Packet<K>;
  static constexpr LaneOffsets<K> kLanes;
  constexpr int kBlockHeight = K / P::kBlockWidth;
  const LightingModel& lighting = *shading.lighting;
  const Eigen::Vector3f to_light = lighting.to_light();
  const bool shadows = lighting.shadows();
  RTCIntersectContext primary_context = MakeContext(RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
  alignas(64) int valid[K];
  alignas(64) typename P::RayHit primary;
  alignas(64) HitLanes<K> lanes;
  alignas(64) HitGeometry<K> hit;
  alignas(64) float colour[3][K];
  alignas(64) float shaded[3][K];
  alignas(64) float linear[3][K];
  alignas(64) float depth[K];
  alignas(64) int32_t write_now[K];
  std::size_t pixel[K];
  ShadowQueue<K> queue(to_light);
  TileCounts counts;
  SetTileConstants<K>(&primary.ray, camera.origin, raster.near_m);

  for (int block_y = rect.y0; block_y < rect.y1; block_y += kBlockHeight) {
    for (int block_x = rect.x0; block_x < rect.x1; block_x += P::kBlockWidth) {
      counts.primary_rays += SetPrimaryRays<K>(raster, camera, rect, block_x, block_y, valid, &primary);
      P::Intersect(valid, env.scene, &primary_context, &primary);

      // Scalar pass: what each lane hit.
      for (int k = 0; k < K; ++k) {
        pixel[k] = static_cast<std::size_t>(block_y + kLanes.row_index[k]) * static_cast<std::size_t>(image.width) +
                   static_cast<std::size_t>(block_x + kLanes.column_index[k]);
        if (valid[k] == 0) {
          lanes.SetEmpty(k, LaneKind::kInactive, lighting.background());
        } else if (primary.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) {
          lanes.SetEmpty(k, LaneKind::kMiss, lighting.background());
        } else {
          ++counts.primary_hits;
          const unsigned int instance = primary.hit.instID[0][k];
          lanes.GatherHit(k, env.surfaces[instance], env.frames[instance], primary.hit.primID[k],
                          BaseReflectance(env, instance));
        }
      }

      // Lane-parallel: hit points, normals, the light's cosine.
      ComputeHitGeometry<K>(camera.origin, primary.ray.dir_x, primary.ray.dir_y, primary.ray.dir_z, primary.ray.tfar,
                            to_light, lanes, &hit);
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < K; ++k) colour[c][k] = lanes.base[c][k];
      }
      // Labels (scalar, only on labelled surfaces).
      for (int k = 0; k < K; ++k) {
        if (lanes.labelled[k] == nullptr || lanes.kind[k] != LaneKind::kDiffuse) continue;
        const SurfaceModel& surface = *lanes.labelled[k];
        const Eigen::Vector3f p_local(hit.p_local[0][k], hit.p_local[1][k], hit.p_local[2][k]);
        const Eigen::Vector3f n_local(hit.n_local[0][k], hit.n_local[1][k], hit.n_local[2][k]);
        if (InsideLabel(surface, p_local, n_local)) {
          for (int c = 0; c < 3; ++c) colour[c][k] = surface.appearance.label_rgb[c];
        }
      }

      // Lane-parallel: lighting without shadows; misses show the dome, emissive lanes their colour.
      lighting.ShadeLanes<K>(colour, hit.n[2], hit.cosine, shaded);
      for (int k = 0; k < K; ++k) {
        const bool diffuse = lanes.kind[k] == LaneKind::kDiffuse;
        const bool miss = lanes.kind[k] == LaneKind::kMiss;
        linear[0][k] = Blend(diffuse, shaded[0][k], colour[0][k]);
        linear[1][k] = Blend(diffuse, shaded[1][k], colour[1][k]);
        linear[2][k] = Blend(diffuse, shaded[2][k], colour[2][k]);
        depth[k] = Blend(miss, 0.0f, primary.ray.tfar[k]);
        // Lit diffuse lanes wait for their shadow ray; the others are final now. (& rather than
        // &&: no branches in the loop.)
        const bool waits = shadows & diffuse & (hit.cosine[k] > 0.0f);
        write_now[k] = -static_cast<int32_t>((lanes.kind[k] != LaneKind::kInactive) & !waits);
      }
      WriteLanes<K>(image, *shading.encoder, linear, write_now, pixel, depth, lanes.object_id);

      for (int k = 0; k < K; ++k) {
        if (write_now[k] != 0 || lanes.kind[k] != LaneKind::kDiffuse) continue;
        queue.Push(hit, colour, k, pixel[k], depth[k], lanes.object_id[k]);
        if (queue.full()) counts.shadow_rays += queue.Flush(env.scene, shading, image);
      }
    }
  }
  counts.shadow_rays += queue.Flush(env.scene, shading, image);
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
  SetTileConstants<K>(&primary.ray, camera.origin, raster.near_m);
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
