// Procedural textures evaluated by the renderer at a hit point (the appearance perturbation axis,
// docs/perturbations.md): checker, stripes, value noise and a wood-like grain, or a flat colour.
// A texture is evaluated in the textured instance's own frame, so it sticks to a moving object;
// it is a pure function of the point (no random state), so an image never depends on threads.
#pragma once

#include <string>

#include <Eigen/Core>

#include "engine/surface_texture.h"

namespace tavis::render {

// engine::SurfaceTexture compiled for the per-hit evaluation: the angle as its cosine and sine,
// the feature size as its inverse.
struct ProceduralTexture {
  engine::TexturePattern pattern = engine::TexturePattern::kNone;
  float inv_scale = 1.0f;  // 1 / feature size in metres
  float cos_angle = 1.0f;
  float sin_angle = 0.0f;
  float turbulence = 0.0f;
  Eigen::Vector3f colour_a = Eigen::Vector3f::Constant(0.5f);
  Eigen::Vector3f colour_b = Eigen::Vector3f::Constant(0.5f);
};

// Throws std::invalid_argument naming the bad value: a textured pattern whose scale_m is outside
// [0.001, 100] m, a colour outside [0, 1], an angle outside [-360, 360] degrees or a turbulence
// outside [0, 8].
ProceduralTexture MakeProceduralTexture(const engine::SurfaceTexture& texture);

// Throws the same for a compiled texture (RenderInputs::instance_texture from a caller), naming
// it `what`.
void ValidateProceduralTexture(const ProceduralTexture& texture, const std::string& what);

// The texture coordinates (metres) of local point p on a face with local normal n: the two
// coordinates across n's largest component (x, y on a face looking up or down; y, z facing x;
// x, z facing y), as a box projection.
Eigen::Vector2f FaceCoordinates(const Eigen::Vector3f& p, const Eigen::Vector3f& n);

// Where texture coordinates `uv` (metres, before the texture's angle) lie between the two colours:
// 0 is colour_a, 1 colour_b. Checker and stripes give exactly 0 or 1; noise and wood lie in [0, 1].
float PatternValue(const ProceduralTexture& texture, const Eigen::Vector2f& uv);

// Value noise at (x, y) in lattice units: a fixed hash of the lattice corners, smoothly
// interpolated; in [0, 1], equal to the corner's hash at integer points.
float ValueNoise(float x, float y);

// Diffuse reflectance of the textured surface at local point p with local normal n: colour_a
// (kNone, kSolid), exactly colour_a or colour_b (checker, stripes), or a blend (noise, wood).
Eigen::Vector3f TextureReflectance(const ProceduralTexture& texture, const Eigen::Vector3f& p,
                                   const Eigen::Vector3f& n);

}  // namespace tavis::render
