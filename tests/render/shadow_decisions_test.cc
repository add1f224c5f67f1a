// Shadows decided without rays (render/internal/shadow_casters.h) and flat faces shaded once per
// render (render/internal/flat_shades.h) must give exactly the pixels of tracing every shadow ray
// and shading every pixel: random clusters of every shape kind, touching and interpenetrating,
// seen from random cameras, one of them inside a box.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "render/palette.h"
#include "tests/render/test_scenes.h"

namespace tavis::render {
namespace {

constexpr int kWidth = 120;
constexpr int kHeight = 90;

// Floor, table, 14 random shapes over it (boxes, spheres, capsules, cylinders; plain, labelled and
// one emissive), two cameras looking at the cluster; `inside_room` adds a closed box around it
// all and a third camera inside it.
testing::TestScene RandomCluster(unsigned seed, bool inside_room) {
  std::mt19937 rng(seed);
  testing::TestScene scene = testing::RandomClusterOverTable(&rng);
  scene.AddCamera(HeadCameraSpec(kWidth, kHeight), CameraLookAt(Vec3(0.0, 0.3, 1.6), Vec3(0.6, 0.0, 1.1)));
  scene.AddCamera(FixedCameraSpec(kWidth, kHeight), CameraLookAt(Vec3(1.2, -0.6, 1.5), Vec3(0.6, 0.0, 1.1)));
  if (inside_room) {
    scene.Add(MakeBox(Vec3(3.0, 3.0, 3.0)), PaletteAppearance("wood"), kBackgroundObjectId,
              MakeTransform(Vec3(0.6, 0.0, 1.2), Mat3::Identity()));
    scene.AddCamera(WristCameraSpec("inside", kWidth, kHeight), CameraLookAt(Vec3(0.3, 0.2, 1.3), Vec3(0.6, 0.0, 1.1)));
  }
  return scene;
}

TEST(ShadowDecisionsTest, ExactShadowTestsGiveTheImagesOfTracedShadowRays) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const testing::TestScene scene = RandomCluster(seed, seed == 3);
    RenderOptions traced_options;
    traced_options.trace_every_shadow_ray = true;
    BatchRenderer fast(scene.layout, 1);
    BatchRenderer traced(scene.layout, 1, traced_options);
    ImageBatch fast_images = fast.MakeImageBatch();
    ImageBatch traced_images = traced.MakeImageBatch();
    const RenderStats fast_stats = fast.Render(scene.Inputs(), &fast_images);
    const RenderStats traced_stats = traced.Render(scene.Inputs(), &traced_images);

    EXPECT_EQ(fast_stats.primary_hits, traced_stats.primary_hits) << "seed " << seed;
    EXPECT_GT(traced_stats.shadow_rays, 1000) << "seed " << seed;
    // Most shadow rays are decided without Embree.
    EXPECT_LT(fast_stats.shadow_rays, traced_stats.shadow_rays / 2) << "seed " << seed;
    for (int c = 0; c < fast_images.n_cameras(); ++c) {
      const uint8_t* a = fast_images.rgb(0, c);
      const uint8_t* b = traced_images.rgb(0, c);
      int differing = 0;
      for (int i = 0; i < 3 * kWidth * kHeight; ++i) differing += a[i] != b[i] ? 1 : 0;
      EXPECT_EQ(differing, 0) << "seed " << seed << " camera " << c;
    }
  }
}

TEST(ShadowDecisionsTest, PerEnvColoursReachFlatFacesAndEmissiveSurfaces) {
  // The same scene twice: colours given per env through instance_rgb, and baked into the layout.
  testing::TestScene given = RandomCluster(7, false);
  testing::TestScene baked = given;
  std::vector<Eigen::Vector3f> rgb;
  for (std::size_t i = 0; i < baked.layout.instances.size(); ++i) {
    const Eigen::Vector3f colour(0.1f + 0.05f * static_cast<float>(i % 7), 0.8f - 0.04f * static_cast<float>(i), 0.3f);
    baked.layout.instances[i].appearance.rgb = colour;
    rgb.push_back(colour);
  }
  BatchRenderer given_renderer(given.layout, 1);
  BatchRenderer baked_renderer(baked.layout, 1);
  ImageBatch given_images = given_renderer.MakeImageBatch();
  ImageBatch baked_images = baked_renderer.MakeImageBatch();
  RenderInputs inputs = given.Inputs();
  inputs.instance_rgb = rgb;
  given_renderer.Render(inputs, &given_images);
  baked_renderer.Render(baked.Inputs(), &baked_images);
  for (int c = 0; c < given_images.n_cameras(); ++c) {
    const uint8_t* a = given_images.rgb(0, c);
    const uint8_t* b = baked_images.rgb(0, c);
    EXPECT_TRUE(std::equal(a, a + 3 * kWidth * kHeight, b)) << "camera " << c;
  }
}

}  // namespace
}  // namespace tavis::render
