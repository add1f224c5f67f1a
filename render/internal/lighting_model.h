// Lighting of a diffuse surface by the dome and the distant light, and the sRGB encoding of
// linear display values.
#pragma once

#include <array>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <Eigen/Core>

#include "render/scene_layout.h"

namespace tavis::render::internal {

class LightingModel {
 public:
  explicit LightingModel(const LightingSpec& spec);

  // Unit vector from a surface towards the distant light.
  const Eigen::Vector3f& to_light() const { return to_light_; }
  bool shadows() const { return shadows_; }
  // Linear display value of what rays that hit nothing see: the dome itself.
  const Eigen::Vector3f& background() const { return background_; }

  // Linear display value of reflectance `rgb` with world normal n; `direct_cosine` is n . to_light
  // when the light reaches the point and 0 in shadow. The dome term weights the sky by how much
  // of it the normal faces, with a fraction `ground_bounce` coming back from below.
  Eigen::Vector3f Shade(const Eigen::Vector3f& rgb, const Eigen::Vector3f& n, float direct_cosine) const {
    return rgb.cwiseProduct(Irradiance(n, direct_cosine));
  }
  // What Shade multiplies the reflectance by: the same for every point of a flat face, so a
  // textured face computes it once (FlatShades) and Shade's result stays the same floats.
  Eigen::Vector3f Irradiance(const Eigen::Vector3f& n, float direct_cosine) const {
    const float sky = 0.5f * (1.0f + n.z()) + ground_bounce_ * 0.5f * (1.0f - n.z());
    return sky * ambient_ + direct_cosine * direct_;
  }

 private:
  Eigen::Vector3f to_light_;
  Eigen::Vector3f ambient_;  // dome irradiance on an upward face, times exposure
  Eigen::Vector3f direct_;   // distant-light irradiance at normal incidence, times exposure
  Eigen::Vector3f background_;
  float ground_bounce_;
  bool shadows_;
};

// Linear [0, 1] -> 8-bit sRGB through a table (values outside [0, 1] clamp).
class SrgbEncoder {
 public:
  SrgbEncoder();

  uint8_t Encode(float linear) const {
    const float scaled = linear * static_cast<float>(kSteps - 1) + 0.5f;
    const int index = scaled <= 0.0f ? 0 : scaled >= kSteps - 1 ? kSteps - 1 : static_cast<int>(scaled);
    return table_[static_cast<std::size_t>(index)];
  }

  // The three channels at once: the same table entries as Encode per channel, with the scaling
  // and the clamp done on one SSE register (the same float operations, so the same bytes).
  void Encode(const Eigen::Vector3f& linear, uint8_t* rgb) const {
#if defined(__SSE2__)
    const __m128 scaled = _mm_add_ps(
        _mm_mul_ps(_mm_set_ps(0.0f, linear.z(), linear.y(), linear.x()), _mm_set1_ps(static_cast<float>(kSteps - 1))),
        _mm_set1_ps(0.5f));
    const __m128 clamped =
        _mm_min_ps(_mm_max_ps(scaled, _mm_setzero_ps()), _mm_set1_ps(static_cast<float>(kSteps - 1)));
    alignas(16) int32_t index[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(index), _mm_cvttps_epi32(clamped));
    for (int c = 0; c < 3; ++c) rgb[c] = table_[static_cast<std::size_t>(index[c])];
#else
    for (int c = 0; c < 3; ++c) rgb[c] = Encode(linear[c]);
#endif
  }

 private:
  static constexpr int kSteps = 4096;
  std::array<uint8_t, kSteps> table_;
};

}  // namespace tavis::render::internal
