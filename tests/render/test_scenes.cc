#include "tests/render/test_scenes.h"

#include <cmath>

#include "render/palette.h"

namespace tavis::render::testing {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

RigidTransform At(double x, double y, double z, double yaw_deg = 0.0) {
  return MakeTransform(Vec3(x, y, z), QuatFromYaw(yaw_deg * kDegToRad).toRotationMatrix());
}

}  // namespace

void TestScene::Add(const ShapeGeometry& geometry, const Appearance& appearance, int32_t object_id,
                    const RigidTransform& pose) {
  layout.instances.push_back({geometry, appearance, object_id});
  X_WI.push_back(pose);
  instance_visible.push_back(1);
}

void TestScene::AddCamera(const CameraSpec& camera, const RigidTransform& pose) {
  layout.cameras.push_back(camera);
  X_WC.push_back(pose);
  camera_enabled.push_back(1);
}

void TestScene::Replicate(int n) {
  auto repeat = [n](auto* values) {
    const auto first_env = *values;
    for (int env = 1; env < n; ++env) values->insert(values->end(), first_env.begin(), first_env.end());
  };
  repeat(&X_WI);
  repeat(&X_WC);
  repeat(&instance_visible);
  repeat(&camera_enabled);
  num_envs = n;
}

RenderInputs TestScene::Inputs() const {
  RenderInputs inputs;
  inputs.X_WI = X_WI;
  inputs.X_WC = X_WC;
  inputs.instance_visible = instance_visible;
  inputs.camera_enabled = camera_enabled;
  return inputs;
}

RigidTransform PitchedHeadCameraPose(double pitch_deg) {
  const Mat3 R = Eigen::AngleAxisd(pitch_deg * kDegToRad, Vec3::UnitY()).toRotationMatrix();
  return MakeTransform(Vec3(0.105, 0.0, 1.454), R);
}

RigidTransform Gr1t2WristCameraPose(const RigidTransform& X_W_hand) {
  const RigidTransform X_hand_camera = MakeTransform(
      Vec3(0.15, 0.0, 0.05), QuatFromWxyz(0.4617486, 0.0, 0.8870108, 0.0).normalized().toRotationMatrix());
  return X_W_hand * X_hand_camera;
}

TestScene GoldenScene(int width, int height) {
  TestScene scene;
  scene.Add(MakePlane(), PaletteAppearance("floor"), kBackgroundObjectId, RigidTransform::Identity());
  const Appearance& table = PaletteAppearance("table");
  scene.Add(MakeBox(Vec3(0.9, 1.2, 0.04)), table, kBackgroundObjectId, At(0.6, -0.1, 0.98));
  for (const double x : {0.2, 1.0}) {
    for (const double y : {-0.65, 0.45})
      scene.Add(MakeBox(Vec3(0.05, 0.05, 0.96)), table, kBackgroundObjectId, At(x, y, 0.48));
  }
  scene.Add(MakeBox(Vec3::Constant(0.055)), PaletteAppearance("red_cube"), 0, At(0.45, 0.0, 1.0275, 20.0));
  scene.Add(MakeCylinder(0.0248, 0.0758), PaletteAppearance("soup_can"), 1, At(0.42, 0.15, 1.0379));
  RigidTransform capsule_pose = At(0.38, -0.16, 1.06, 30.0);
  capsule_pose.rotate(Eigen::AngleAxisd(90.0 * kDegToRad, Vec3::UnitY()));
  scene.Add(MakeCapsule(0.03, 0.16), PaletteAppearance("robot_link"), 2, capsule_pose);

  scene.AddCamera(HeadCameraSpec(width, height), PitchedHeadCameraPose(45.0));
  scene.AddCamera(FixedCameraSpec(width, height), FixedCameraPose());
  scene.AddCamera(WristCameraSpec("left_wrist", width, height),
                  CameraLookAt(Vec3(0.22, 0.25, 1.32), Vec3(0.45, 0.08, 1.0)));
  scene.AddCamera(WristCameraSpec("right_wrist", width, height),
                  CameraLookAt(Vec3(0.22, -0.25, 1.32), Vec3(0.45, -0.08, 1.0)));
  return scene;
}

PixelBlob FindObject(const ImageBatch& images, int env, int camera, int32_t object_id) {
  const int32_t* ids = images.object_id(env, camera);
  PixelBlob blob;
  double sum_u = 0.0;
  double sum_v = 0.0;
  for (int row = 0; row < images.height(camera); ++row) {
    for (int column = 0; column < images.width(camera); ++column) {
      if (ids[row * images.width(camera) + column] != object_id) continue;
      ++blob.count;
      sum_u += column + 0.5;
      sum_v += row + 0.5;
    }
  }
  if (blob.count > 0) {
    blob.u = sum_u / static_cast<double>(blob.count);
    blob.v = sum_v / static_cast<double>(blob.count);
  }
  return blob;
}

int Brightness(const ImageBatch& images, int env, int camera, double u, double v) {
  const int column = static_cast<int>(std::floor(u));
  const int row = static_cast<int>(std::floor(v));
  const uint8_t* pixel = images.rgb(env, camera) + 3 * (row * images.width(camera) + column);
  return pixel[0] + pixel[1] + pixel[2];
}

bool AllZero(const ImageBatch& images, int env, int camera) {
  const uint8_t* rgb = images.rgb(env, camera);
  const int64_t bytes = 3LL * images.width(camera) * images.height(camera);
  for (int64_t i = 0; i < bytes; ++i) {
    if (rgb[i] != 0) return false;
  }
  return true;
}

EnvImages RenderEnvZero(const TestScene& scene, const RenderInputs& inputs) {
  RenderOptions options;
  options.with_object_id = true;
  BatchRenderer renderer(scene.layout, scene.num_envs, options);
  ImageBatch images = renderer.MakeImageBatch();
  renderer.Validate(inputs);
  renderer.Render(inputs, &images);
  EnvImages out;
  for (int c = 0; c < images.n_cameras(); ++c) {
    const std::size_t pixels = static_cast<std::size_t>(images.width(c)) * images.height(c);
    out.rgb.emplace_back(images.rgb(0, c), images.rgb(0, c) + 3 * pixels);
    out.ids.emplace_back(images.object_id(0, c), images.object_id(0, c) + pixels);
  }
  return out;
}

namespace {

RigidTransform RandomPose(std::mt19937* rng, const Vec3& low, const Vec3& high) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Vec3 p(low.x() + unit(*rng) * (high.x() - low.x()), low.y() + unit(*rng) * (high.y() - low.y()),
               low.z() + unit(*rng) * (high.z() - low.z()));
  const Quat q = Quat(unit(*rng) - 0.5, unit(*rng) - 0.5, unit(*rng) - 0.5, unit(*rng) - 0.5).normalized();
  return MakeTransform(p, q.toRotationMatrix());
}

}  // namespace

TestScene RandomClusterOverTable(std::mt19937* rng) {
  std::uniform_real_distribution<double> size(0.02, 0.12);
  TestScene scene;
  scene.Add(MakePlane(), PaletteAppearance("floor"), kBackgroundObjectId, RigidTransform::Identity());
  scene.Add(MakeBox(Vec3(0.9, 1.2, 0.04)), PaletteAppearance("table"), kBackgroundObjectId,
            MakeTransform(Vec3(0.6, 0.0, 0.98), Mat3::Identity()));
  const char* looks[] = {"robot_link", "gripper", "soup_can", "pudding_box", "red_cube", "gelatin_box", "wood"};
  for (int i = 0; i < 14; ++i) {
    const RigidTransform X = RandomPose(rng, Vec3(0.35, -0.25, 1.0), Vec3(0.85, 0.25, 1.35));
    const double s = size(*rng);
    const ShapeGeometry shapes[] = {MakeBox(Vec3(s, 0.5 * s + 0.01, 1.5 * s)), MakeSphere(0.5 * s),
                                    MakeCapsule(0.3 * s, 2.0 * s), MakeCylinder(0.4 * s, 1.2 * s)};
    const Appearance& look = PaletteAppearance(i == 5 ? "signal_light" : looks[i % 7]);
    scene.Add(shapes[i % 4], look, i, X);
  }
  return scene;
}

std::string GoldenDirectory() { return std::string(TAVIS_TEST_DATA_DIR) + "/golden"; }

}  // namespace tavis::render::testing
