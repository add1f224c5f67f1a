// Capsules and spheres shaded as packet lanes (tile_tracer.cc's ShadeRoundPacket): the lane
// functions (smooth normals, rotation to the world, irradiance) are the same floats as the
// one-point functions of the per-pixel path, and rendered, an unlabelled capsule and sphere are
// the same bytes as when a label sends them down the per-pixel path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "render/internal/env_scenes.h"
#include "render/internal/lighting_model.h"
#include "render/internal/surface_shading.h"
#include "tests/render/test_scenes.h"

namespace tavis::render {
namespace {

constexpr int K = 16;

internal::SurfaceModel RoundSurface(ShapeKind kind, float radius, float half_length) {
  internal::SurfaceModel surface;
  surface.kind = kind;
  surface.capsule_half_length = half_length;
  surface.half_extents = Eigen::Vector3f(radius, radius, half_length + radius);
  return surface;
}

TEST(RoundShadingLanes, NormalsRotationsAndIrradianceAreTheSameFloatsAsOnePointAtATime) {
  const std::vector<internal::SurfaceModel> surfaces = {RoundSurface(ShapeKind::kCapsule, 0.04f, 0.11f),
                                                        RoundSurface(ShapeKind::kCapsule, 0.3f, 0.0f),
                                                        RoundSurface(ShapeKind::kSphere, 0.07f, 0.0f)};
  // A turned, moved instance frame (column-major [R | t]): rotations about x and z.
  const Eigen::Matrix3f R =
      (Eigen::AngleAxisf(0.7f, Eigen::Vector3f::UnitZ()) * Eigen::AngleAxisf(-1.1f, Eigen::Vector3f::UnitX()))
          .toRotationMatrix();
  internal::InstanceFrame frame{};
  for (int i = 0; i < 9; ++i) frame.xfm[i] = R(i % 3, i / 3);
  frame.xfm[9] = 0.4f;
  frame.xfm[10] = -0.1f;
  frame.xfm[11] = 1.05f;
  LightingSpec spec;
  spec.ground_bounce = 0.3f;
  const internal::LightingModel lighting(spec);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  int checked = 0;
  for (const internal::SurfaceModel& surface : surfaces) {
    for (int round = 0; round < 50; ++round) {
      float p[3][K];
      for (int k = 0; k < K; ++k) {
        // Points around the shape, past its ends, and (lane 0) on its axis, where the normal is up.
        const float scale = surface.half_extents.z() * 1.5f;
        p[0][k] = k == 0 ? 0.0f : scale * unit(rng);
        p[1][k] = k == 0 ? 0.0f : scale * unit(rng);
        p[2][k] = k == 0 ? 0.5f * surface.capsule_half_length : scale * unit(rng);
      }
      float n_local[3][K], n_world[3][K], cosine[K], irradiance[3][K];
      internal::RoundNormalLanes<K>(surface, p, n_local);
      frame.RotateToWorldLanes<K>(n_local, n_world);
      for (int k = 0; k < K; ++k) cosine[k] = 0.1f * static_cast<float>(k % 7);
      lighting.IrradianceLanes<K>(n_world[2], cosine, irradiance);
      for (int k = 0; k < K; ++k) {
        SCOPED_TRACE(::testing::Message()
                     << "kind " << static_cast<int>(surface.kind) << " round " << round << " lane " << k);
        const Eigen::Vector3f one_local = internal::LocalNormal(surface, Eigen::Vector3f(p[0][k], p[1][k], p[2][k]), 0);
        ASSERT_EQ(one_local, Eigen::Vector3f(n_local[0][k], n_local[1][k], n_local[2][k]));
        const Eigen::Vector3f one_world = frame.RotateToWorld(one_local);
        ASSERT_EQ(one_world, Eigen::Vector3f(n_world[0][k], n_world[1][k], n_world[2][k]));
        ASSERT_EQ(lighting.Irradiance(one_world, cosine[k]),
                  Eigen::Vector3f(irradiance[0][k], irradiance[1][k], irradiance[2][k]));
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 3 * 50 * K);
  // Lane 0 lies on the axis: its normal is the up vector, as LocalNormal's.
  float on_axis[3][K] = {};
  float n[3][K];
  internal::RoundNormalLanes<K>(surfaces[2], on_axis, n);
  EXPECT_EQ(Eigen::Vector3f(n[0][0], n[1][0], n[2][0]), Eigen::Vector3f::UnitZ());
}

// A capsule lying across the view and a sphere, both large enough to fill whole packets, seen by
// a camera from above and one from below the floor's level (inside the sphere: the normal turns
// towards the camera). Object ids 1 and 2.
testing::TestScene RoundScene() {
  testing::TestScene scene;
  Appearance look;
  look.rgb = Eigen::Vector3f(0.2f, 0.6f, 0.3f);
  scene.Add(MakePlane(), look, kBackgroundObjectId, RigidTransform::Identity());
  const Mat3 lying = Eigen::AngleAxisd(1.3, Vec3::UnitY()).toRotationMatrix();
  scene.Add(MakeCapsule(0.12, 0.5), look, 1, MakeTransform(Vec3(0.5, 0.0, 0.9), lying));
  Appearance other = look;
  other.rgb = Eigen::Vector3f(0.7f, 0.5f, 0.1f);
  scene.Add(MakeSphere(0.2), other, 2, MakeTransform(Vec3(0.55, 0.35, 1.0), Mat3::Identity()));
  scene.AddCamera(HeadCameraSpec(96, 72), CameraLookAt(Vec3(0.0, 0.1, 1.5), Vec3(0.5, 0.1, 0.95)));
  scene.AddCamera(FixedCameraSpec(64, 48), CameraLookAt(Vec3(0.55, 0.35, 1.0), Vec3(0.9, 0.2, 1.3)));
  return scene;
}

using Rendered = testing::EnvImages;

Rendered RenderScene(const testing::TestScene& scene) { return testing::RenderEnvZero(scene, scene.Inputs()); }

// A caps label (no green) recolours only where the normal is within 45 degrees of the axis and
// sends the whole shape down the per-pixel path; every other pixel of it must be the same bytes.
TEST(RoundShadingRender, AnUnlabelledCapsuleAndSphereAreTheSameBytesAsThePerPixelPathDrawsThem) {
  const testing::TestScene scene = RoundScene();
  const Rendered lanes = RenderScene(scene);
  testing::TestScene labelled = scene;
  for (std::size_t i : {std::size_t{1}, std::size_t{2}}) {
    labelled.layout.instances[i].appearance.label = LabelPattern::kCaps;
    labelled.layout.instances[i].appearance.label_rgb = Eigen::Vector3f(1.0f, 0.0f, 1.0f);
  }
  const Rendered per_pixel = RenderScene(labelled);
  ASSERT_EQ(per_pixel.ids, lanes.ids);
  for (std::size_t c = 0; c < lanes.rgb.size(); ++c) {
    SCOPED_TRACE(scene.layout.cameras[c].name);
    int same[3] = {}, other = 0;
    for (std::size_t p = 0; p < lanes.ids[c].size(); ++p) {
      const int32_t id = lanes.ids[c][p];
      if (id != 1 && id != 2) continue;
      if (std::memcmp(&lanes.rgb[c][3 * p], &per_pixel.rgb[c][3 * p], 3) == 0) {
        ++same[id];
      } else if (per_pixel.rgb[c][3 * p + 1] != 0) {
        ++other;  // not the label's colour: a pixel the two paths shade differently
      }
    }
    EXPECT_EQ(other, 0);
    if (c == 0) {
      EXPECT_GT(same[1], 400) << "the capsule's side";
      EXPECT_GT(same[2], 400) << "the sphere's side";
    } else {
      EXPECT_GT(same[2], 1000) << "the sphere seen from inside";
    }
  }
}

}  // namespace
}  // namespace tavis::render
