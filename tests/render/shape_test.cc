// Shape tessellation and sharing: round shapes have round silhouettes of the right size, and
// identical shapes share one BVH.
#include <gtest/gtest.h>

#include <cmath>

#include "render/palette.h"
#include "tests/render/test_scenes.h"

namespace tavis::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

// One shape (object id 0) in front of a head camera at the origin, rendered with object ids.
ImageBatch RenderAlone(const ShapeGeometry& shape, const RigidTransform& X_WI) {
  testing::TestScene scene;
  scene.Add(shape, PaletteAppearance("robot_link"), 0, X_WI);
  scene.AddCamera(HeadCameraSpec(), RigidTransform::Identity());
  RenderOptions options;
  options.with_object_id = true;
  BatchRenderer renderer(scene.layout, 1, options);
  ImageBatch images = renderer.MakeImageBatch();
  renderer.Render(scene.Inputs(), &images);
  return images;
}

int64_t SilhouettePixels(const ShapeGeometry& shape, const RigidTransform& X_WI) {
  return testing::FindObject(RenderAlone(shape, X_WI), 0, 0, 0).count;
}

TEST(ShapeTest, SphereSilhouetteIsTheExactDisc) {
  const double fx = IntrinsicsOf(HeadCameraSpec()).fx;
  const double r = 0.05;
  const double d = 0.5;
  const double radius_px = fx * r / std::sqrt(d * d - r * r);
  const double area = kPi * radius_px * radius_px;  // about 6660 px
  const int64_t pixels = SilhouettePixels(MakeSphere(r), MakeTransform(Vec3(d, 0.0, 0.0), Mat3::Identity()));
  EXPECT_NEAR(static_cast<double>(pixels), area, 0.01 * area);
}

TEST(ShapeTest, CylinderSeenEndOnIsTheExactDisc) {
  const double fx = IntrinsicsOf(HeadCameraSpec()).fx;
  const double radius_px = fx * 0.04 / 0.45;  // the near cap, 0.45 m away
  const double area = kPi * radius_px * radius_px;
  const RigidTransform X_WI =
      MakeTransform(Vec3(0.5, 0.0, 0.0), Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitY()).toRotationMatrix());
  EXPECT_NEAR(static_cast<double>(SilhouettePixels(MakeCylinder(0.04, 0.1), X_WI)), area, 0.01 * area);
}

TEST(ShapeTest, CapsuleIsAsTallAsItsDiameterAndAsWideAsItsLength) {
  // Capsule across the view (axis along world y) 0.6 m away: centre row spans its full length.
  const RigidTransform X_WI =
      MakeTransform(Vec3(0.6, 0.0, 0.0), Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitX()).toRotationMatrix());
  const ImageBatch images = RenderAlone(MakeCapsule(0.03, 0.2), X_WI);
  const int32_t* ids = images.object_id(0, 0);
  int row_pixels = 0;
  int column_pixels = 0;
  for (int column = 0; column < 640; ++column) row_pixels += ids[240 * 640 + column] == 0 ? 1 : 0;
  for (int row = 0; row < 480; ++row) column_pixels += ids[row * 640 + 320] == 0 ? 1 : 0;
  const double fx = IntrinsicsOf(HeadCameraSpec()).fx;
  // Straight section: diameter 0.06 m at 0.57 m seen edge-on -> 2 * fx * 0.03 / sqrt(0.6^2 - 0.03^2).
  EXPECT_NEAR(column_pixels, 2.0 * fx * 0.03 / std::sqrt(0.36 - 0.0009), 1.5);
  // Full length 0.26 m: each end cap's silhouette is the sphere tangent at +-0.1 m.
  const double end_angle = std::atan2(0.1, 0.6) + std::asin(0.03 / std::hypot(0.1, 0.6));
  EXPECT_NEAR(row_pixels, 2.0 * fx * std::tan(end_angle), 1.5);
}

TEST(ShapeTest, TheMakersFollowTheEnginesSizeConvention) {
  const Shape can{ShapeKind::kCylinder, Vec3(0.03, 0.03, 0.1)};
  EXPECT_EQ(can, MakeCylinder(0.03, 0.1));
  const Shape link{ShapeKind::kCapsule, Vec3(0.04, 0.04, 0.2)};
  EXPECT_EQ(link, MakeCapsule(0.04, 0.2));
  EXPECT_FALSE(link == MakeCapsule(0.04, 0.21));
  EXPECT_TRUE(BoundingHalfSize(MakePlane()).array().isInf().all());
}

TEST(ShapeTest, IdenticalShapesShareOneBvh) {
  const testing::TestScene scene = testing::GoldenScene(32, 24);
  BatchRenderer renderer(scene.layout, 1);
  EXPECT_EQ(renderer.n_instances(), 9);
  EXPECT_EQ(renderer.n_unique_shapes(), 6);  // floor, table top, one leg shape for 4 legs, cube, can, capsule
}

}  // namespace
}  // namespace tavis::render
