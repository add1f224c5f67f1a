// The shadow rays of one tile: lit diffuse pixels wait until the tile's primary rays are done,
// then the exact tests of ShadowCasters decide most of them and Embree traces the rest in full
// packets (one rtcOccluded call per K undecided pixels).
#pragma once

#include <algorithm>
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

  void WriteColour(std::size_t pixel, const uint8_t* colour) const {
    uint8_t* rgb = image.rgb + 3 * pixel;
    rgb[0] = colour[0];
    rgb[1] = colour[1];
    rgb[2] = colour[2];
  }
  // Depth and object id do not depend on the shadow, so a pixel waiting for its shadow ray has
  // them written at once and only its colour waits.
  void WriteDepthAndId(std::size_t pixel, float depth, int32_t object_id) const {
    if (image.depth != nullptr) image.depth[pixel] = depth;
    if (image.object_id != nullptr) image.object_id[pixel] = object_id;
  }
  // Depths of the K pixels block_pixel + lane_offset[k], all of one object.
  template <int K>
  void WriteDepthsAndId(std::size_t block_pixel, const std::size_t* lane_offset, const float* depths,
                        int32_t object_id) const {
    if (image.depth != nullptr) {
      for (int k = 0; k < K; ++k) image.depth[block_pixel + lane_offset[k]] = depths[k];
    }
    if (image.object_id != nullptr) {
      for (int k = 0; k < K; ++k) image.object_id[block_pixel + lane_offset[k]] = object_id;
    }
  }
  void Write(std::size_t pixel, const uint8_t* colour, float depth, int32_t object_id) const {
    WriteColour(pixel, colour);
    WriteDepthAndId(pixel, depth, object_id);
  }
};

// The waiting pixels are kept as arrays of their fields (structure of arrays), each written by
// its own store: a queued struct built on the stack and copied was a store-forwarding stall on
// every lit pixel (perf annotate: a tenth of the render).
template <int K>
class TileShadows {
 public:
  explicit TileShadows(const Eigen::Vector3f& to_light) : context_(MakeContext(RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT)) {
    // Shadow rays all go towards the distant light; only their origins change.
    SetTileConstants<K>(&rays_, Eigen::Vector3f::Zero(), 0.0f);
    for (int k = 0; k < K; ++k) {
      rays_.dir_x[k] = to_light.x();
      rays_.dir_y[k] = to_light.y();
      rays_.dir_z[k] = to_light.z();
    }
  }

  // Queues the pixel whose shadow ray starts at `origin`, to be written with colours.lit or
  // colours.shadowed.
  void Add(const Eigen::Vector3f& origin, std::size_t pixel, const PixelColours& colours) {
    origin_x_[size_] = origin.x();
    origin_y_[size_] = origin.y();
    origin_z_[size_] = origin.z();
    pixel_[size_] = pixel;
    colours_[size_] = colours;
    low_ = low_.cwiseMin(origin);
    high_ = high_.cwiseMax(origin);
    ++size_;
  }

  // Add for the K pixels block_pixel + lane_offset[k] of one colour pair, origins (x, y, z)[k].
  void AddBlock(const float* x, const float* y, const float* z, std::size_t block_pixel, const std::size_t* lane_offset,
                const PixelColours& colours) {
    for (int k = 0; k < K; ++k) colours_[size_ + k] = colours;
    AddBlockOrigins(x, y, z, block_pixel, lane_offset);
  }

  // The same with a colour pair per pixel (colours[k]: a textured face).
  void AddBlock(const float* x, const float* y, const float* z, std::size_t block_pixel, const std::size_t* lane_offset,
                const PixelColours* colours) {
    for (int k = 0; k < K; ++k) colours_[size_ + k] = colours[k];
    AddBlockOrigins(x, y, z, block_pixel, lane_offset);
  }

  // Colours every waiting pixel, lit or in shadow, and empties the list; returns the number of
  // rays traced with Embree. Without casters (nullptr) every ray is traced.
  int Resolve(RTCScene scene, const ShadowCasters* casters, const PixelWriter& writer) {
    if (size_ == 0) return 0;
    LightBounds candidates[kMaxCandidates];
    const int n_candidates = casters == nullptr ? -1 : casters->Candidates(low_, high_, candidates, kMaxCandidates);
    int traced = 0;
    if (n_candidates == 0) {  // nothing can shade this tile: every waiting pixel is lit
      for (int i = 0; i < size_; ++i) Write(i, false, writer);
    } else {
      if (n_candidates > 0) {
        Decide(*casters, candidates, n_candidates);
      } else {
        std::fill_n(test_, size_, ShadowTest::kUnknown);
      }
      for (int i = 0; i < size_; ++i) {
        if (test_[i] == ShadowTest::kUnknown) {
          Trace(i);
          if (n_traced_ == K) traced += Flush(scene, writer);
          continue;
        }
        Write(i, test_[i] == ShadowTest::kHit, writer);
      }
      traced += Flush(scene, writer);
    }
    size_ = 0;
    low_ = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
    high_ = -low_;
    return traced;
  }

 private:
  // More candidates than this for one tile: every ray of the tile goes to Embree.
  static constexpr int kMaxCandidates = 32;
  static constexpr int kCapacity = kTileSize * kTileSize;

  // The origins, pixels and bounds of AddBlock's K pixels (their colours are already in place).
  void AddBlockOrigins(const float* x, const float* y, const float* z, std::size_t block_pixel,
                       const std::size_t* lane_offset) {
    float low_x = low_.x(), low_y = low_.y(), low_z = low_.z();
    float high_x = high_.x(), high_y = high_.y(), high_z = high_.z();
    for (int k = 0; k < K; ++k) {
      origin_x_[size_ + k] = x[k];
      origin_y_[size_ + k] = y[k];
      origin_z_[size_ + k] = z[k];
      pixel_[size_ + k] = block_pixel + lane_offset[k];
    }
    for (int k = 0; k < K; ++k) {
      low_x = std::min(low_x, x[k]);
      low_y = std::min(low_y, y[k]);
      low_z = std::min(low_z, z[k]);
      high_x = std::max(high_x, x[k]);
      high_y = std::max(high_y, y[k]);
      high_z = std::max(high_z, z[k]);
    }
    low_ = Eigen::Vector3f(low_x, low_y, low_z);
    high_ = Eigen::Vector3f(high_x, high_y, high_z);
    size_ += K;
  }

  // test_[i] for every waiting pixel: kHit if a candidate blocks its ray for certain, else
  // kUnknown if one may, else kMiss. Caster by caster over all pixels, four pixels per bounds test;
  // the exact test runs only for the pixels inside a caster's bounds.
  void Decide(const ShadowCasters& casters, const LightBounds* candidates, int n_candidates) {
    const int padded = (size_ + 3) & ~3;
    for (int i = 0; i < size_; ++i) {
      const Eigen::Vector3f uvw = casters.ToLight(origin(i));
      u_[i] = uvw.x();
      v_[i] = uvw.y();
      w_[i] = uvw.z();
    }
    for (int i = size_; i < padded; ++i) {
      u_[i] = v_[i] = w_[i] = std::numeric_limits<float>::quiet_NaN();  // reaches no caster
      origin_x_[i] = origin_y_[i] = origin_z_[i] = 0.0f;
    }
    std::fill_n(test_, size_, ShadowTest::kMiss);
    for (int c = 0; c < n_candidates; ++c) {
      const int32_t caster = candidates[c].caster;
      const bool plane = casters.IsPlane(caster);
      for (int group = 0; group < padded; group += 4) {
        int bits = candidates[c].MayReach4(u_ + group, v_ + group, w_ + group);
        if (bits == 0) continue;
        // Most rays inside a caster's bounds still miss its box: four rays per box test.
        if (!plane) bits &= casters.MeetsBox4(caster, origin_x_ + group, origin_y_ + group, origin_z_ + group);
        for (; bits != 0; bits &= bits - 1) {
          const int i = group + __builtin_ctz(static_cast<unsigned int>(bits));
          if (test_[i] == ShadowTest::kHit) continue;
          const ShadowTest test = plane ? casters.Test(caster, origin(i)) : casters.TestPastBox(caster, origin(i));
          if (test != ShadowTest::kMiss) test_[i] = test;
        }
      }
    }
  }

  Eigen::Vector3f origin(int i) const { return {origin_x_[i], origin_y_[i], origin_z_[i]}; }

  void Write(int i, bool blocked, const PixelWriter& writer) const {
    writer.WriteColour(pixel_[i], blocked ? colours_[i].shadowed : colours_[i].lit);
  }

  void Trace(int i) {
    rays_.org_x[n_traced_] = origin_x_[i];
    rays_.org_y[n_traced_] = origin_y_[i];
    rays_.org_z[n_traced_] = origin_z_[i];
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
  float origin_x_[kCapacity];
  float origin_y_[kCapacity];
  float origin_z_[kCapacity];
  std::size_t pixel_[kCapacity];
  PixelColours colours_[kCapacity];
  // The waiting pixels' shadow ray origins in the light frame (padded to a multiple of 4), and
  // what the casters decided for them.
  float u_[kCapacity];
  float v_[kCapacity];
  float w_[kCapacity];
  ShadowTest test_[kCapacity];
  Eigen::Vector3f low_ = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f high_ = -low_;
  int size_ = 0;
};

}  // namespace tavis::render::internal
