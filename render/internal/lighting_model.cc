#include "render/internal/lighting_model.h"

#include <cmath>

namespace tavis::render::internal {
namespace {

constexpr float kPi = 3.14159265f;

}  // namespace

LightingModel::LightingModel(const LightingSpec& spec)
    : to_light_(-spec.distant_direction.normalized()),
      ambient_(spec.dome_rgb * (kPi * spec.dome_intensity * spec.exposure)),
      direct_(spec.distant_rgb * (spec.distant_intensity * spec.exposure)),
      background_(ambient_),
      ground_bounce_(spec.ground_bounce),
      shadows_(spec.shadows) {}

SrgbEncoder::SrgbEncoder() {
  for (int i = 0; i < kSteps; ++i) {
    const double linear = static_cast<double>(i) / (kSteps - 1);
    const double encoded = linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
    table_[static_cast<std::size_t>(i)] = static_cast<uint8_t>(std::lround(255.0 * encoded));
  }
}

}  // namespace tavis::render::internal
