// The shadow rays of one tile: lit diffuse pixels wait until the tile's primary rays are done,
// then the exact tests of ShadowCasters decide most of them and Embree traces the rest in full
// packets (one rtcOccluded call per K undecided pixels).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

#include <embree3/rtcore.h>
#include <Eigen/Core>

#include "render/internal/flat_shades.h"
#include "render/internal/ray_packet.h"
#include "render/internal/shadow_casters.h"
#include "render/internal/tile_tracer.h"

namespace tavis::render::internal {

// Writes one shaded pixel: sRGB colour, and depth and object id where the image has them.
struct PixelWriter {
  const ImageView& image;

  void Write(std::size_t pixel, const uint8_t* colour, float depth, int32_t object_id) const {
    uint8_t* rgb = image.rgb + 3 * pixel;
    rgb[0] = colour[0];
    rgb[1] = colour[1];
    rgb[2] = colour[2];
    if (image.depth != nullptr) image.depth[pixel] = depth;
    if (image.object_id != nullptr) image.object_id[pixel] = object_id;
  }
};

template <int K>
class TileShadows {
 public:
  // What a waiting pixel needs once its shadow is known.
  struct Waiting {
    std::size_t pixel;
    PixelColours colours;
    float depth;
    int32_t object_id;
  };

  explicit TileShadows(const Eigen::Vector3f& to_light) : context_(MakeContext(RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT)) {
    // Shadow rays all go towards the distant light; only their origins change.
    SetTileConstants<K>(&rays_, Eigen::Vector3f::Zero(), 0.0f);
    for (int k = 0; k < K; ++k) {
      rays_.dir_x[k] = to_light.x();
      rays_.dir_y[k] = to_light.y();
      rays_.dir_z[k] = to_light.z();
    }
  }

  // Queues the pixel whose shadow ray starts at `origin`.
  void Add(const Eigen::Vector3f& origin, const Waiting& waiting) {
    origins_[size_] = origin;
    waiting_[size_] = waiting;
    low_ = low_.cwiseMin(origin);
    high_ = high_.cwiseMax(origin);
    ++size_;
  }

  // Shades every waiting pixel, lit or in shadow, and empties the list; returns the number of rays
  // traced with Embree.
  // Without casters (nullptr) every ray is traced.
  int Resolve(RTCScene scene, const ShadowCasters* casters, const PixelWriter& writer) {
    if (size_ == 0) return 0;
    LightBounds candidates[kMaxCandidates];
    const int n_candidates = casters == nullptr ? -1 : casters->Candidates(low_, high_, candidates, kMaxCandidates);
    int traced = 0;
    for (int i = 0; i < size_; ++i) {
      const ShadowTest test = n_candidates < 0    ? ShadowTest::kUnknown
                              : n_candidates == 0 ? ShadowTest::kMiss
                                                  : Decide(*casters, candidates, n_candidates, origins_[i]);
      if (test == ShadowTest::kUnknown) {
        Trace(i);
        if (n_traced_ == K) traced += Flush(scene, writer);
        continue;
      }
      Write(i, test == ShadowTest::kHit, writer);
    }
    traced += Flush(scene, writer);
    size_ = 0;
    low_ = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
    high_ = -low_;
    return traced;
  }

 private:
  // More candidates than this for one tile: every ray of the tile goes to Embree.
  static constexpr int kMaxCandidates = 32;
  static constexpr int kCapacity = kTileSize * kTileSize;

  static ShadowTest Decide(const ShadowCasters& casters, const LightBounds* candidates, int n_candidates,
                           const Eigen::Vector3f& origin) {
    const Eigen::Vector3f uvw = casters.ToLight(origin);
    ShadowTest result = ShadowTest::kMiss;
    for (int c = 0; c < n_candidates; ++c) {
      if (!candidates[c].MayReach(uvw)) continue;
      const ShadowTest test = casters.Test(candidates[c].caster, origin);
      if (test == ShadowTest::kHit) return test;
      if (test == ShadowTest::kUnknown) result = test;
    }
    return result;
  }

  void Write(int i, bool blocked, const PixelWriter& writer) const {
    const Waiting& w = waiting_[i];
    writer.Write(w.pixel, blocked ? w.colours.shadowed : w.colours.lit, w.depth, w.object_id);
  }

  void Trace(int i) {
    rays_.org_x[n_traced_] = origins_[i].x();
    rays_.org_y[n_traced_] = origins_[i].y();
    rays_.org_z[n_traced_] = origins_[i].z();
    traced_[n_traced_] = i;
    ++n_traced_;
  }

  // Traces the queued rays, writes their pixels and empties the queue; returns the rays traced.
  int Flush(RTCScene scene, const PixelWriter& writer) {
    if (n_traced_ == 0) return 0;
    alignas(64) int valid[K];
    for (int k = 0; k < K; ++k) {
      valid[k] = k < n_traced_ ? -1 : 0;
      rays_.tfar[k] = k < n_traced_ ? std::numeric_limits<float>::infinity() : 0.0f;  // inactive lanes stay finite
    }
    Packet<K>::Occluded(valid, scene, &context_, &rays_);
    // rtcOccluded sets tfar to -inf for blocked rays.
    for (int k = 0; k < n_traced_; ++k) Write(traced_[k], rays_.tfar[k] < 0.0f, writer);
    const int traced = n_traced_;
    n_traced_ = 0;
    return traced;
  }

  // Shadow packets are traced without the coherent hint: with it, rtcOccluded16 of Embree 3.13.5
  // never returned on an AVX-512 AMD CPU (observed on the development machine).
  RTCIntersectContext context_;
  alignas(64) typename Packet<K>::Ray rays_;
  int traced_[K];
  int n_traced_ = 0;
  Eigen::Vector3f origins_[kCapacity];
  Waiting waiting_[kCapacity];
  Eigen::Vector3f low_ = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f high_ = -low_;
  int size_ = 0;
};

}  // namespace tavis::render::internal
