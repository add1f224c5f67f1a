// The flat, immutable description of what one env's scene contains: shapes with their looks, the
// cameras and the lights. Built once; per-tick poses arrive separately (render_inputs.h).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "render/appearance.h"
#include "render/camera.h"
#include "render/shape.h"

namespace tavis::render {

inline constexpr int32_t kBackgroundObjectId = -1;

struct InstanceSpec {
  ShapeGeometry geometry;
  Appearance appearance;
  int32_t object_id = kBackgroundObjectId;  // -1 for floor, table, robot; task objects 0..n-1
};

// Reference spec §2.1: a white dome light of intensity 800 and a white distant light of
// intensity 2000 travelling along (-0.342, -0.321, -0.883), shadows on. Irradiance from the dome
// is pi * intensity on an upward face; `exposure` maps irradiance times reflectance to linear
// display values (the default puts a white, fully lit upward face at 0.8).
struct LightingSpec {
  float dome_intensity = 800.0f;
  Eigen::Vector3f dome_rgb = Eigen::Vector3f::Ones();
  float distant_intensity = 2000.0f;
  Eigen::Vector3f distant_rgb = Eigen::Vector3f::Ones();
  Eigen::Vector3f distant_direction = Eigen::Vector3f(-0.342f, -0.321f, -0.883f);  // of travel
  bool shadows = true;
  // Fraction of the dome's light that reaches a downward face (light bounced off the ground).
  float ground_bounce = 0.25f;
  float exposure = 0.8f / 4280.0f;
};

struct SceneLayout {
  std::vector<InstanceSpec> instances;
  std::vector<CameraSpec> cameras;
  LightingSpec lighting;
};

// Throws std::invalid_argument naming the instance/camera index and the bad value: no cameras,
// duplicate camera names, invalid shapes or cameras, colours outside [0, 1], a zero or
// non-finite light direction, negative intensities or exposure, object ids below -1.
void ValidateSceneLayout(const SceneLayout& layout);

}  // namespace tavis::render
