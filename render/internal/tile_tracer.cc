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
// other ray fields come from SetTileConstants. Returns the number of valid lanes. Always inline:
// with the textured instantiations of ShadeTileK beside the untextured ones GCC stopped inlining
// it, and the call cost 100 more instructions per block (callgrind, bench/render_bench.cc).
template <int K>
[[gnu::always_inline]] inline int SetPrimaryRays(const CameraRaster& raster, const CameraFrame& camera,
                                                 const TileRect& rect, int block_x, int block_y, int* valid,
                                                 typename Packet<K>::RayHit* packet) {
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

// Writes one shaded pixel: sRGB colour, and depth and object id where the image has them.
struct PixelWriter {
  const ImageView& image;
  const SrgbEncoder& encoder;

  void Write(std::size_t pixel, const Eigen::Vector3f& linear, float depth, int32_t object_id) const {
    uint8_t* rgb = image.rgb + 3 * pixel;
    rgb[0] = encoder.Encode(linear.x());
    rgb[1] = encoder.Encode(linear.y());
    rgb[2] = encoder.Encode(linear.z());
    if (image.depth != nullptr) image.depth[pixel] = depth;
    if (image.object_id != nullptr) image.object_id[pixel] = object_id;
  }
};

// Lit diffuse pixels waiting for their shadow ray, packed into full packets across the blocks of
// a tile: one rtcOccluded call per K waiting pixels rather than one per block.
template <int K>
class ShadowQueue {
 public:
  // What a waiting pixel needs once its shadow ray is known.
  struct Waiting {
    std::size_t pixel;
    Eigen::Vector3f colour;
    Eigen::Vector3f normal;
    float cosine;
    float depth;
    int32_t object_id;
  };

  explicit ShadowQueue(const Eigen::Vector3f& to_light) : context_(MakeContext(RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT)) {
    // Shadow rays all go towards the distant light; only their origins change.
    SetTileConstants<K>(&rays_, Eigen::Vector3f::Zero(), 0.0f);
    for (int k = 0; k < K; ++k) {
      rays_.dir_x[k] = to_light.x();
      rays_.dir_y[k] = to_light.y();
      rays_.dir_z[k] = to_light.z();
    }
  }

  bool full() const { return size_ == K; }

  void Push(const Eigen::Vector3f& origin, const Waiting& waiting) {
    rays_.org_x[size_] = origin.x();
    rays_.org_y[size_] = origin.y();
    rays_.org_z[size_] = origin.z();
    waiting_[size_] = waiting;
    ++size_;
  }

  // Traces the waiting shadow rays, writes their pixels and empties the queue; returns the number
  // of rays traced.
  int Flush(RTCScene scene, const LightingModel& lighting, const PixelWriter& writer) {
    if (size_ == 0) return 0;
    alignas(64) int valid[K];
    for (int k = 0; k < K; ++k) {
      valid[k] = k < size_ ? -1 : 0;
      rays_.tfar[k] = k < size_ ? std::numeric_limits<float>::infinity() : 0.0f;  // inactive lanes stay finite
    }
    Packet<K>::Occluded(valid, scene, &context_, &rays_);
    for (int k = 0; k < size_; ++k) {
      const Waiting& w = waiting_[k];
      // rtcOccluded sets tfar to -inf for blocked rays.
      const bool blocked = rays_.tfar[k] < 0.0f;
      writer.Write(w.pixel, lighting.Shade(w.colour, w.normal, blocked ? 0.0f : w.cosine), w.depth, w.object_id);
    }
    const int traced = size_;
    size_ = 0;
    return traced;
  }

 private:
  // Shadow packets are traced without the coherent hint: with it, rtcOccluded16 of Embree 3.13.5
  // never returned on an AVX-512 AMD CPU (observed on the development machine).
  RTCIntersectContext context_;
  alignas(64) typename Packet<K>::Ray rays_;
  Waiting waiting_[K];
  int size_ = 0;
};

// kTextured: whether the env has textures (EnvView::textures). The untextured instantiation folds
// the texture lookup away, so its loop is exactly the one without textures (sharing one loop cost
// the untextured pixels 2.5% more instructions: callgrind, bench/render_bench.cc).
template <int K, bool kTextured>
TileCounts ShadeTileK(const EnvView& env, const CameraRaster& raster, const CameraFrame& camera, const TileRect& rect,
                      const Shading& shading, const ImageView& image) {
  using P = Packet<K>;
  static constexpr LaneOffsets<K> kLanes;
  constexpr int kBlockHeight = K / P::kBlockWidth;
  const LightingModel& lighting = *shading.lighting;
  const PixelWriter writer{image, *shading.encoder};
  const Eigen::Vector3f to_light = lighting.to_light();
  const bool shadows = lighting.shadows();
  RTCIntersectContext primary_context = MakeContext(RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
  alignas(64) int valid[K];
  alignas(64) typename P::RayHit primary;
  ShadowQueue<K> queue(to_light);
  TileCounts counts;
  SetTileConstants<K>(&primary.ray, camera.origin, raster.near_m);

  for (int block_y = rect.y0; block_y < rect.y1; block_y += kBlockHeight) {
    for (int block_x = rect.x0; block_x < rect.x1; block_x += P::kBlockWidth) {
      counts.primary_rays += SetPrimaryRays<K>(raster, camera, rect, block_x, block_y, valid, &primary);
      P::Intersect(valid, env.scene, &primary_context, &primary);

      for (int k = 0; k < K; ++k) {
        if (valid[k] == 0) continue;
        const std::size_t pixel =
            static_cast<std::size_t>(block_y + kLanes.row_index[k]) * static_cast<std::size_t>(image.width) +
            static_cast<std::size_t>(block_x + kLanes.column_index[k]);
        if (primary.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) {
          writer.Write(pixel, lighting.background(), 0.0f, kBackgroundObjectId);
          continue;
        }
        ++counts.primary_hits;
        const unsigned int instance = primary.hit.instID[0][k];
        const SurfaceModel& surface = env.surfaces[instance];
        const float depth = primary.ray.tfar[k];
        const Eigen::Vector3f base = env.rgb_override != nullptr ? env.rgb_override[instance] : surface.appearance.rgb;
        if (surface.appearance.emissive) {
          writer.Write(pixel, base, depth, surface.object_id);
          continue;
        }
        const InstanceFrame& frame = env.frames[instance];
        const Eigen::Vector3f direction(primary.ray.dir_x[k], primary.ray.dir_y[k], primary.ray.dir_z[k]);
        const Eigen::Vector3f p = camera.origin + depth * direction;
        // Plain boxes and planes (floor, table, most links) need no local point: their normal
        // follows from the triangle and they have no label.
        const Eigen::Vector3f p_local = NeedsLocalPoint(surface) ? frame.ToLocal(p) : Eigen::Vector3f::Zero();
        const Eigen::Vector3f n_local = LocalNormal(surface, p_local, primary.hit.primID[k]);
        Eigen::Vector3f n = frame.RotateToWorld(n_local);
        if (n.dot(direction) > 0.0f) n = -n;  // seen from behind (a plane from below, a camera inside)
        const Eigen::Vector3f colour =
            Reflectance(surface, TexturedBase(kTextured ? env.textures : nullptr, instance, frame, p, n_local, base),
                        p_local, n_local);
        const float cosine = std::max(0.0f, n.dot(to_light));
        if (cosine > 0.0f && shadows) {
          queue.Push(p + kShadowRayOffset * n, {pixel, colour, n, cosine, depth, surface.object_id});
          if (queue.full()) counts.shadow_rays += queue.Flush(env.scene, lighting, writer);
          continue;
        }
        writer.Write(pixel, lighting.Shade(colour, n, cosine), depth, surface.object_id);
      }
    }
  }
  counts.shadow_rays += queue.Flush(env.scene, lighting, writer);
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
  if (env.textures != nullptr) {
    return packet_width == 16 ? ShadeTileK<16, true>(env, raster, camera, rect, shading, image)
                              : ShadeTileK<8, true>(env, raster, camera, rect, shading, image);
  }
  return packet_width == 16 ? ShadeTileK<16, false>(env, raster, camera, rect, shading, image)
                            : ShadeTileK<8, false>(env, raster, camera, rect, shading, image);
}

TileCounts CastPrimaryTile(int packet_width, const EnvView& env, const CameraRaster& raster, const CameraFrame& camera,
                           const TileRect& rect) {
  return packet_width == 16 ? CastPrimaryTileK<16>(env, raster, camera, rect)
                            : CastPrimaryTileK<8>(env, raster, camera, rect);
}

void ClearTile(const TileRect& rect, const ImageView& image) {
  const std::size_t width = static_cast<std::size_t>(rect.x1 - rect.x0);
  for (int row = rect.y0; row < rect.y1; ++row) {
    const std::size_t first =
        static_cast<std::size_t>(row) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(rect.x0);
    std::memset(image.rgb + 3 * first, 0, 3 * width);
    if (image.depth != nullptr) std::fill_n(image.depth + first, width, 0.0f);
    if (image.object_id != nullptr) std::fill_n(image.object_id + first, width, kBackgroundObjectId);
  }
}

}  // namespace tavis::render::internal
