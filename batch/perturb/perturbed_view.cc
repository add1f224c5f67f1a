#include "batch/perturb/perturbed_view.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "engine/random.h"

namespace tavis::batch::perturb {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

Mat3 RotationFromDegrees(const Vec3& rpy_deg) { return RotationFromRpy(rpy_deg * kDegToRad); }

// Planck's law up to a constant factor: the spectral radiance of a black body at `kelvin` at
// wavelength `metres`.
double Planck(double metres, double kelvin) {
  constexpr double kSecondRadiationConstant = 1.438777e-2;  // h c / k_B, m K
  return 1.0 / (std::pow(metres, 5) * (std::exp(kSecondRadiationConstant / (metres * kelvin)) - 1.0));
}

// The three wavelengths that stand for the display's red, green and blue primaries.
constexpr double kRedM = 610e-9;
constexpr double kGreenM = 550e-9;
constexpr double kBlueM = 465e-9;

// 1-D Gaussian weights for radius ceil(3 sigma), summing to 1.
std::vector<float> GaussianKernel(double sigma) {
  const int radius = std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
  std::vector<float> weights(static_cast<std::size_t>(2 * radius + 1));
  double sum = 0.0;
  for (int i = -radius; i <= radius; ++i) sum += std::exp(-0.5 * i * i / (sigma * sigma));
  for (int i = -radius; i <= radius; ++i) {
    weights[static_cast<std::size_t>(i + radius)] = static_cast<float>(std::exp(-0.5 * i * i / (sigma * sigma)) / sum);
  }
  return weights;
}

// Separable blur with the edge pixels repeated beyond the border.
void Blur(const std::vector<float>& kernel, int width, int height, uint8_t* rgb) {
  const int radius = static_cast<int>(kernel.size() / 2);
  std::vector<float> rows(static_cast<std::size_t>(width) * height * 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int ch = 0; ch < 3; ++ch) {
        float sum = 0.0f;
        for (int k = -radius; k <= radius; ++k) {
          const int xs = std::clamp(x + k, 0, width - 1);
          sum +=
              kernel[static_cast<std::size_t>(k + radius)] * rgb[(static_cast<std::size_t>(y) * width + xs) * 3 + ch];
        }
        rows[(static_cast<std::size_t>(y) * width + x) * 3 + ch] = sum;
      }
    }
  }
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int ch = 0; ch < 3; ++ch) {
        float sum = 0.0f;
        for (int k = -radius; k <= radius; ++k) {
          const int ys = std::clamp(y + k, 0, height - 1);
          sum +=
              kernel[static_cast<std::size_t>(k + radius)] * rows[(static_cast<std::size_t>(ys) * width + x) * 3 + ch];
        }
        rgb[(static_cast<std::size_t>(y) * width + x) * 3 + ch] =
            static_cast<uint8_t>(std::clamp(std::lround(sum), 0L, 255L));
      }
    }
  }
}

// A camera's stable number for the noise key: FNV-1a of its name, so that its noise does not
// depend on which other cameras are rendered.
uint64_t CameraKey(const std::string& name) {
  uint64_t hash = 0xcbf29ce484222325ull;
  for (const char c : name) hash = (hash ^ static_cast<uint8_t>(c)) * 0x100000001b3ull;
  return hash;
}

// Adds N(0, stddev) to each channel; a pixel's draw is a pure function of (key, pixel index).
void AddNoise(uint64_t key, double stddev, std::size_t pixels, uint8_t* rgb) {
  for (std::size_t p = 0; p < pixels; ++p) {
    for (int ch = 0; ch < 3; ++ch) {
      const uint64_t bits = engine::MixBits(key ^ (3 * p + static_cast<uint64_t>(ch)));
      // Box-Muller on the two 32-bit halves; 1 - u1 lies in (0, 1], so the logarithm is finite.
      const double u1 = static_cast<double>(bits >> 32) * 0x1.0p-32;
      const double u2 = static_cast<double>(bits & 0xFFFFFFFFull) * 0x1.0p-32;
      const double normal = std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(2.0 * M_PI * u2);
      uint8_t& value = rgb[3 * p + static_cast<std::size_t>(ch)];
      value = static_cast<uint8_t>(std::clamp(std::lround(value + stddev * normal), 0L, 255L));
    }
  }
}

}  // namespace

render::CameraSpec PerturbedCameraSpec(render::CameraSpec spec, const engine::RenderPerturbation& perturbation) {
  const double scale = spec.name == "head"    ? perturbation.head_fov_scale
                       : spec.name == "fixed" ? perturbation.fixed_fov_scale
                                              : 1.0;
  if (scale == 1.0) return spec;
  const double angle = scale * 2.0 * std::atan(spec.horizontal_aperture_mm / (2.0 * spec.focal_length_mm));
  if (!(angle > 0.0 && angle < M_PI)) {
    throw std::invalid_argument("field of view scale " + std::to_string(scale) + " gives the " + spec.name +
                                " camera an angle of view of " + std::to_string(angle / kDegToRad) +
                                " degrees (must lie in (0, 180))");
  }
  spec.focal_length_mm = spec.horizontal_aperture_mm / (2.0 * std::tan(angle / 2.0));
  return spec;
}

RigidTransform CameraMountOffset(const std::string& camera, const engine::RenderPerturbation& perturbation) {
  if (camera != "head") return RigidTransform::Identity();
  return MakeTransform(perturbation.head_offset_m, RotationFromDegrees(perturbation.head_rotation_deg));
}

RigidTransform PerturbedFixedCameraPose(const RigidTransform& X_WC, const engine::RenderPerturbation& perturbation) {
  if (perturbation.fixed_offset_m.isZero(0) && perturbation.fixed_rotation_deg.isZero(0)) return X_WC;
  // Moved in the world, then panned about the world's vertical (yaw), tilted about its own
  // image-left axis (pitch, positive looks down) and rolled about its optical axis: a tripod
  // camera set up at a new viewpoint.
  const Vec3 rpy = perturbation.fixed_rotation_deg * kDegToRad;
  const Mat3 pan = Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()).toRotationMatrix();
  const Mat3 tilt_roll =
      (Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) * Eigen::AngleAxisd(rpy.x(), Vec3::UnitX())).toRotationMatrix();
  return MakeTransform(X_WC.translation() + perturbation.fixed_offset_m, pan * X_WC.linear() * tilt_roll);
}

Eigen::Vector3f BlackBodyTint(double kelvin) {
  if (!(kelvin >= 1000.0 && kelvin <= 40000.0)) {
    throw std::invalid_argument("colour temperature " + std::to_string(kelvin) + " K is outside [1000, 40000] K");
  }
  constexpr double kWhiteK = 6500.0;
  Eigen::Vector3d rgb(Planck(kRedM, kelvin) / Planck(kRedM, kWhiteK),
                      Planck(kGreenM, kelvin) / Planck(kGreenM, kWhiteK),
                      Planck(kBlueM, kelvin) / Planck(kBlueM, kWhiteK));
  // Rec. 709 luminance weights: the tinted light is as bright as the white one.
  rgb /= 0.2126 * rgb.x() + 0.7152 * rgb.y() + 0.0722 * rgb.z();
  return rgb.cast<float>();
}

void PerturbLighting(const engine::RenderPerturbation& perturbation, render::LightingSpec* lighting) {
  if (!perturbation.changes_lighting()) return;
  const float scale = static_cast<float>(perturbation.light_intensity_scale);
  lighting->dome_intensity *= scale;
  lighting->distant_intensity *= scale;
  if (perturbation.colour_temperature_k != 0.0) {
    // A light's colour lies in [0, 1] (render::ValidateSceneLayout): the tint's largest component
    // goes into the intensity instead.
    const Eigen::Vector3f tint = BlackBodyTint(perturbation.colour_temperature_k);
    const float peak = tint.maxCoeff();
    lighting->dome_rgb = lighting->dome_rgb.cwiseProduct(tint / peak);
    lighting->distant_rgb = lighting->distant_rgb.cwiseProduct(tint / peak);
    lighting->dome_intensity *= peak;
    lighting->distant_intensity *= peak;
  }
  if (perturbation.light_azimuth_deg != 0.0 || perturbation.light_elevation_deg != 0.0) {
    const Eigen::Vector3d travel = lighting->distant_direction.cast<double>().normalized();
    const Eigen::Vector2d horizontal = travel.head<2>();
    const double azimuth = std::atan2(horizontal.y(), horizontal.x()) + perturbation.light_azimuth_deg * kDegToRad;
    // The sun's elevation above the horizon (the light travels downwards).
    const double elevation = std::atan2(-travel.z(), horizontal.norm()) + perturbation.light_elevation_deg * kDegToRad;
    if (!(elevation > 0.0 && elevation <= M_PI / 2.0)) {
      throw std::invalid_argument("light elevation change " + std::to_string(perturbation.light_elevation_deg) +
                                  " degrees puts the light at " + std::to_string(elevation / kDegToRad) +
                                  " degrees above the horizon (must lie in (0, 90])");
    }
    lighting->distant_direction = Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
                                                  std::cos(elevation) * std::sin(azimuth), -std::sin(elevation))
                                      .cast<float>();
  }
}

void ApplySensorPerturbationToEnv(const engine::RenderPerturbation& perturbation, const engine::BatchState& state,
                                  const std::vector<std::string>& camera_names, const std::vector<uint8_t>& enabled,
                                  int env, render::ImageBatch* images) {
  if (!perturbation.changes_images()) return;
  const std::vector<float> kernel =
      perturbation.blur_sigma_px > 0.0 ? GaussianKernel(perturbation.blur_sigma_px) : std::vector<float>();
  const int cameras = images->n_cameras();
  for (int camera = 0; camera < cameras; ++camera) {
    if (enabled[static_cast<std::size_t>(env) * cameras + camera] == 0) continue;
    const int width = images->width(camera);
    const int height = images->height(camera);
    uint8_t* rgb = images->rgb(env, camera);
    if (!kernel.empty()) Blur(kernel, width, height, rgb);
    if (perturbation.noise_stddev > 0.0) {
      const uint64_t episode_key =
          engine::DeriveKey(perturbation.noise_seed, static_cast<uint64_t>(engine::RandomStreamId::kSensorNoise),
                            static_cast<uint64_t>(state.episode[static_cast<std::size_t>(env)]));
      const uint64_t tick = static_cast<uint64_t>(state.control_step[static_cast<std::size_t>(env)]);
      const uint64_t key = engine::MixBits(episode_key ^ engine::MixBits(tick) ^
                                           CameraKey(camera_names[static_cast<std::size_t>(camera)]));
      AddNoise(key, perturbation.noise_stddev, static_cast<std::size_t>(width) * height, rgb);
    }
  }
}

void ApplySensorPerturbation(const engine::RenderPerturbation& perturbation, const engine::BatchState& state,
                             const std::vector<std::string>& camera_names, const std::vector<uint8_t>& enabled,
                             render::ImageBatch* images) {
  if (!perturbation.changes_images()) return;
  tbb::parallel_for(0, images->num_envs(), [&](int env) {
    ApplySensorPerturbationToEnv(perturbation, state, camera_names, enabled, env, images);
  });
}

}  // namespace tavis::batch::perturb
