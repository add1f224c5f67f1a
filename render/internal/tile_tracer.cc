#include "render/internal/tile_tracer.h"

#include <algorithm>
#include <cstring>

#include "render/internal/ray_packet.h"
#include "render/internal/tile_shadows.h"

namespace tavis::render::internal {
namespace {

// Shadow rays start this far off the surface so they do not hit the facet they leave from
// (the smooth normal and the tessellated facet differ slightly on round shapes).
constexpr float kShadowRayOffset = 1e-3f;

// Lane k of a packet covers pixel (block_x + column_index[k], block_y + row_index[k]).
template <int K>
struct LaneOffsets {
  int column_index[K];
  int row_index[K];
  constexpr LaneOffsets() : column_index(), row_index() {
    for (int k = 0; k < K; ++k) {
      column_index[k] = k % Packet<K>::kBlockWidth;
      row_index[k] = k / Packet<K>::kBlockWidth;
    }
  }
};

// The camera-axis terms of one tile's primary-ray directions, per pixel column (forward + a * left)
// and row (b * up). A direction is the column term plus the row term, added in the same order as
// forward + a * left + b * up, so the directions are the same floats as without the table.
struct TileRayTerms {
  float column[3][kTileSize];
  float row[3][kTileSize];

  TileRayTerms(const CameraRaster& raster, const CameraFrame& camera, const TileRect& rect) {
    for (int i = 0; i < kTileSize; ++i) {
      const float a = (raster.cx - (static_cast<float>(rect.x0 + i) + 0.5f)) * raster.inv_fx;
      const float b = (raster.cy - (static_cast<float>(rect.y0 + i) + 0.5f)) * raster.inv_fx;
      for (int axis = 0; axis < 3; ++axis) {
        column[axis][i] = camera.forward[axis] + a * camera.left[axis];
        row[axis][i] = b * camera.up[axis];
      }
    }
  }
};

// Whether every primary ray of the tile provably hits nothing (InstanceBounds): the pyramid of
// its corner pixels' directions, computed as SetPrimaryRays computes them.
bool TileSeesNothing(const EnvView& env, const CameraRaster& raster, const CameraFrame& camera,
                     const TileRayTerms& terms, const TileRect& rect) {
  if (env.bounds == nullptr) return false;
  const int last_column = rect.x1 - rect.x0 - 1;
  const int last_row = rect.y1 - rect.y0 - 1;
  const int columns[4] = {0, last_column, last_column, 0};  // around the tile
  const int rows[4] = {0, 0, last_row, last_row};
  InstanceBounds::Pyramid pyramid{camera.origin, camera.forward, raster.near_m, raster.far_m, {}};
  for (int c = 0; c < 4; ++c) {
    for (int axis = 0; axis < 3; ++axis) {
      pyramid.corner[c][axis] = terms.column[axis][columns[c]] + terms.row[axis][rows[c]];
    }
  }
  return env.bounds->MissesEverything(pyramid);
}

// Directions of the primary rays of the block whose top-left pixel is (block_x, block_y); lanes
// outside the tile are invalid. The other ray fields come from SetTileConstants. Returns the
// number of valid lanes. Written row by row of the block, four lanes at a time, so that the
// compiler vectorises it (lane k is column k % 4, row k / 4 of the block).
template <int K>
int SetPrimaryRays(const CameraRaster& raster, const TileRayTerms& terms, const TileRect& rect, int block_x,
                   int block_y, int* valid, typename Packet<K>::RayHit* packet) {
  constexpr int kWidth = Packet<K>::kBlockWidth;
  constexpr int kRows = K / kWidth;
  const int columns_left = rect.x1 - block_x;
  const int rows_left = rect.y1 - block_y;
  // Blocks start at multiples of the block size inside the tile, so these stay below kTileSize.
  const int column0 = block_x - rect.x0;
  const int row0 = block_y - rect.y0;
  int count = 0;
  if (columns_left >= kWidth && rows_left >= kRows) {  // every block of an image a multiple of the tile
    std::fill_n(valid, K, -1);
    count = K;
  } else {
    for (int r = 0; r < kRows; ++r) {
      for (int c = 0; c < kWidth; ++c) {
        const bool inside = c < columns_left && r < rows_left;
        valid[r * kWidth + c] = inside ? -1 : 0;
        count += inside ? 1 : 0;
      }
    }
  }
  for (int r = 0; r < kRows; ++r) {
    const float row_x = terms.row[0][row0 + r];
    const float row_y = terms.row[1][row0 + r];
    const float row_z = terms.row[2][row0 + r];
    for (int c = 0; c < kWidth; ++c) {
      packet->ray.dir_x[r * kWidth + c] = terms.column[0][column0 + c] + row_x;
      packet->ray.dir_y[r * kWidth + c] = terms.column[1][column0 + c] + row_y;
      packet->ray.dir_z[r * kWidth + c] = terms.column[2][column0 + c] + row_z;
    }
  }
  for (int k = 0; k < K; ++k) {
    packet->ray.tfar[k] = raster.far_m;
    packet->hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    packet->hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
  }
  return count;
}

// Writes a shaded pixel, or queues it for its shadow ray when the light can reach its surface.
template <int K>
void Finish(std::size_t pixel, const Eigen::Vector3f& p, const Eigen::Vector3f& n, float cosine,
            const PixelColours& colours, float depth, int32_t object_id, bool shadows, const PixelWriter& writer,
            TileShadows<K>* tile_shadows) {
  writer.WriteDepthAndId(pixel, depth, object_id);
  if (cosine > 0.0f && shadows) {
    tile_shadows->Add(p + kShadowRayOffset * n, pixel, colours);
    return;
  }
  writer.WriteColour(pixel, colours.lit);
}

// A textured flat face's two colours at local point p_local (the texture times the face's
// irradiance, lit and, where the light can reach, in shadow): the same floats as the per-pixel
// path's Shade.
inline PixelColours TexturedFaceColours(const FlatShades::Face& f, const ProceduralTexture& texture,
                                        const Eigen::Vector3f& p_local, bool shadows, const SrgbEncoder& encoder) {
  const Eigen::Vector3f colour = TexturedBase(texture, p_local, f.local_normal);
  PixelColours colours{};  // shadowed stays unused where the light cannot reach
  encoder.Encode(colour.cwiseProduct(f.lit), colours.lit);
  if (f.cosine > 0.0f && shadows) encoder.Encode(colour.cwiseProduct(f.shadowed), colours.shadowed);
  return colours;
}

// Shades the primary hit of lane k into `pixel` (or queues it for its shadow ray).
template <int K>
void ShadeHit(const EnvView& env, const CameraFrame& camera, const Shading& shading,
              const typename Packet<K>::RayHit& primary, int k, std::size_t pixel, const PixelWriter& writer,
              TileShadows<K>* tile_shadows) {
  const LightingModel& lighting = *shading.lighting;
  const unsigned int instance = primary.hit.instID[0][k];
  const SurfaceModel& surface = env.surfaces[instance];
  const float depth = primary.ray.tfar[k];
  const FlatShades::Kind kind = env.flat->kind(instance);
  if (kind == FlatShades::Kind::kEmissive) {
    writer.Write(pixel, env.flat->emissive(instance), depth, surface.object_id);
    return;
  }
  const Eigen::Vector3f direction(primary.ray.dir_x[k], primary.ray.dir_y[k], primary.ray.dir_z[k]);
  const Eigen::Vector3f p = camera.origin + depth * direction;
  if (kind != FlatShades::Kind::kShaded) {
    // Boxes and planes (floor, table, most links): one normal and lighting per face, from its
    // triangle; a plain face has its two colours ready, a textured one (the appearance axis)
    // multiplies its texture by the face's irradiance.
    const uint32_t face = primary.hit.primID[k] / 2;  // a plane's two triangles are its face 0
    const FlatShades::Face* f = &env.flat->outside(instance, face);
    if (f->normal.dot(direction) > 0.0f) f = &env.flat->inside(instance, face);  // a plane from below, a camera inside
    if (kind == FlatShades::Kind::kFlat) {
      Finish<K>(pixel, p, f->normal, f->cosine, f->colours, depth, surface.object_id, lighting.shadows(), writer,
                tile_shadows);
      return;
    }
    const PixelColours colours = TexturedFaceColours(*f, env.textures[instance], env.frames[instance].ToLocal(p),
                                                     lighting.shadows(), *shading.encoder);
    Finish<K>(pixel, p, f->normal, f->cosine, colours, depth, surface.object_id, lighting.shadows(), writer,
              tile_shadows);
    return;
  }
  // Round shapes and labelled surfaces: shaded per pixel.
  const bool textured = HasTexture(env.textures, instance);
  const Eigen::Vector3f base = env.rgb_override != nullptr ? env.rgb_override[instance] : surface.appearance.rgb;
  const InstanceFrame& frame = env.frames[instance];
  const Eigen::Vector3f p_local = frame.ToLocal(p);
  const Eigen::Vector3f n_local = LocalNormal(surface, p_local, primary.hit.primID[k]);
  Eigen::Vector3f n = frame.RotateToWorld(n_local);
  if (n.dot(direction) > 0.0f) n = -n;  // seen from behind (a camera inside)
  const Eigen::Vector3f colour =
      Reflectance(surface, textured ? TexturedBase(env.textures[instance], p_local, n_local) : base, p_local, n_local);
  const float cosine = std::max(0.0f, n.dot(lighting.to_light()));
  PixelColours colours;
  if (cosine > 0.0f && lighting.shadows()) {
    colours = ShadeBoth(lighting, *shading.encoder, colour, n, cosine);
  } else {
    shading.encoder->Encode(lighting.Shade(colour, n, cosine), colours.lit);
  }
  Finish<K>(pixel, p, n, cosine, colours, depth, surface.object_id, lighting.shadows(), writer, tile_shadows);
}

// If every lane of a full packet hit the same face of the same flat instance (kFlat or
// kTexturedFlat), from the same side, returns that face; else nullptr. Most packets of the floor,
// the table and the links are such, and then shading is the same few operations on every lane.
template <int K>
const FlatShades::Face* CommonFlatFace(const EnvView& env, const typename Packet<K>::RayHit& primary, int n_valid) {
  if (n_valid != K) return nullptr;
  const unsigned int instance = primary.hit.instID[0][0];
  const uint32_t face = primary.hit.primID[0] / 2;
  bool same = true;
  for (int k = 0; k < K; ++k) {
    same &= primary.hit.instID[0][k] == instance && primary.hit.primID[k] / 2 == face;
  }
  if (!same || instance == RTC_INVALID_GEOMETRY_ID) return nullptr;
  const FlatShades::Kind kind = env.flat->kind(instance);
  if (kind != FlatShades::Kind::kFlat && kind != FlatShades::Kind::kTexturedFlat) return nullptr;
  const FlatShades::Face& outside = env.flat->outside(instance, face);
  int from_inside = 0;
  for (int k = 0; k < K; ++k) {
    const Eigen::Vector3f direction(primary.ray.dir_x[k], primary.ray.dir_y[k], primary.ray.dir_z[k]);
    from_inside += outside.normal.dot(direction) > 0.0f ? 1 : 0;
  }
  if (from_inside == 0) return &outside;
  return from_inside == K ? &env.flat->inside(instance, face) : nullptr;
}

// A textured face's colour pairs for the K hits at world points (x, y, z)[k]: the texture
// evaluated as arrays (EvaluateTextureLanes) and multiplied by the face's irradiance, lit and,
// where the light can reach (`queue`), in shadow. The same bytes as TexturedFaceColours per lane.
template <int K>
void TexturedFaceLanes(const FlatShades::Face& f, const ProceduralTexture& texture, const InstanceFrame& frame,
                       const float* x, const float* y, const float* z, bool queue, const SrgbEncoder& encoder,
                       PixelColours* colours) {
  float local[3][K];
  frame.ToLocalLanes<K>(x, y, z, local);
  const float* const local_axes[3] = {local[0], local[1], local[2]};
  float r[K], g[K], b[K];
  EvaluateTextureLanes<K>(texture, local_axes, FaceUvAxes(f.local_normal), r, g, b);
  float shaded_r[K], shaded_g[K], shaded_b[K];
  for (int k = 0; k < K; ++k) {
    shaded_r[k] = r[k] * f.lit.x();
    shaded_g[k] = g[k] * f.lit.y();
    shaded_b[k] = b[k] * f.lit.z();
  }
  encoder.EncodeLanes<K>(shaded_r, shaded_g, shaded_b, colours[0].lit, sizeof(PixelColours));
  if (!queue) return;  // shadowed stays unused where the light cannot reach
  for (int k = 0; k < K; ++k) {
    shaded_r[k] = r[k] * f.shadowed.x();
    shaded_g[k] = g[k] * f.shadowed.y();
    shaded_b[k] = b[k] * f.shadowed.z();
  }
  encoder.EncodeLanes<K>(shaded_r, shaded_g, shaded_b, colours[0].shadowed, sizeof(PixelColours));
}

// ShadeHit for every lane of a packet that CommonFlatFace answered: the same pixels, with the
// per-hit look-ups done once and the hit points, a textured face's colours and the shadow-ray
// origins computed as arrays (the compiler vectorises them), queued together.
template <int K>
void ShadeFlatPacket(const EnvView& env, const FlatShades::Face& f, const CameraFrame& camera, const Shading& shading,
                     const typename Packet<K>::RayHit& primary, std::size_t block_pixel, const std::size_t* lane_offset,
                     const PixelWriter& writer, TileShadows<K>* tile_shadows) {
  const unsigned int instance = primary.hit.instID[0][0];
  const bool textured = env.flat->kind(instance) == FlatShades::Kind::kTexturedFlat;
  const bool queue = f.cosine > 0.0f && shading.lighting->shadows();
  writer.WriteDepthsAndId<K>(block_pixel, lane_offset, primary.ray.tfar, env.surfaces[instance].object_id);
  if (!textured && !queue) {
    for (int k = 0; k < K; ++k) writer.WriteColour(block_pixel + lane_offset[k], f.colours.lit);
    return;
  }
  // The hit points p = origin + depth * direction, per component as Eigen's.
  alignas(16) float x[K], y[K], z[K];
  for (int k = 0; k < K; ++k) x[k] = camera.origin.x() + primary.ray.tfar[k] * primary.ray.dir_x[k];
  for (int k = 0; k < K; ++k) y[k] = camera.origin.y() + primary.ray.tfar[k] * primary.ray.dir_y[k];
  for (int k = 0; k < K; ++k) z[k] = camera.origin.z() + primary.ray.tfar[k] * primary.ray.dir_z[k];
  PixelColours colours[K];
  if (textured) {
    TexturedFaceLanes<K>(f, env.textures[instance], env.frames[instance], x, y, z, queue, *shading.encoder, colours);
    if (!queue) {
      for (int k = 0; k < K; ++k) writer.WriteColour(block_pixel + lane_offset[k], colours[k].lit);
      return;
    }
  }
  // The shadow rays start at p + kShadowRayOffset * n.
  const Eigen::Vector3f offset = kShadowRayOffset * f.normal;
  for (int k = 0; k < K; ++k) x[k] += offset.x();
  for (int k = 0; k < K; ++k) y[k] += offset.y();
  for (int k = 0; k < K; ++k) z[k] += offset.z();
  if (textured) {
    tile_shadows->AddBlock(x, y, z, block_pixel, lane_offset, colours);
  } else {
    tile_shadows->AddBlock(x, y, z, block_pixel, lane_offset, f.colours);
  }
}

// If every lane of a full packet hit the same capsule or sphere of one colour (no label, no
// texture), returns its instance; else RTC_INVALID_GEOMETRY_ID. The robot's links are capsules,
// and such packets are most of what the per-pixel path would shade.
template <int K>
unsigned int CommonRoundInstance(const EnvView& env, const typename Packet<K>::RayHit& primary, int n_valid) {
  const unsigned int instance = primary.hit.instID[0][0];
  if (n_valid != K || instance == RTC_INVALID_GEOMETRY_ID) return RTC_INVALID_GEOMETRY_ID;
  bool same = true;
  for (int k = 0; k < K; ++k) same &= primary.hit.instID[0][k] == instance;
  if (!same || env.flat->kind(instance) != FlatShades::Kind::kShaded) return RTC_INVALID_GEOMETRY_ID;
  const SurfaceModel& surface = env.surfaces[instance];
  if (!HasRoundNormalLanes(surface) || !HasConstantReflectance(surface) || HasTexture(env.textures, instance)) {
    return RTC_INVALID_GEOMETRY_ID;
  }
  return instance;
}

// ShadeHit for every lane of a packet that CommonRoundInstance answered: the hit points, their
// smooth normals, the light cosines and both colours as arrays (the same floats as ShadeHit's per
// lane), then each pixel written or queued for its shadow ray.
template <int K>
void ShadeRoundPacket(const EnvView& env, unsigned int instance, const CameraFrame& camera, const Shading& shading,
                      const typename Packet<K>::RayHit& primary, std::size_t block_pixel,
                      const std::size_t* lane_offset, const PixelWriter& writer, TileShadows<K>* tile_shadows) {
  const SurfaceModel& surface = env.surfaces[instance];
  const InstanceFrame& frame = env.frames[instance];
  const LightingModel& lighting = *shading.lighting;
  writer.WriteDepthsAndId<K>(block_pixel, lane_offset, primary.ray.tfar, surface.object_id);
  const float* const direction[3] = {primary.ray.dir_x, primary.ray.dir_y, primary.ray.dir_z};
  alignas(16) float p[3][K];
  for (int axis = 0; axis < 3; ++axis) {
    for (int k = 0; k < K; ++k) p[axis][k] = camera.origin[axis] + primary.ray.tfar[k] * direction[axis][k];
  }
  float local[3][K], n_local[3][K], n[3][K];
  frame.ToLocalLanes<K>(p[0], p[1], p[2], local);
  RoundNormalLanes<K>(surface, local, n_local);
  frame.RotateToWorldLanes<K>(n_local, n);
  const Eigen::Vector3f& to_light = lighting.to_light();
  float cosine[K];
  for (int k = 0; k < K; ++k) {
    // Seen from behind (a camera inside): the normal turns towards the camera.
    const float facing = n[0][k] * direction[0][k] + (n[1][k] * direction[1][k] + n[2][k] * direction[2][k]);
    const float sign = facing > 0.0f ? -1.0f : 1.0f;
    for (int axis = 0; axis < 3; ++axis) n[axis][k] *= sign;
    const float d = n[0][k] * to_light.x() + (n[1][k] * to_light.y() + n[2][k] * to_light.z());
    cosine[k] = 0.0f < d ? d : 0.0f;  // std::max(0.0f, d)
  }
  const Eigen::Vector3f base = env.rgb_override != nullptr ? env.rgb_override[instance] : surface.appearance.rgb;
  float irradiance[3][K], shaded[3][K];
  PixelColours colours[K];
  lighting.IrradianceLanes<K>(n[2], cosine, irradiance);
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < K; ++k) shaded[c][k] = base[c] * irradiance[c][k];
  }
  shading.encoder->EncodeLanes<K>(shaded[0], shaded[1], shaded[2], colours[0].lit, sizeof(PixelColours));
  bool queue[K];
  bool any_queued = false;
  for (int k = 0; k < K; ++k) {
    queue[k] = cosine[k] > 0.0f && lighting.shadows();
    any_queued |= queue[k];
  }
  if (any_queued) {
    const float no_direct[K] = {};
    lighting.IrradianceLanes<K>(n[2], no_direct, irradiance);
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < K; ++k) shaded[c][k] = base[c] * irradiance[c][k];
    }
    shading.encoder->EncodeLanes<K>(shaded[0], shaded[1], shaded[2], colours[0].shadowed, sizeof(PixelColours));
  }
  for (int k = 0; k < K; ++k) {
    const std::size_t pixel = block_pixel + lane_offset[k];
    if (!queue[k]) {
      writer.WriteColour(pixel, colours[k].lit);
      continue;
    }
    const Eigen::Vector3f origin(p[0][k] + kShadowRayOffset * n[0][k], p[1][k] + kShadowRayOffset * n[1][k],
                                 p[2][k] + kShadowRayOffset * n[2][k]);
    tile_shadows->Add(origin, pixel, colours[k]);
  }
}

template <int K>
TileCounts ShadeTileK(const EnvView& env, const CameraRaster& raster, const CameraFrame& camera, const TileRect& rect,
                      const Shading& shading, const ImageView& image) {
  using P = Packet<K>;
  static constexpr LaneOffsets<K> kLanes;
  constexpr int kBlockHeight = K / P::kBlockWidth;
  const PixelWriter writer{image};
  uint8_t background[3];
  shading.encoder->Encode(shading.lighting->background(), background);
  RTCIntersectContext primary_context = MakeContext(RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
  alignas(64) int valid[K];
  alignas(64) typename P::RayHit primary;
  TileShadows<K> tile_shadows(shading.lighting->to_light());
  TileCounts counts;
  SetTileConstants<K>(&primary.ray, camera.origin, raster.near_m);
  const TileRayTerms terms(raster, camera, rect);
  const std::size_t width = static_cast<std::size_t>(image.width);
  if (TileSeesNothing(env, raster, camera, terms, rect)) {
    for (int y = rect.y0; y < rect.y1; ++y) {
      for (int x = rect.x0; x < rect.x1; ++x) {
        writer.Write(static_cast<std::size_t>(y) * width + static_cast<std::size_t>(x), background, 0.0f,
                     kBackgroundObjectId);
      }
    }
    counts.primary_rays += (rect.x1 - rect.x0) * (rect.y1 - rect.y0);
    counts.sky_tiles = 1;
    return counts;
  }
  std::size_t lane_offset[K];  // pixel of lane k minus the block's top-left pixel
  for (int k = 0; k < K; ++k) {
    lane_offset[k] =
        static_cast<std::size_t>(kLanes.row_index[k]) * width + static_cast<std::size_t>(kLanes.column_index[k]);
  }

  for (int block_y = rect.y0; block_y < rect.y1; block_y += kBlockHeight) {
    for (int block_x = rect.x0; block_x < rect.x1; block_x += P::kBlockWidth) {
      const int n_valid = SetPrimaryRays<K>(raster, terms, rect, block_x, block_y, valid, &primary);
      counts.primary_rays += n_valid;
      P::Intersect(valid, env.scene, &primary_context, &primary);
      const std::size_t block_pixel = static_cast<std::size_t>(block_y) * width + static_cast<std::size_t>(block_x);
      if (const FlatShades::Face* face = CommonFlatFace<K>(env, primary, n_valid)) {
        counts.primary_hits += K;
        ShadeFlatPacket<K>(env, *face, camera, shading, primary, block_pixel, lane_offset, writer, &tile_shadows);
        continue;
      }
      if (const unsigned int round = CommonRoundInstance<K>(env, primary, n_valid); round != RTC_INVALID_GEOMETRY_ID) {
        counts.primary_hits += K;
        ShadeRoundPacket<K>(env, round, camera, shading, primary, block_pixel, lane_offset, writer, &tile_shadows);
        continue;
      }
      for (int k = 0; k < K; ++k) {
        if (valid[k] == 0) continue;
        const std::size_t pixel = block_pixel + lane_offset[k];
        if (primary.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) {
          writer.Write(pixel, background, 0.0f, kBackgroundObjectId);
          continue;
        }
        ++counts.primary_hits;
        ShadeHit<K>(env, camera, shading, primary, k, pixel, writer, &tile_shadows);
      }
    }
  }
  if (shading.lighting->shadows()) counts.shadow_rays += tile_shadows.Resolve(env.scene, env.casters, writer);
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
  const TileRayTerms terms(raster, camera, rect);
  if (TileSeesNothing(env, raster, camera, terms, rect)) {
    counts.primary_rays += (rect.x1 - rect.x0) * (rect.y1 - rect.y0);
    counts.sky_tiles = 1;
    return counts;
  }
  for (int block_y = rect.y0; block_y < rect.y1; block_y += kBlockHeight) {
    for (int block_x = rect.x0; block_x < rect.x1; block_x += P::kBlockWidth) {
      counts.primary_rays += SetPrimaryRays<K>(raster, terms, rect, block_x, block_y, valid, &primary);
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
    const std::size_t first =
        static_cast<std::size_t>(row) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(rect.x0);
    std::memset(image.rgb + 3 * first, 0, 3 * width);
    if (image.depth != nullptr) std::fill_n(image.depth + first, width, 0.0f);
    if (image.object_id != nullptr) std::fill_n(image.object_id + first, width, kBackgroundObjectId);
  }
}

}  // namespace tavis::render::internal
