// The finished sRGB colours of every flat face of one env, computed once per render.
//
// A plain box face or plane (one reflectance, no label, so the floor, the table and most robot
// links) has one normal, so its lighting, lit and in shadow, is the same at every pixel: the tile
// loop then only picks the face's two colours instead of shading and encoding each pixel. The
// colours come from the same functions, on the same values, as the per-pixel path's, so the
// pixels are identical. Emissive instances get their one colour the same way. A textured box or
// plane (the appearance axis) keeps its per-face normal and irradiance, so that a pixel only
// evaluates its texture and multiplies.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "render/internal/env_scenes.h"
#include "render/internal/lighting_model.h"
#include "render/internal/surface_shading.h"
#include "render/procedural_texture.h"

namespace tavis::render::internal {

// A pixel's colour lit by the distant light and in its shadow (equal when the light cannot reach).
struct PixelColours {
  uint8_t lit[3];
  uint8_t shadowed[3];
};

// Encoded colours of reflectance `rgb` with world normal n, lit with `cosine` (n . to_light,
// 0 when the light is behind the face) and in shadow.
inline PixelColours ShadeBoth(const LightingModel& lighting, const SrgbEncoder& encoder, const Eigen::Vector3f& rgb,
                              const Eigen::Vector3f& n, float cosine) {
  PixelColours colours;
  encoder.Encode(lighting.Shade(rgb, n, cosine), colours.lit);
  encoder.Encode(lighting.Shade(rgb, n, 0.0f), colours.shadowed);
  return colours;
}

class FlatShades {
 public:
  enum class Kind : uint8_t { kShaded, kFlat, kTexturedFlat, kEmissive };

  // A face seen from one side: the normal turned towards the viewer, its light cosine, colours
  // (kFlat), and for kTexturedFlat the outward local normal and the irradiance lit and in shadow
  // (LightingModel::Irradiance).
  struct Face {
    Eigen::Vector3f normal;
    float cosine;
    PixelColours colours;
    Eigen::Vector3f local_normal;
    Eigen::Vector3f lit;
    Eigen::Vector3f shadowed;
  };

  FlatShades() = default;
  explicit FlatShades(const SurfaceModel* surfaces, int n_instances);

  // Recomputes the faces at this render's frames, colours and textures (rgb_override and
  // textures may be nullptr).
  void Build(const InstanceFrame* frames, const Eigen::Vector3f* rgb_override, const ProceduralTexture* textures,
             const LightingModel& lighting, const SrgbEncoder& encoder);

  Kind kind(unsigned int instance) const { return kinds_[instance]; }
  // Face `face` (a box's triangle / 2; 0 for a plane) of a flat instance, from its outward side.
  const Face& outside(unsigned int instance, uint32_t face) const { return faces_[2 * (6 * instance + face)]; }
  // The same face seen from behind (a plane from below, a camera inside a box).
  const Face& inside(unsigned int instance, uint32_t face) const { return faces_[2 * (6 * instance + face) + 1]; }
  const uint8_t* emissive(unsigned int instance) const { return faces_[12 * instance].colours.lit; }

 private:
  const SurfaceModel* surfaces_ = nullptr;
  std::vector<Kind> plain_kinds_;  // [instance] without textures
  std::vector<Kind> kinds_;        // [instance] at this render's textures
  std::vector<Face> faces_;        // [instance][face 0..5][outside, inside]
};

}  // namespace tavis::render::internal
