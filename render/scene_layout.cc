#include "render/scene_layout.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "render/internal/colour_check.h"

namespace tavis::render {
namespace {

using internal::IsUnitColour;

void ValidateLighting(const LightingSpec& lighting) {
  auto fail = [](const std::string& message) { throw std::invalid_argument("lighting: " + message); };
  if (!std::isfinite(lighting.dome_intensity) || lighting.dome_intensity < 0.0f)
    fail("dome_intensity = " + std::to_string(lighting.dome_intensity) + " must be finite and >= 0");
  if (!std::isfinite(lighting.distant_intensity) || lighting.distant_intensity < 0.0f)
    fail("distant_intensity = " + std::to_string(lighting.distant_intensity) + " must be finite and >= 0");
  if (!IsUnitColour(lighting.dome_rgb))
    fail("dome_rgb " + internal::DescribeColour(lighting.dome_rgb) + " must be in [0, 1]");
  if (!IsUnitColour(lighting.distant_rgb))
    fail("distant_rgb " + internal::DescribeColour(lighting.distant_rgb) + " must be in [0, 1]");
  if (!lighting.distant_direction.allFinite() || lighting.distant_direction.norm() < 1e-6f)
    fail("distant_direction " + internal::DescribeColour(lighting.distant_direction) + " must be finite and non-zero");
  if (!std::isfinite(lighting.ground_bounce) || lighting.ground_bounce < 0.0f || lighting.ground_bounce > 1.0f)
    fail("ground_bounce = " + std::to_string(lighting.ground_bounce) + " must be in [0, 1]");
  if (!std::isfinite(lighting.exposure) || lighting.exposure <= 0.0f)
    fail("exposure = " + std::to_string(lighting.exposure) + " must be positive and finite");
}

}  // namespace

void ValidateSceneLayout(const SceneLayout& layout) {
  if (layout.cameras.empty()) throw std::invalid_argument("scene layout has no cameras");
  for (std::size_t c = 0; c < layout.cameras.size(); ++c) {
    ValidateCamera(layout.cameras[c]);
    for (std::size_t other = 0; other < c; ++other) {
      if (layout.cameras[other].name == layout.cameras[c].name)
        throw std::invalid_argument("scene layout: camera name '" + layout.cameras[c].name + "' is used twice");
    }
  }
  for (std::size_t i = 0; i < layout.instances.size(); ++i) {
    const InstanceSpec& instance = layout.instances[i];
    const std::string what = "instance " + std::to_string(i);
    ValidateShape(instance.geometry, what);
    if (!IsUnitColour(instance.appearance.rgb))
      throw std::invalid_argument(what + ": rgb " + internal::DescribeColour(instance.appearance.rgb) +
                                  " must be in [0, 1]");
    if (!IsUnitColour(instance.appearance.label_rgb))
      throw std::invalid_argument(what + ": label_rgb " + internal::DescribeColour(instance.appearance.label_rgb) +
                                  " must be in [0, 1]");
    if (instance.object_id < kBackgroundObjectId)
      throw std::invalid_argument(what + ": object_id = " + std::to_string(instance.object_id) + " must be >= -1");
  }
  ValidateLighting(layout.lighting);
}

}  // namespace tavis::render
