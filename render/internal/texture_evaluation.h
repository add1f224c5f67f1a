// The per-hit evaluation of a render::ProceduralTexture, inline: the shading loop evaluates it
// where it reads a hit's colour (textured_base.h), and render/procedural_texture.cc wraps the same
// functions for everyone else. Inline because a call from the shading loop cost more than the
// pattern (the loop's floats are saved around any call; callgrind, bench/render_bench.cc's
// Textured variants).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include <Eigen/Core>

#include "render/procedural_texture.h"

namespace tavis::render::internal {

// The wood's noise varies slowly along the grain and faster across it: the rings wander over a
// few ring spacings across, and over several along the grain.
inline constexpr float kGrainAlong = 0.15f;
inline constexpr float kGrainAcross = 0.5f;

// floor(x) as an integer for |x| < 2^31 (texture coordinates in feature sizes): cheaper than
// std::floor's range checks.
inline int32_t FloorToInt(float x) {
  const int32_t truncated = static_cast<int32_t>(x);
  return truncated - (static_cast<float>(truncated) > x ? 1 : 0);
}

// The value noise's lattice: 256 values in [0, 1) and a permutation of 0..255, both fixed (made
// at compile time from an integer hash), so a corner's value is two table look-ups
// (Perlin's scheme); the noise repeats every 256 cells.
struct NoiseTables {
  std::array<uint8_t, 256> permutation{};
  std::array<float, 256> values{};
};

constexpr uint32_t MixNoiseBits(uint32_t h) {
  h = (h ^ (h >> 16)) * 0x7feb352du;
  h = (h ^ (h >> 15)) * 0x846ca68bu;
  return h ^ (h >> 16);
}

constexpr NoiseTables MakeNoiseTables() {
  NoiseTables tables;
  for (int i = 0; i < 256; ++i) {
    tables.permutation[static_cast<std::size_t>(i)] = static_cast<uint8_t>(i);
    tables.values[static_cast<std::size_t>(i)] =
        static_cast<float>(MixNoiseBits(static_cast<uint32_t>(i) + 0x9e3779b9u) >> 8) * 0x1.0p-24f;
  }
  for (int i = 255; i > 0; --i) {  // Fisher-Yates with the hash as its random numbers
    const std::size_t j = MixNoiseBits(static_cast<uint32_t>(i) * 0x85ebca6bu) % static_cast<uint32_t>(i + 1);
    const uint8_t swapped = tables.permutation[static_cast<std::size_t>(i)];
    tables.permutation[static_cast<std::size_t>(i)] = tables.permutation[j];
    tables.permutation[j] = swapped;
  }
  return tables;
}

inline constexpr NoiseTables kNoiseTables = MakeNoiseTables();

// Value noise at (x, y) in lattice units: in [0, 1], the corner's value at integer points, smoothly
// interpolated between.
inline float Noise(float x, float y) {
  const int32_t i = FloorToInt(x);
  const int32_t j = FloorToInt(y);
  const float tx = x - static_cast<float>(i);
  const float ty = y - static_cast<float>(j);
  // Smoothstep weights: the noise is continuous with a continuous slope across cell edges.
  const float sx = tx * tx * (3.0f - 2.0f * tx);
  const float sy = ty * ty * (3.0f - 2.0f * ty);
  const auto& perm = kNoiseTables.permutation;
  const auto& value = kNoiseTables.values;
  const uint32_t column0 = perm[static_cast<uint32_t>(i) & 255u];
  const uint32_t column1 = perm[static_cast<uint32_t>(i + 1) & 255u];
  const uint32_t row = static_cast<uint32_t>(j);
  const float v00 = value[perm[(column0 + row) & 255u]];
  const float v10 = value[perm[(column1 + row) & 255u]];
  const float v01 = value[perm[(column0 + row + 1u) & 255u]];
  const float v11 = value[perm[(column1 + row + 1u) & 255u]];
  const float bottom = v00 + sx * (v10 - v00);
  const float top = v01 + sx * (v11 - v01);
  return bottom + sy * (top - bottom);
}

// Texture coordinates of p on the face with normal n: the two axes across n's largest component.
inline Eigen::Vector2f FaceUv(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  const float ax = std::fabs(n.x());
  const float ay = std::fabs(n.y());
  const float az = std::fabs(n.z());
  if (az >= ax && az >= ay) return {p.x(), p.y()};
  if (ax >= ay) return {p.y(), p.z()};
  return {p.x(), p.z()};
}

// Where face coordinates uv (metres) lie between the colours: 0 colour_a, 1 colour_b.
inline float Pattern(const ProceduralTexture& texture, const Eigen::Vector2f& uv) {
  // Turned by the angle, in units of the feature size: u runs along the grain / across the stripes.
  const float u = (texture.cos_angle * uv.x() + texture.sin_angle * uv.y()) * texture.inv_scale;
  const float v = (-texture.sin_angle * uv.x() + texture.cos_angle * uv.y()) * texture.inv_scale;
  switch (texture.pattern) {
    case engine::TexturePattern::kChecker: return static_cast<float>((FloorToInt(u) ^ FloorToInt(v)) & 1);
    case engine::TexturePattern::kStripes: return static_cast<float>(FloorToInt(u) & 1);
    case engine::TexturePattern::kNoise: return Noise(u, v);
    case engine::TexturePattern::kWood: {
      // Rings one feature size apart across the grain (v), each darkening towards its edge (the
      // late wood) and restarting light; value noise bends them.
      const float ring = v + texture.turbulence * Noise(kGrainAlong * u, kGrainAcross * v);
      const float t = ring - static_cast<float>(FloorToInt(ring));
      return t * t;
    }
    case engine::TexturePattern::kNone:
    case engine::TexturePattern::kSolid: break;
  }
  return 0.0f;
}

// The reflectance at local point p with local normal n (render::TextureReflectance). Always
// inlined: the shading loop calls it from two places (flat faces, round shapes), and GCC then
// made it a call again (perf: 9% of a textured render).
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
inline Eigen::Vector3f
EvaluateTexture(const ProceduralTexture& texture, const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  switch (texture.pattern) {
    case engine::TexturePattern::kNone:
    case engine::TexturePattern::kSolid: return texture.colour_a;
    case engine::TexturePattern::kChecker:
    case engine::TexturePattern::kStripes:
      // Exactly one of the two colours, not a blend that rounds differently.
      return Pattern(texture, FaceUv(p, n)) != 0.0f ? texture.colour_b : texture.colour_a;
    case engine::TexturePattern::kNoise:
    case engine::TexturePattern::kWood: break;
  }
  const float value = Pattern(texture, FaceUv(p, n));
  return texture.colour_a + value * (texture.colour_b - texture.colour_a);
}

}  // namespace tavis::render::internal
