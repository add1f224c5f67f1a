#include "kinematics/gripper_geometry.h"

#include <gtest/gtest.h>

#include <string>

#include "tests/kinematics/robot_fixture.h"

namespace tavis::kinematics {
namespace {

constexpr double kTolerance = 1e-12;  // m

class GripperGeometryTest : public ::testing::TestWithParam<std::string> {
 protected:
  GripperGeometryTest() : robot_(::tavis::testing::LoadRobot(GetParam())), geometry_(robot_.gripper) {}

  const GripperSpec& spec() const { return robot_.gripper; }
  // Distance between the pads' inner faces along the closing axis at a commanded gap.
  double InnerFaceDistance(double gap) const {
    const Vec3 between = geometry_.PadCentre(kJawSigns[0], gap) - geometry_.PadCentre(kJawSigns[1], gap);
    return between.dot(spec().closing_axis) - geometry_.pad_thickness();
  }

  RobotModel robot_;
  GripperGeometry geometry_;
};

TEST_P(GripperGeometryTest, PadsAreTheGapApartAlongTheClosingAxis) {
  EXPECT_NEAR(InnerFaceDistance(spec().open_gap), spec().open_gap, kTolerance);
  EXPECT_NEAR(InnerFaceDistance(spec().closed_gap), spec().closed_gap, kTolerance);
}

TEST_P(GripperGeometryTest, PadsSitSymmetricAboutThePadCentre) {
  const double gap = spec().open_gap;
  const Vec3 midpoint = 0.5 * (geometry_.PadCentre(kJawSigns[0], gap) + geometry_.PadCentre(kJawSigns[1], gap));
  EXPECT_NEAR((midpoint - spec().pad_center).norm(), 0.0, kTolerance);
  const Vec3 offset = geometry_.PadCentre(kJawSigns[0], gap) - spec().pad_center;
  EXPECT_NEAR(offset.cross(spec().closing_axis).norm(), 0.0, kTolerance) << "jaws move along the closing axis only";
  EXPECT_TRUE(geometry_.X_IkPad(kJawSigns[1], gap).translation().isApprox(geometry_.PadCentre(kJawSigns[1], gap)));
  EXPECT_TRUE(geometry_.X_IkPad(kJawSigns[1], gap).linear().isIdentity());
}

TEST_P(GripperGeometryTest, PadThicknessIsThePadSizeAlongTheClosingAxis) {
  EXPECT_GT(geometry_.pad_thickness(), 0.0);
  EXPECT_NEAR(geometry_.pad_thickness(), spec().pad_size.cwiseProduct(spec().closing_axis).cwiseAbs().sum(),
              kTolerance);
}

TEST_P(GripperGeometryTest, EachFingerTravelsHalfTheGapChange) {
  const double travel = geometry_.finger_travel();
  EXPECT_GT(travel, 0.0);
  EXPECT_NEAR(geometry_.GapFromClosing(0.0, 0.0), spec().open_gap, kTolerance);
  EXPECT_NEAR(geometry_.GapFromClosing(travel, travel), spec().closed_gap, kTolerance);
  EXPECT_NEAR(InnerFaceDistance(spec().open_gap) - InnerFaceDistance(spec().closed_gap), 2.0 * travel, kTolerance);
}

TEST_P(GripperGeometryTest, CommandsMapOntoTheFingerStrokeClamped) {
  const double travel = geometry_.finger_travel();
  EXPECT_EQ(geometry_.ClosingTarget(-1.0), 0.0);
  EXPECT_DOUBLE_EQ(geometry_.ClosingTarget(0.0), 0.5 * travel);
  EXPECT_DOUBLE_EQ(geometry_.ClosingTarget(1.0), travel);
  EXPECT_EQ(geometry_.ClosingTarget(-3.0), 0.0);
  EXPECT_DOUBLE_EQ(geometry_.ClosingTarget(3.0), travel);
}

TEST_P(GripperGeometryTest, VisualFingerSpansFromTheHousingBottomToThePadCentre) {
  const Vec3 housing_centre = geometry_.X_IkHousing().translation();
  EXPECT_NEAR(geometry_.housing_bottom(), housing_centre.z() - 0.5 * spec().housing_size.z(), kTolerance);
  ASSERT_GT(geometry_.visual_finger_length(), 0.0) << "the pads hang below the housing on both robots";
  const Vec3 centre = geometry_.visual_finger_centre();
  const double half_length = 0.5 * geometry_.visual_finger_size().z();
  EXPECT_NEAR(centre.z() + half_length, geometry_.housing_bottom(), kTolerance);
  EXPECT_NEAR(centre.z() - half_length, spec().pad_center.z(), kTolerance);
  EXPECT_NEAR(centre.x(), spec().pad_center.x(), kTolerance);
  EXPECT_NEAR(centre.y(), spec().pad_center.y(), kTolerance);
  // The finger has its pad's cross-section, so at any gap it moves flush with its pad.
  EXPECT_EQ(geometry_.visual_finger_size().head<2>(), spec().pad_size.head<2>());
}

INSTANTIATE_TEST_SUITE_P(Robots, GripperGeometryTest, ::testing::Values("gr1t2", "reachy2"));

}  // namespace
}  // namespace tavis::kinematics
