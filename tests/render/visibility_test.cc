// What appears in an image: frustum and far-plane clipping, hidden instances, occlusion,
// blocked cameras, and cast shadows.
#include <gtest/gtest.h>

#include "render/palette.h"
#include "tests/render/test_scenes.h"

namespace tavis::render {
namespace {

using testing::FindObject;
using testing::TestScene;

RigidTransform At(const Vec3& p) { return MakeTransform(p, Mat3::Identity()); }

RenderOptions IdsAndDepth() {
  RenderOptions options;
  options.with_object_id = true;
  options.with_depth = true;
  return options;
}

// Wrist camera at the origin looking along +x; spheres of object ids 0.. placed by the caller.
TestScene WristViewOf(const std::vector<Vec3>& sphere_centres) {
  TestScene scene;
  for (std::size_t i = 0; i < sphere_centres.size(); ++i) {
    scene.Add(MakeSphere(0.03), PaletteAppearance("soup_can"), static_cast<int32_t>(i), At(sphere_centres[i]));
  }
  scene.AddCamera(WristCameraSpec("wrist", 320, 240), RigidTransform::Identity());
  return scene;
}

TEST(VisibilityTest, ObjectsOutsideTheFrustumOrBeyondTheFarPlaneDoNotAppear) {
  TestScene scene = WristViewOf({
      Vec3(0.8, 0.0, 0.0),   // 0: in view, inside the 1 m far plane
      Vec3(1.3, 0.1, 0.0),   // 1: in the field of view, beyond the far plane
      Vec3(0.5, 0.5, 0.0),   // 2: 45 deg to the side, outside the 26.5 deg half field of view
      Vec3(-0.5, 0.0, 0.0),  // 3: behind the camera
      Vec3(0.05, 0.0, 0.0),  // 4: nearer than the 0.10 m near plane (the sphere spans 0.02-0.08)
  });
  BatchRenderer renderer(scene.layout, 1, IdsAndDepth());
  ImageBatch images = renderer.MakeImageBatch();
  renderer.Render(scene.Inputs(), &images);
  EXPECT_GT(FindObject(images, 0, 0, 0).count, 100);
  for (int32_t id = 1; id <= 4; ++id) EXPECT_EQ(FindObject(images, 0, 0, id).count, 0) << "object " << id;
  // Depth is along the optical axis: the front of sphere 0 at the image centre is 0.77 m away.
  const float* depth = images.depth(0, 0);
  ASSERT_NE(depth, nullptr);
  EXPECT_NEAR(depth[120 * 320 + 160], 0.77f, 2e-3f);
  EXPECT_EQ(depth[0], 0.0f);
}

TEST(VisibilityTest, HiddenInstancesAreNotDrawn) {
  TestScene scene = WristViewOf({Vec3(0.6, 0.0, 0.0)});
  BatchRenderer renderer(scene.layout, 1, IdsAndDepth());
  ImageBatch images = renderer.MakeImageBatch();
  scene.instance_visible[0] = 0;
  renderer.Render(scene.Inputs(), &images);
  EXPECT_EQ(FindObject(images, 0, 0, 0).count, 0);
  scene.instance_visible[0] = 1;
  renderer.Render(scene.Inputs(), &images);
  EXPECT_GT(FindObject(images, 0, 0, 0).count, 100);
}

TEST(VisibilityTest, NearerBoxOccludesTheOneBehind) {
  TestScene scene;
  scene.Add(MakeBox(Vec3(0.05, 0.3, 0.3)), PaletteAppearance("meat_can"), 0, At(Vec3(0.9, 0.0, 0.0)));
  scene.Add(MakeBox(Vec3(0.05, 0.1, 0.1)), PaletteAppearance("gelatin_box"), 1, At(Vec3(0.5, 0.0, 0.0)));
  scene.AddCamera(WristCameraSpec("wrist", 320, 240), RigidTransform::Identity());
  BatchRenderer renderer(scene.layout, 1, IdsAndDepth());
  ImageBatch images = renderer.MakeImageBatch();
  renderer.Render(scene.Inputs(), &images);
  const int32_t* ids = images.object_id(0, 0);
  EXPECT_EQ(ids[120 * 320 + 160], 1);  // centre: the front box
  EXPECT_EQ(ids[120 * 320 + 115], 0);  // beside the front box (34 px half-width): the back box (55 px)
  EXPECT_NEAR(images.depth(0, 0)[120 * 320 + 160], 0.475f, 1e-3f);
  EXPECT_GT(FindObject(images, 0, 0, 0).count, FindObject(images, 0, 0, 1).count);
}

TEST(VisibilityTest, BlockedCameraGivesAnAllZeroImageAndTracesNoRays) {
  TestScene scene = testing::GoldenScene(160, 120);
  scene.Replicate(2);
  BatchRenderer renderer(scene.layout, 2, IdsAndDepth());
  ImageBatch images = renderer.MakeImageBatch();
  renderer.Render(scene.Inputs(), &images);  // fill every image first
  ASSERT_FALSE(testing::AllZero(images, 1, 0));
  scene.camera_enabled[4 + 0] = 0;  // env 1's head camera
  const RenderStats stats = renderer.Render(scene.Inputs(), &images);
  EXPECT_TRUE(testing::AllZero(images, 1, 0));
  EXPECT_EQ(FindObject(images, 1, 0, kBackgroundObjectId).count, 160 * 120);
  const float* depth = images.depth(1, 0);
  ASSERT_NE(depth, nullptr);
  EXPECT_EQ(depth[60 * 160 + 80], 0.0f);
  for (int camera = 1; camera < 4; ++camera) EXPECT_FALSE(testing::AllZero(images, 1, camera)) << camera;
  EXPECT_FALSE(testing::AllZero(images, 0, 0));
  EXPECT_EQ(stats.primary_rays, 7 * 160 * 120);
}

TEST(VisibilityTest, CamerasNotRequestedThisTickAreLeftUntouched) {
  TestScene scene = testing::GoldenScene(160, 120);
  BatchRenderer renderer(scene.layout, 1);
  ImageBatch images = renderer.MakeImageBatch();
  RenderInputs inputs = scene.Inputs();
  const std::vector<uint8_t> only_head = {1, 0, 0, 0};
  inputs.render_camera = only_head;
  const RenderStats stats = renderer.Render(inputs, &images);
  EXPECT_EQ(stats.primary_rays, 160 * 120);
  EXPECT_FALSE(testing::AllZero(images, 0, 0));
  for (int camera = 1; camera < 4; ++camera) EXPECT_TRUE(testing::AllZero(images, 0, camera)) << camera;
}

TEST(VisibilityTest, BoxCastsAShadowOnTheTable) {
  // A 10 cm box on the table; the light travels along (-0.342, -0.321, -0.883), so its shadow
  // falls on the -x, -y side. (0.43, -0.07) is in the shadow, outside the box's footprint.
  auto render_table = [](bool shadows) {
    TestScene scene;
    scene.layout.lighting.shadows = shadows;
    scene.Add(MakeBox(Vec3(0.9, 1.2, 0.04)), PaletteAppearance("table"), kBackgroundObjectId,
              At(Vec3(0.6, -0.1, 0.98)));
    scene.Add(MakeBox(Vec3::Constant(0.1)), PaletteAppearance("red_cube"), 0, At(Vec3(0.5, 0.0, 1.05)));
    scene.AddCamera(FixedCameraSpec(), FixedCameraPose());
    BatchRenderer renderer(scene.layout, 1);
    ImageBatch images = renderer.MakeImageBatch();
    renderer.Render(scene.Inputs(), &images);
    const PixelProjection shadowed = ProjectWorldPoint(FixedCameraSpec(), FixedCameraPose(), Vec3(0.43, -0.07, 1.0));
    const PixelProjection lit = ProjectWorldPoint(FixedCameraSpec(), FixedCameraPose(), Vec3(0.62, 0.1, 1.0));
    return std::make_pair(testing::Brightness(images, 0, 0, shadowed.u, shadowed.v),
                          testing::Brightness(images, 0, 0, lit.u, lit.v));
  };
  const auto [shadowed, lit] = render_table(true);
  EXPECT_LT(shadowed, lit * 0.8) << "shadowed " << shadowed << ", lit " << lit;
  const auto [unshadowed, lit_again] = render_table(false);
  EXPECT_EQ(unshadowed, lit_again);  // with shadows off the table is uniformly lit
}

}  // namespace
}  // namespace tavis::render
