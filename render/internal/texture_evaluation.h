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

// Which coordinates of a local point are a face's texture coordinates (u, v): the two axes across
// the largest component of its normal n. One face has one answer, so a packet of hits on one face
// asks once.
struct FaceAxes {
  int u;
  int v;
};

inline FaceAxes FaceUvAxes(const Eigen::Vector3f& n) {
  const float ax = std::fabs(n.x());
  const float ay = std::fabs(n.y());
  const float az = std::fabs(n.z());
  if (az >= ax && az >= ay) return {0, 1};
  if (ax >= ay) return {1, 2};
  return {0, 2};
}

// Texture coordinates of p on the face with normal n.
inline Eigen::Vector2f FaceUv(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  const FaceAxes axes = FaceUvAxes(n);
  return {p[axes.u], p[axes.v]};
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

// Noise for K points at once: the cells, weights and blends as arrays (the compiler vectorises
// them), the table look-ups one lane at a time. The same floats as Noise lane by lane.
template <int K>
void NoiseLanes(const float* x, const float* y, float* noise) {
  int32_t i[K], j[K];
  float sx[K], sy[K];
  for (int k = 0; k < K; ++k) {
    i[k] = FloorToInt(x[k]);
    j[k] = FloorToInt(y[k]);
    const float tx = x[k] - static_cast<float>(i[k]);
    const float ty = y[k] - static_cast<float>(j[k]);
    sx[k] = tx * tx * (3.0f - 2.0f * tx);
    sy[k] = ty * ty * (3.0f - 2.0f * ty);
  }
  float v00[K], v10[K], v01[K], v11[K];
  const auto& perm = kNoiseTables.permutation;
  const auto& value = kNoiseTables.values;
  for (int k = 0; k < K; ++k) {
    const uint32_t column0 = perm[static_cast<uint32_t>(i[k]) & 255u];
    const uint32_t column1 = perm[static_cast<uint32_t>(i[k] + 1) & 255u];
    const uint32_t row = static_cast<uint32_t>(j[k]);
    v00[k] = value[perm[(column0 + row) & 255u]];
    v10[k] = value[perm[(column1 + row) & 255u]];
    v01[k] = value[perm[(column0 + row + 1u) & 255u]];
    v11[k] = value[perm[(column1 + row + 1u) & 255u]];
  }
  for (int k = 0; k < K; ++k) {
    const float bottom = v00[k] + sx[k] * (v10[k] - v00[k]);
    const float top = v01[k] + sx[k] * (v11[k] - v01[k]);
    noise[k] = bottom + sy[k] * (top - bottom);
  }
}

// EvaluateTexture for K points of one face, as arrays: local points (px, py, pz)[k] in, the
// reflectance (r, g, b)[k] out. The face's axes are chosen once (FaceUvAxes of its local normal);
// every lane is the same floats as EvaluateTexture of that point, so a packet of hits shades
// exactly as its pixels one at a time (tests/render/procedural_texture_test.cc).
template <int K>
void EvaluateTextureLanes(const ProceduralTexture& texture, const float* const local[3], const FaceAxes& axes, float* r,
                          float* g, float* b) {
  float value[K] = {};  // 0 (colour_a) for the patterns without a value
  const float* uv_x = local[axes.u];
  const float* uv_y = local[axes.v];
  float u[K], v[K];
  for (int k = 0; k < K; ++k) {
    u[k] = (texture.cos_angle * uv_x[k] + texture.sin_angle * uv_y[k]) * texture.inv_scale;
    v[k] = (-texture.sin_angle * uv_x[k] + texture.cos_angle * uv_y[k]) * texture.inv_scale;
  }
  switch (texture.pattern) {
    case engine::TexturePattern::kNone:
    case engine::TexturePattern::kSolid: break;
    case engine::TexturePattern::kChecker:
      for (int k = 0; k < K; ++k) value[k] = static_cast<float>((FloorToInt(u[k]) ^ FloorToInt(v[k])) & 1);
      break;
    case engine::TexturePattern::kStripes:
      for (int k = 0; k < K; ++k) value[k] = static_cast<float>(FloorToInt(u[k]) & 1);
      break;
    case engine::TexturePattern::kNoise: NoiseLanes<K>(u, v, value); break;
    case engine::TexturePattern::kWood: {
      float along[K], across[K], bend[K];
      for (int k = 0; k < K; ++k) {
        along[k] = kGrainAlong * u[k];
        across[k] = kGrainAcross * v[k];
      }
      NoiseLanes<K>(along, across, bend);
      for (int k = 0; k < K; ++k) {
        const float ring = v[k] + texture.turbulence * bend[k];
        const float t = ring - static_cast<float>(FloorToInt(ring));
        value[k] = t * t;
      }
      break;
    }
  }
  const Eigen::Vector3f& a = texture.colour_a;
  const Eigen::Vector3f& c = texture.colour_b;
  if (texture.pattern == engine::TexturePattern::kChecker || texture.pattern == engine::TexturePattern::kStripes) {
    // Exactly one of the two colours, as EvaluateTexture.
    for (int k = 0; k < K; ++k) {
      const bool second = value[k] != 0.0f;
      r[k] = second ? c.x() : a.x();
      g[k] = second ? c.y() : a.y();
      b[k] = second ? c.z() : a.z();
    }
    return;
  }
  // colour_a + value * (colour_b - colour_a) per channel (value 0 for a solid colour: colour_a).
  const float dr = c.x() - a.x(), dg = c.y() - a.y(), db = c.z() - a.z();
  for (int k = 0; k < K; ++k) {
    r[k] = a.x() + value[k] * dr;
    g[k] = a.y() + value[k] * dg;
    b[k] = a.z() + value[k] * db;
  }
}

}  // namespace tavis::render::internal
