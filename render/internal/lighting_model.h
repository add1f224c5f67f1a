// Lighting of a diffuse surface by the dome and the distant light, and the sRGB encoding of
// linear display values.
#pragma once

#include <array>
#include <cstdint>

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
    const float sky = 0.5f * (1.0f + n.z()) + ground_bounce_ * 0.5f * (1.0f - n.z());
    return rgb.cwiseProduct(sky * ambient_ + direct_cosine * direct_);
  }

  // Shade() over K lanes in structure-of-arrays form: out[c][k] is channel c of
  // Shade(rgb[.][k], a normal with z component nz[k], direct_cosine[k]), computed in the same
  // order, so the values are identical. One loop without branches over arrays that do not
  // overlap (__restrict), so it vectorises.
  template <int K>
  void ShadeLanes(const float (&__restrict rgb)[3][K], const float (&__restrict nz)[K],
                  const float (&__restrict direct_cosine)[K], float (&__restrict out)[3][K]) const {
    const float half_bounce = ground_bounce_ * 0.5f;
    const float ambient_r = ambient_.x(), ambient_g = ambient_.y(), ambient_b = ambient_.z();
    const float direct_r = direct_.x(), direct_g = direct_.y(), direct_b = direct_.z();
    for (int k = 0; k < K; ++k) {
      const float sky = 0.5f * (1.0f + nz[k]) + half_bounce * (1.0f - nz[k]);
      out[0][k] = rgb[0][k] * (sky * ambient_r + direct_cosine[k] * direct_r);
      out[1][k] = rgb[1][k] * (sky * ambient_g + direct_cosine[k] * direct_g);
      out[2][k] = rgb[2][k] * (sky * ambient_b + direct_cosine[k] * direct_b);
    }
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

  uint8_t Encode(float linear) const { return table_[static_cast<std::size_t>(TableIndex(linear))]; }

  // Encode() in two steps, so the index arithmetic can run over many values at once (it
  // vectorises; the table look-up does not): Encode(x) == Lookup(TableIndex(x)).
  static int32_t TableIndex(float linear) {
    const float scaled = linear * static_cast<float>(kSteps - 1) + 0.5f;
    // Clamped in float before the conversion, so no lane converts an out-of-range value.
    const float low_clamped = scaled > 0.0f ? scaled : 0.0f;
    const float clamped = low_clamped < static_cast<float>(kSteps - 1) ? low_clamped : static_cast<float>(kSteps - 1);
    return static_cast<int32_t>(clamped);
  }
  uint8_t Lookup(int32_t index) const { return table_[static_cast<std::size_t>(index)]; }

 private:
  static constexpr int kSteps = 4096;
  std::array<uint8_t, kSteps> table_;
};

}  // namespace tavis::render::internal
