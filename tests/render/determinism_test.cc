// Images do not depend on the number of threads.
#include <gtest/gtest.h>

#include <cstring>

#include <tbb/global_control.h>

#include "tests/render/test_scenes.h"

namespace tavis::render {
namespace {

constexpr int kEnvs = 3;

// The golden scene in three envs whose objects and head cameras differ slightly.
testing::TestScene VariedScene() {
  testing::TestScene scene = testing::GoldenScene(200, 150);
  const std::size_t n_instances = scene.layout.instances.size();
  scene.Replicate(kEnvs);
  for (int env = 1; env < kEnvs; ++env) {
    for (std::size_t i = 0; i < n_instances; ++i) {
      if (scene.layout.instances[i].object_id == kBackgroundObjectId) continue;
      scene.X_WI[env * n_instances + i].pretranslate(Vec3(0.02 * env, -0.015 * env, 0.0));
    }
    scene.X_WC[env * 4] = testing::PitchedHeadCameraPose(40.0 + 3.0 * env);
  }
  return scene;
}

ImageBatch RenderWithThreads(int threads) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  testing::TestScene scene = VariedScene();
  RenderOptions options;
  options.with_depth = true;
  options.with_object_id = true;
  BatchRenderer renderer(scene.layout, kEnvs, options);
  ImageBatch images = renderer.MakeImageBatch();
  renderer.Render(scene.Inputs(), &images);
  return images;
}

TEST(DeterminismTest, OneAndTwoThreadsGiveIdenticalImages) {
  const ImageBatch one = RenderWithThreads(1);
  const ImageBatch two = RenderWithThreads(2);
  for (int env = 0; env < kEnvs; ++env) {
    for (int camera = 0; camera < one.n_cameras(); ++camera) {
      const std::size_t pixels = static_cast<std::size_t>(one.width(camera)) * one.height(camera);
      EXPECT_EQ(std::memcmp(one.rgb(env, camera), two.rgb(env, camera), 3 * pixels), 0) << env << "/" << camera;
      EXPECT_EQ(std::memcmp(one.depth(env, camera), two.depth(env, camera), pixels * sizeof(float)), 0);
      EXPECT_EQ(std::memcmp(one.object_id(env, camera), two.object_id(env, camera), pixels * sizeof(int32_t)), 0);
    }
  }
  // The envs really differ, so the comparison covers per-env poses.
  EXPECT_NE(std::memcmp(one.rgb(0, 0), one.rgb(1, 0), 3 * 200 * 150), 0);
}

}  // namespace
}  // namespace tavis::render
