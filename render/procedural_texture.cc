#include "render/procedural_texture.h"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>

namespace tavis::render {
namespace {

using engine::TexturePattern;

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
constexpr float kMinScaleM = 1e-3f;
constexpr float kMaxScaleM = 100.0f;
constexpr float kMaxTurbulence = 8.0f;
// The wood's noise varies slowly along the grain and faster across it: the rings wander over a
// few ring spacings across, and over several along the grain.
constexpr float kGrainAlong = 0.15f;
constexpr float kGrainAcross = 0.5f;

bool IsUnitColour(const Eigen::Vector3f& rgb) {
  return rgb.allFinite() && (rgb.array() >= 0.0f).all() && (rgb.array() <= 1.0f).all();
}

std::string Describe(const Eigen::Vector3f& v) {
  std::ostringstream text;
  text << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return text.str();
}

// A lattice corner's value in [0, 1): an integer hash of (i, j) (a fixed function, no seed).
float LatticeValue(int32_t i, int32_t j) {
  uint32_t h = static_cast<uint32_t>(i) * 0x8da6b343u ^ static_cast<uint32_t>(j) * 0xd8163841u;
  h = (h ^ (h >> 16)) * 0x7feb352du;
  h = (h ^ (h >> 15)) * 0x846ca68bu;
  h ^= h >> 16;
  return static_cast<float>(h >> 8) * 0x1.0p-24f;
}

// The parity of the cell holding x: 0 or 1 (negative cells too).
int CellParity(float x) { return static_cast<int>(std::floor(x)) & 1; }

}  // namespace

ProceduralTexture MakeProceduralTexture(const engine::SurfaceTexture& texture) {
  ProceduralTexture compiled;
  compiled.pattern = texture.pattern;
  compiled.inv_scale = static_cast<float>(1.0 / texture.scale_m);
  compiled.cos_angle = static_cast<float>(std::cos(texture.angle_deg * kDegToRad));
  compiled.sin_angle = static_cast<float>(std::sin(texture.angle_deg * kDegToRad));
  compiled.turbulence = static_cast<float>(texture.turbulence);
  compiled.colour_a = texture.colour_a;
  compiled.colour_b = texture.colour_b;
  if (!(std::fabs(texture.angle_deg) <= 360.0)) {
    throw std::invalid_argument("texture angle_deg = " + std::to_string(texture.angle_deg) +
                                " must lie in [-360, 360]");
  }
  ValidateProceduralTexture(compiled, "texture");
  return compiled;
}

void ValidateProceduralTexture(const ProceduralTexture& texture, const std::string& what) {
  if (texture.pattern == TexturePattern::kNone) return;
  const float scale = 1.0f / texture.inv_scale;
  if (texture.pattern != TexturePattern::kSolid && !(scale >= kMinScaleM && scale <= kMaxScaleM)) {
    throw std::invalid_argument(what + ": scale " + std::to_string(scale) + " m must lie in [0.001, 100] m");
  }
  if (!IsUnitColour(texture.colour_a))
    throw std::invalid_argument(what + ": colour_a " + Describe(texture.colour_a) + " must be in [0, 1]");
  if (!IsUnitColour(texture.colour_b))
    throw std::invalid_argument(what + ": colour_b " + Describe(texture.colour_b) + " must be in [0, 1]");
  const float rotation_norm = texture.cos_angle * texture.cos_angle + texture.sin_angle * texture.sin_angle;
  if (!(std::fabs(rotation_norm - 1.0f) < 1e-4f)) {
    throw std::invalid_argument(what + ": (cos, sin) of the angle (" + std::to_string(texture.cos_angle) + ", " +
                                std::to_string(texture.sin_angle) + ") is not a unit vector");
  }
  if (!(texture.turbulence >= 0.0f && texture.turbulence <= kMaxTurbulence)) {
    throw std::invalid_argument(what + ": turbulence " + std::to_string(texture.turbulence) + " must lie in [0, 8]");
  }
}

Eigen::Vector2f FaceCoordinates(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  const Eigen::Vector3f m = n.cwiseAbs();
  if (m.z() >= m.x() && m.z() >= m.y()) return {p.x(), p.y()};
  if (m.x() >= m.y()) return {p.y(), p.z()};
  return {p.x(), p.z()};
}

float ValueNoise(float x, float y) {
  const float fx = std::floor(x);
  const float fy = std::floor(y);
  const int32_t i = static_cast<int32_t>(fx);
  const int32_t j = static_cast<int32_t>(fy);
  const float tx = x - fx;
  const float ty = y - fy;
  // Smoothstep weights: the noise is continuous with a continuous slope across cell edges.
  const float sx = tx * tx * (3.0f - 2.0f * tx);
  const float sy = ty * ty * (3.0f - 2.0f * ty);
  const float bottom = LatticeValue(i, j) + sx * (LatticeValue(i + 1, j) - LatticeValue(i, j));
  const float top = LatticeValue(i, j + 1) + sx * (LatticeValue(i + 1, j + 1) - LatticeValue(i, j + 1));
  return bottom + sy * (top - bottom);
}

float PatternValue(const ProceduralTexture& texture, const Eigen::Vector2f& uv) {
  // Turned by the angle, in units of the feature size: u runs along the grain / across the stripes.
  const float u = (texture.cos_angle * uv.x() + texture.sin_angle * uv.y()) * texture.inv_scale;
  const float v = (-texture.sin_angle * uv.x() + texture.cos_angle * uv.y()) * texture.inv_scale;
  switch (texture.pattern) {
    case TexturePattern::kChecker: return static_cast<float>(CellParity(u) ^ CellParity(v));
    case TexturePattern::kStripes: return static_cast<float>(CellParity(u));
    case TexturePattern::kNoise: return ValueNoise(u, v);
    case TexturePattern::kWood: {
      // Rings one feature size apart across the grain (v), each darkening towards its edge (the
      // late wood) and restarting light; value noise bends them.
      const float ring = v + texture.turbulence * ValueNoise(kGrainAlong * u, kGrainAcross * v);
      const float t = ring - std::floor(ring);
      return t * t;
    }
    case TexturePattern::kNone:
    case TexturePattern::kSolid: break;
  }
  return 0.0f;
}

Eigen::Vector3f TextureReflectance(const ProceduralTexture& texture, const Eigen::Vector3f& p,
                                   const Eigen::Vector3f& n) {
  switch (texture.pattern) {
    case TexturePattern::kNone:
    case TexturePattern::kSolid: return texture.colour_a;
    case TexturePattern::kChecker:
    case TexturePattern::kStripes:
      // Exactly one of the two colours, not a blend that rounds differently.
      return PatternValue(texture, FaceCoordinates(p, n)) != 0.0f ? texture.colour_b : texture.colour_a;
    case TexturePattern::kNoise:
    case TexturePattern::kWood: break;
  }
  const float value = PatternValue(texture, FaceCoordinates(p, n));
  return texture.colour_a + value * (texture.colour_b - texture.colour_a);
}

}  // namespace tavis::render
