// Intrinsics, mounts and projection: the helper against hand-computed pixels, and the renderer's
// object-id buffer against the helper.
#include <gtest/gtest.h>

#include <cmath>

#include "render/camera.h"
#include "render/palette.h"
#include "tests/render/test_scenes.h"

namespace tavis::render {
namespace {

using testing::FindObject;
using testing::PixelBlob;
using testing::TestScene;

TEST(CameraTest, IntrinsicsMatchTheReference) {
  EXPECT_NEAR(IntrinsicsOf(HeadCameraSpec()).fx, 458.125, 1e-3);
  EXPECT_NEAR(IntrinsicsOf(WristCameraSpec("wrist")).fx, 641.374, 1e-3);
  EXPECT_NEAR(IntrinsicsOf(FixedCameraSpec()).fx, 184.776, 1e-3);
  const CameraIntrinsics fixed = IntrinsicsOf(FixedCameraSpec());
  EXPECT_DOUBLE_EQ(fixed.fy, fixed.fx);
  EXPECT_DOUBLE_EQ(fixed.cx, 320.0);
  EXPECT_DOUBLE_EQ(fixed.cy, 240.0);
  const double hfov_deg = 2.0 * std::atan(0.5 * 640.0 / fixed.fx) * 180.0 / 3.14159265358979;
  EXPECT_NEAR(hfov_deg, 119.99, 0.01);
}

TEST(CameraTest, FixedCameraLooksFortyFiveDegreesDown) {
  const RigidTransform X_WC = FixedCameraPose();
  EXPECT_TRUE(X_WC.translation().isApprox(Vec3(0.2, 0.0, 1.43)));
  EXPECT_TRUE(X_WC.linear().col(0).isApprox(Vec3(std::sqrt(0.5), 0.0, -std::sqrt(0.5)), 1e-6));  // optical axis
  EXPECT_TRUE(X_WC.linear().col(2).isApprox(Vec3(std::sqrt(0.5), 0.0, std::sqrt(0.5)), 1e-6));   // image up
}

TEST(CameraTest, WristMountLooksBackAlongTheGripper) {
  // Reference §6.1: optical axis (-0.574, 0, -0.819), up (0.819, 0, -0.574) in the hand frame.
  const RigidTransform X_HC = testing::Gr1t2WristCameraPose(RigidTransform::Identity());
  EXPECT_TRUE(X_HC.translation().isApprox(Vec3(0.15, 0.0, 0.05)));
  EXPECT_NEAR(X_HC.linear()(0, 0), -0.574, 1e-3);
  EXPECT_NEAR(X_HC.linear()(2, 0), -0.819, 1e-3);
  EXPECT_NEAR(X_HC.linear()(0, 2), 0.819, 1e-3);
  EXPECT_NEAR(X_HC.linear()(2, 2), -0.574, 1e-3);
}

TEST(CameraTest, ProjectionMatchesHandComputedPixels) {
  // Fixed camera, world point (0.6, 0.1, 1.0): camera-frame (0.58690, 0.1, -0.021213).
  const PixelProjection fixed = ProjectWorldPoint(FixedCameraSpec(), FixedCameraPose(), Vec3(0.6, 0.1, 1.0));
  EXPECT_NEAR(fixed.depth, 0.586899, 1e-5);
  EXPECT_NEAR(fixed.u, 320.0 - 184.7769 * 0.1 / 0.586899, 1e-3);
  EXPECT_NEAR(fixed.v, 240.0 + 184.7769 * 0.0212132 / 0.586899, 1e-3);

  // Head camera level at the origin: a point left of and above the axis is left of and above centre.
  const double head_fx = 15.0 / 20.955 * 640.0;
  const PixelProjection head = ProjectWorldPoint(HeadCameraSpec(), RigidTransform::Identity(), Vec3(2.0, 0.1, 0.2));
  EXPECT_NEAR(head.u, 320.0 - head_fx * 0.05, 1e-9);
  EXPECT_NEAR(head.v, 240.0 - head_fx * 0.1, 1e-9);
  EXPECT_TRUE(IsVisibleInImage(HeadCameraSpec(), head));
  EXPECT_FALSE(IsVisibleInImage(HeadCameraSpec(),
                                ProjectWorldPoint(HeadCameraSpec(), RigidTransform::Identity(), Vec3(-1.0, 0.0, 0.0))));
}

TEST(CameraTest, LookAtPointsTheOpticalAxisAtTheTarget) {
  const RigidTransform X_WC = CameraLookAt(Vec3(0.2, 0.3, 1.4), Vec3(0.5, -0.1, 1.0));
  const PixelProjection p = ProjectWorldPoint(HeadCameraSpec(), X_WC, Vec3(0.5, -0.1, 1.0));
  EXPECT_NEAR(p.u, 320.0, 1e-9);
  EXPECT_NEAR(p.v, 240.0, 1e-9);
  EXPECT_GT(X_WC.linear().col(2).z(), 0.0);  // image up points up
  EXPECT_THROW(CameraLookAt(Vec3::Zero(), Vec3(0.0, 0.0, -1.0)), std::invalid_argument);
}

// The centroid of a small sphere's object-id pixels lands on the projection of its centre.
void ExpectSphereAtItsProjection(const CameraSpec& camera, const RigidTransform& X_WC, const Vec3& centre,
                                 double radius) {
  SCOPED_TRACE(camera.name);
  TestScene scene;
  scene.Add(MakeSphere(radius), PaletteAppearance("red_cube"), 0, MakeTransform(centre, Mat3::Identity()));
  scene.AddCamera(camera, X_WC);
  RenderOptions options;
  options.with_object_id = true;
  BatchRenderer renderer(scene.layout, 1, options);
  ImageBatch images = renderer.MakeImageBatch();
  renderer.Render(scene.Inputs(), &images);

  const PixelProjection expected = ProjectWorldPoint(camera, X_WC, centre);
  ASSERT_TRUE(IsVisibleInImage(camera, expected));
  const PixelBlob blob = FindObject(images, 0, 0, 0);
  ASSERT_GT(blob.count, 50);
  EXPECT_NEAR(blob.u, expected.u, 1.0);
  EXPECT_NEAR(blob.v, expected.v, 1.0);
}

TEST(CameraTest, SphereCentroidMatchesProjectionInHeadCamera) {
  ExpectSphereAtItsProjection(HeadCameraSpec(), testing::PitchedHeadCameraPose(45.0), Vec3(0.5, 0.12, 1.03), 0.02);
}

TEST(CameraTest, SphereCentroidMatchesProjectionInWristCamera) {
  // Hand above the table with its approach axis (-z) pointing down: the camera looks down and back.
  const RigidTransform X_W_hand = MakeTransform(Vec3(0.3, -0.2, 1.2), Mat3::Identity());
  const RigidTransform X_WC = testing::Gr1t2WristCameraPose(X_W_hand);
  const Vec3 on_axis = X_WC * Vec3(0.3, 0.0, 0.0);
  const Vec3 off_axis = X_WC * Vec3(0.4, 0.05, -0.03);
  ExpectSphereAtItsProjection(WristCameraSpec("left_wrist"), X_WC, on_axis, 0.01);
  ExpectSphereAtItsProjection(WristCameraSpec("left_wrist"), X_WC, off_axis, 0.01);
  const PixelProjection off = ProjectWorldPoint(WristCameraSpec("left_wrist"), X_WC, off_axis);
  EXPECT_NEAR(off.u, 320.0 - 641.374 * 0.05 / 0.4, 1e-3);
  EXPECT_NEAR(off.v, 240.0 + 641.374 * 0.03 / 0.4, 1e-3);
}

TEST(CameraTest, SphereCentroidMatchesProjectionInFixedCamera) {
  ExpectSphereAtItsProjection(FixedCameraSpec(), FixedCameraPose(), Vec3(0.6, 0.1, 1.0), 0.02);
  ExpectSphereAtItsProjection(FixedCameraSpec(), FixedCameraPose(), Vec3(0.35, -0.3, 1.05), 0.02);
}

}  // namespace
}  // namespace tavis::render
