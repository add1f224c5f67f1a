// Small scenes and image helpers shared by the render tests.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "render/batch_renderer.h"

namespace tavis::render::testing {

// A layout with the poses of one or more envs, owning the buffers RenderInputs points into.
struct TestScene {
  SceneLayout layout;
  int num_envs = 1;
  std::vector<RigidTransform> X_WI;  // [env][instance]
  std::vector<RigidTransform> X_WC;  // [env][camera]
  std::vector<uint8_t> instance_visible;
  std::vector<uint8_t> camera_enabled;

  // Appends an instance at pose X_WI to the layout and to every env's poses (single env only).
  void Add(const ShapeGeometry& geometry, const Appearance& appearance, int32_t object_id, const RigidTransform& X_WI);
  void AddCamera(const CameraSpec& camera, const RigidTransform& X_WC);
  // Copies env 0 to n envs.
  void Replicate(int n);
  RenderInputs Inputs() const;
};

// Floor, a table (top and four legs), a red cube (object 0), a soup-can cylinder (object 1) and a
// capsule (object 2); cameras head, fixed, left_wrist, right_wrist at width x height.
TestScene GoldenScene(int width, int height);

// Floor, table, and 14 shapes of random pose and size over it (boxes, spheres, capsules,
// cylinders; plain, labelled and one emissive; object ids 0-13), drawn from `rng`; no camera.
TestScene RandomClusterOverTable(std::mt19937* rng);

// Head camera 10 cm in front of the neck at GR1T2's zero pose, pitched down by `pitch_deg`.
RigidTransform PitchedHeadCameraPose(double pitch_deg);

// Camera pose = link pose composed with the reference GR1T2 wrist-camera mount (§6.1).
RigidTransform Gr1t2WristCameraPose(const RigidTransform& X_W_hand);

struct PixelBlob {
  int64_t count = 0;
  double u = 0.0;  // centroid, continuous pixel coordinates (pixel centres at +0.5)
  double v = 0.0;
};

PixelBlob FindObject(const ImageBatch& images, int env, int camera, int32_t object_id);

// Sum of the three channels of pixel (u, v) rounded down to integers.
int Brightness(const ImageBatch& images, int env, int camera, double u, double v);

bool AllZero(const ImageBatch& images, int env, int camera);

// Env 0's colours and object ids of every camera, copied out: what tests compare byte for byte.
struct EnvImages {
  std::vector<std::vector<uint8_t>> rgb;  // [camera]
  std::vector<std::vector<int32_t>> ids;  // [camera]
};

// Validates `inputs` (the scene's own or changed ones) and renders env 0 with object ids.
EnvImages RenderEnvZero(const TestScene& scene, const RenderInputs& inputs);

std::string GoldenDirectory();

}  // namespace tavis::render::testing
