// Images do not depend on the number of threads, nor on whether envs are drawn all at once
// (Render) or one at a time (RenderEnv, whose tiles idle threads take).
#include <gtest/gtest.h>

#include <cstring>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

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

struct Rendered {
  ImageBatch images;
  RenderStats stats;
};

// `per_env`: each env by RenderEnv, one after the other from this thread, as a per-slot worker
// draws its env while the other threads have nothing to do.
Rendered RenderWithThreads(int threads, bool per_env = false) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  testing::TestScene scene = VariedScene();
  RenderOptions options;
  options.with_depth = true;
  options.with_object_id = true;
  BatchRenderer renderer(scene.layout, kEnvs, options);
  Rendered out{renderer.MakeImageBatch(), RenderStats{}};
  const RenderInputs inputs = scene.Inputs();
  if (!per_env) {
    out.stats = renderer.Render(inputs, &out.images);
    return out;
  }
  tbb::task_arena arena(threads);
  arena.execute([&] {
    for (int env = 0; env < kEnvs; ++env) {
      const RenderStats stats = renderer.RenderEnv(env, inputs, &out.images);
      out.stats.primary_rays += stats.primary_rays;
      out.stats.shadow_rays += stats.shadow_rays;
      out.stats.primary_hits += stats.primary_hits;
      out.stats.sky_tiles += stats.sky_tiles;
    }
  });
  return out;
}

void ExpectSameImages(const ImageBatch& one, const ImageBatch& two) {
  for (int env = 0; env < kEnvs; ++env) {
    for (int camera = 0; camera < one.n_cameras(); ++camera) {
      const std::size_t pixels = static_cast<std::size_t>(one.width(camera)) * one.height(camera);
      EXPECT_EQ(std::memcmp(one.rgb(env, camera), two.rgb(env, camera), 3 * pixels), 0) << env << "/" << camera;
      EXPECT_EQ(std::memcmp(one.depth(env, camera), two.depth(env, camera), pixels * sizeof(float)), 0);
      EXPECT_EQ(std::memcmp(one.object_id(env, camera), two.object_id(env, camera), pixels * sizeof(int32_t)), 0);
    }
  }
}

TEST(DeterminismTest, OneAndTwoThreadsGiveIdenticalImages) {
  const Rendered one = RenderWithThreads(1);
  const Rendered two = RenderWithThreads(2);
  ExpectSameImages(one.images, two.images);
  // The envs really differ, so the comparison covers per-env poses.
  EXPECT_NE(std::memcmp(one.images.rgb(0, 0), one.images.rgb(1, 0), 3 * 200 * 150), 0);
}

TEST(DeterminismTest, RenderEnvOnFourThreadsGivesTheImagesAndCountsOfRenderOnOne) {
  const Rendered all = RenderWithThreads(1);
  const Rendered each = RenderWithThreads(4, true);
  ExpectSameImages(all.images, each.images);
  EXPECT_EQ(all.stats.primary_rays, each.stats.primary_rays);
  EXPECT_EQ(all.stats.shadow_rays, each.stats.shadow_rays);
  EXPECT_EQ(all.stats.primary_hits, each.stats.primary_hits);
  EXPECT_EQ(all.stats.sky_tiles, each.stats.sky_tiles);
  EXPECT_GT(each.stats.primary_hits, 0);
}

}  // namespace
}  // namespace tavis::render
