// Ray tracing of one image tile in coherent packets: primary rays, then a shadow-ray packet for
// the lit-facing hits, then shading into the output pixels.
#pragma once

#include <cstdint>

#include <embree3/rtcore.h>
#include <Eigen/Core>

#include "render/internal/env_scenes.h"
#include "render/internal/flat_shades.h"
#include "render/internal/instance_bounds.h"
#include "render/internal/lighting_model.h"
#include "render/internal/shadow_casters.h"
#include "render/internal/surface_shading.h"
#include "render/internal/textured_base.h"

namespace tavis::render::internal {

// Tiles are kTileSize x kTileSize pixels (smaller at the right and bottom image edges).
inline constexpr int kTileSize = 16;

// Pinhole raster of one camera (see render/camera.h for the conventions).
struct CameraRaster {
  int width = 0;
  int height = 0;
  float inv_fx = 0.0f;
  float cx = 0.0f;
  float cy = 0.0f;
  float near_m = 0.0f;
  float far_m = 0.0f;
};

// World-space camera axes for this tick. forward has unit length, so a primary ray
// forward + a * left + b * up reaches depth t along the optical axis at parameter t.
struct CameraFrame {
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();
  Eigen::Vector3f forward = Eigen::Vector3f::UnitX();
  Eigen::Vector3f left = Eigen::Vector3f::UnitY();
  Eigen::Vector3f up = Eigen::Vector3f::UnitZ();
};

struct TileRect {
  int x0 = 0;
  int y0 = 0;
  int x1 = 0;  // exclusive
  int y1 = 0;
};

// What one env's rays see.
struct EnvView {
  RTCScene scene = nullptr;
  const InstanceFrame* frames = nullptr;          // per instance
  const SurfaceModel* surfaces = nullptr;         // per instance
  const Eigen::Vector3f* rgb_override = nullptr;  // per instance, or nullptr
  const FlatShades* flat = nullptr;               // for shading
  const ShadowCasters* casters = nullptr;         // shadows decided without rays where exact; nullptr: all traced
  const ProceduralTexture* textures = nullptr;    // per instance, or nullptr (no textures)
  const InstanceBounds* bounds = nullptr;         // tiles of sky skip Embree; nullptr: every tile traced
};

// One camera image of one env; depth and object_id may be nullptr.
struct ImageView {
  uint8_t* rgb = nullptr;
  float* depth = nullptr;
  int32_t* object_id = nullptr;
  int width = 0;
};

struct Shading {
  const LightingModel* lighting = nullptr;
  const SrgbEncoder* encoder = nullptr;
};

struct TileCounts {
  int64_t primary_rays = 0;
  int64_t shadow_rays = 0;
  int64_t primary_hits = 0;
  int64_t sky_tiles = 0;

  TileCounts& operator+=(const TileCounts& other) {
    primary_rays += other.primary_rays;
    shadow_rays += other.shadow_rays;
    primary_hits += other.primary_hits;
    sky_tiles += other.sky_tiles;
    return *this;
  }
};

// 16 where the CPU traces 16-wide packets natively (AVX-512), else 8.
int PreferredPacketWidth(RTCDevice device);

TileCounts ShadeTile(int packet_width, const EnvView& env, const CameraRaster& raster, const CameraFrame& camera,
                     const TileRect& rect, const Shading& shading, const ImageView& image);

// Primary rays only, results discarded (the benchmark's baseline).
TileCounts CastPrimaryTile(int packet_width, const EnvView& env, const CameraRaster& raster, const CameraFrame& camera,
                           const TileRect& rect);

// All-zero RGB and depth, background object id.
void ClearTile(const TileRect& rect, const ImageView& image);

}  // namespace tavis::render::internal
