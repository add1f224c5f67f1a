#include "render/procedural_texture.h"

#include <cmath>
#include <stdexcept>

#include "render/internal/colour_check.h"
#include "render/internal/texture_evaluation.h"

namespace tavis::render {
namespace {

using engine::TexturePattern;

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
constexpr float kMinScaleM = 1e-3f;
constexpr float kMaxScaleM = 100.0f;
constexpr float kMaxTurbulence = 8.0f;

using internal::IsUnitColour;

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
    throw std::invalid_argument(what + ": colour_a " + internal::DescribeColour(texture.colour_a) +
                                " must be in [0, 1]");
  if (!IsUnitColour(texture.colour_b))
    throw std::invalid_argument(what + ": colour_b " + internal::DescribeColour(texture.colour_b) +
                                " must be in [0, 1]");
  const float rotation_norm = texture.cos_angle * texture.cos_angle + texture.sin_angle * texture.sin_angle;
  if (!(std::fabs(rotation_norm - 1.0f) < 1e-4f)) {
    throw std::invalid_argument(what + ": (cos, sin) of the angle (" + std::to_string(texture.cos_angle) + ", " +
                                std::to_string(texture.sin_angle) + ") is not a unit vector");
  }
  if (!(texture.turbulence >= 0.0f && texture.turbulence <= kMaxTurbulence)) {
    throw std::invalid_argument(what + ": turbulence " + std::to_string(texture.turbulence) + " must lie in [0, 8]");
  }
}

Eigen::Vector2f FaceCoordinates(const Eigen::Vector3f& p, const Eigen::Vector3f& n) { return internal::FaceUv(p, n); }

float ValueNoise(float x, float y) { return internal::Noise(x, y); }

float PatternValue(const ProceduralTexture& texture, const Eigen::Vector2f& uv) {
  return internal::Pattern(texture, uv);
}

Eigen::Vector3f TextureReflectance(const ProceduralTexture& texture, const Eigen::Vector3f& p,
                                   const Eigen::Vector3f& n) {
  return internal::EvaluateTexture(texture, p, n);
}

}  // namespace tavis::render
