// Tiles written as sky without tracing (render/internal/instance_bounds.h) must be exactly what
// tracing every primary ray draws: random clusters of every shape kind over a table
// (RandomClusterOverTable), seen by cameras that look over them into the sky, from below the
// floor, along the floor's horizon, and by a wrist-like camera (clipped at 0.1-1 m) with boxes and
// a capsule right next to it.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "render/palette.h"
#include "tests/render/test_scenes.h"

namespace tavis::render {
namespace {

constexpr int kWidth = 96;
constexpr int kHeight = 72;

testing::TestScene SkyScene(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  testing::TestScene scene = testing::RandomClusterOverTable(&rng);
  // A "hand" right next to the wrist camera: a box behind it, a capsule beside it, and a box
  // that straddles its near clipping depth (0.1 m) above the middle of its view.
  const Vec3 wrist(0.1 + 0.1 * unit(rng), 0.4, 1.3);
  const double lift = 0.4 * unit(rng);
  const Vec3 wrist_target(0.6, 0.1, 1.4 + lift);
  const Vec3 forward = (wrist_target - wrist).normalized();
  scene.Add(MakeBox(Vec3(0.06, 0.05, 0.04)), PaletteAppearance("gripper"), kBackgroundObjectId,
            MakeTransform(wrist - 0.05 * forward, Mat3::Identity()));
  scene.Add(MakeCapsule(0.04, 0.19), PaletteAppearance("robot_link"), kBackgroundObjectId,
            MakeTransform(wrist + Vec3(-0.05, 0.05, -0.12), Mat3::Identity()));
  scene.Add(MakeBox(Vec3(0.03, 0.03, 0.03)), PaletteAppearance("gripper"), kBackgroundObjectId,
            MakeTransform(wrist + 0.09 * forward + Vec3(0.0, 0.0, 0.02), Mat3::Identity()));
  scene.AddCamera(HeadCameraSpec(kWidth, kHeight), CameraLookAt(Vec3(0.0, 0.3, 1.6), Vec3(0.8, 0.0, 1.3 + lift)));
  scene.AddCamera(WristCameraSpec("wrist", kWidth, kHeight), CameraLookAt(wrist, wrist_target));
  scene.AddCamera(FixedCameraSpec(kWidth, kHeight), CameraLookAt(Vec3(1.5, -0.5, -0.5), Vec3(1.0, 0.0, -2.0)));
  scene.AddCamera(WristCameraSpec("horizon", kWidth, kHeight), CameraLookAt(Vec3(-1.0, 0.2, 0.3), Vec3(3.0, 0.0, 0.3)));
  return scene;
}

struct Traced {
  RenderStats stats;
  std::vector<uint8_t> rgb;
  std::vector<float> depth;
  std::vector<int32_t> ids;
};

Traced Render(const testing::TestScene& scene, bool trace_every_primary_ray) {
  RenderOptions options;
  options.with_depth = true;
  options.with_object_id = true;
  options.trace_every_primary_ray = trace_every_primary_ray;
  BatchRenderer renderer(scene.layout, scene.num_envs, options);
  ImageBatch images = renderer.MakeImageBatch();
  Traced out;
  out.stats = renderer.Render(scene.Inputs(), &images);
  for (int c = 0; c < images.n_cameras(); ++c) {
    const std::size_t pixels = static_cast<std::size_t>(images.width(c)) * images.height(c);
    out.rgb.insert(out.rgb.end(), images.rgb(0, c), images.rgb(0, c) + 3 * pixels);
    out.depth.insert(out.depth.end(), images.depth(0, c), images.depth(0, c) + pixels);
    out.ids.insert(out.ids.end(), images.object_id(0, c), images.object_id(0, c) + pixels);
  }
  return out;
}

TEST(SkyTiles, AreTheBytesOfTracingEveryPrimaryRay) {
  int64_t sky_tiles = 0;
  for (unsigned seed = 1; seed <= 6; ++seed) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    const testing::TestScene scene = SkyScene(seed);
    const Traced skipped = Render(scene, false);
    const Traced traced = Render(scene, true);
    EXPECT_EQ(skipped.rgb, traced.rgb);
    EXPECT_EQ(skipped.depth, traced.depth);
    EXPECT_EQ(skipped.ids, traced.ids);
    EXPECT_EQ(skipped.stats.primary_rays, traced.stats.primary_rays);
    EXPECT_EQ(skipped.stats.primary_hits, traced.stats.primary_hits);
    EXPECT_EQ(traced.stats.sky_tiles, 0);
    sky_tiles += skipped.stats.sky_tiles;
  }
  // 4 cameras of 6 x 5 tiles in 6 scenes: the camera below the floor sees only sky, the others some.
  EXPECT_GT(sky_tiles, 6 * 30 + 40);
}

}  // namespace
}  // namespace tavis::render
