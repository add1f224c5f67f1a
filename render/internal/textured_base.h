// The base colour of a hit with the appearance axis's textures (render/procedural_texture.h): the
// one lookup the shading code makes where it used to read the instance's flat colour. Without
// textures (nullptr, or kNone for the instance) it returns the flat colour untouched, so the
// untextured pixels are exactly what they were.
#pragma once

#include <Eigen/Core>

#include "render/internal/env_scenes.h"
#include "render/internal/texture_evaluation.h"
#include "render/procedural_texture.h"

namespace tavis::render::internal {

// textures: per instance, or nullptr; p_world the hit point; n_local the instance's outward
// normal there in its own frame (which face, for the box projection).
inline Eigen::Vector3f TexturedBase(const ProceduralTexture* textures, unsigned int instance,
                                    const InstanceFrame& frame, const Eigen::Vector3f& p_world,
                                    const Eigen::Vector3f& n_local, const Eigen::Vector3f& flat_rgb) {
  if (textures == nullptr || textures[instance].pattern == engine::TexturePattern::kNone) return flat_rgb;
  // In the instance's frame, so that the texture moves with the instance.
  return EvaluateTexture(textures[instance], frame.ToLocal(p_world), n_local);
}

}  // namespace tavis::render::internal
