// The base colour of a hit with the appearance axis's textures (render/procedural_texture.h): the
// one lookup the shading code makes where it reads the instance's flat colour. An instance without
// a texture keeps the flat colour (and the flat-face path), so the untextured pixels are exactly
// what they were.
#pragma once

#include <Eigen/Core>

#include "render/internal/env_scenes.h"
#include "render/internal/texture_evaluation.h"
#include "render/procedural_texture.h"

namespace tavis::render::internal {

// True if the instance has a texture (textures: per instance, or nullptr for none at all).
inline bool HasTexture(const ProceduralTexture* textures, unsigned int instance) {
  return textures != nullptr && textures[instance].pattern != engine::TexturePattern::kNone;
}

// The textured base colour at p_local, the hit in the instance's own frame (so the texture moves
// with the instance); n_local is its outward normal there (which face, for the box projection).
inline Eigen::Vector3f TexturedBase(const ProceduralTexture& texture, const Eigen::Vector3f& p_local,
                                    const Eigen::Vector3f& n_local) {
  return EvaluateTexture(texture, p_local, n_local);
}

}  // namespace tavis::render::internal
