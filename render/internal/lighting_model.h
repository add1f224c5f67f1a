// Lighting of a diffuse surface by the dome and the distant light, and the sRGB encoding of
// linear display values.
#pragma once

#include <array>
#include <cstddef>
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
  // Irradiance for K normals, given by their z components nz[k] (the only one it reads), and
  // cosines direct_cosine[k]: irradiance[channel][k], the same floats per lane.
  template <int K>
  void IrradianceLanes(const float* nz, const float* direct_cosine, float (*irradiance)[K]) const {
    float sky[K];
    for (int k = 0; k < K; ++k) sky[k] = 0.5f * (1.0f + nz[k]) + ground_bounce_ * 0.5f * (1.0f - nz[k]);
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < K; ++k) irradiance[c][k] = sky[k] * ambient_[c] + direct_cosine[k] * direct_[c];
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

  uint8_t Encode(float linear) const {
    const float scaled = linear * static_cast<float>(kSteps - 1) + 0.5f;
    const int index = scaled <= 0.0f ? 0 : scaled >= kSteps - 1 ? kSteps - 1 : static_cast<int>(scaled);
    return table_[static_cast<std::size_t>(index)];
  }

  // K colours given as channel arrays (r, g, b)[k], colour k written to first + k * stride: the
  // scaling and clamp as arrays the compiler vectorises (maxps / minps, the same operations as
  // Encode's), then the table look-ups. The same bytes as Encode per colour.
  template <int K>
  void EncodeLanes(const float* r, const float* g, const float* b, uint8_t* first, std::size_t stride) const {
    const float* channels[3] = {r, g, b};
    int32_t index[3][K];
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < K; ++k) {
        const float scaled = channels[c][k] * static_cast<float>(kSteps - 1) + 0.5f;
        const float above = scaled > 0.0f ? scaled : 0.0f;  // _mm_max_ps(scaled, 0)
        const float clamped = above < static_cast<float>(kSteps - 1) ? above : static_cast<float>(kSteps - 1);
        index[c][k] = static_cast<int32_t>(clamped);
      }
    }
    for (int k = 0; k < K; ++k) {
      uint8_t* rgb = first + static_cast<std::size_t>(k) * stride;
      for (int c = 0; c < 3; ++c) rgb[c] = table_[static_cast<std::size_t>(index[c][k])];
    }
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
    // The indices are read from the register (they fit 16 bits) rather than stored to memory
    // and loaded back one by one.
    const __m128i index = _mm_cvttps_epi32(clamped);
    rgb[0] = table_[static_cast<std::size_t>(_mm_cvtsi128_si32(index))];
    rgb[1] = table_[static_cast<std::size_t>(_mm_extract_epi16(index, 2))];
    rgb[2] = table_[static_cast<std::size_t>(_mm_extract_epi16(index, 4))];
#else
    for (int c = 0; c < 3; ++c) rgb[c] = Encode(linear[c]);
#endif
  }

 private:
  static constexpr int kSteps = 4096;
  std::array<uint8_t, kSteps> table_;
};

}  // namespace tavis::render::internal
