#include "scenarios/expert/grasp_clearance.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/robot_loading.h"

namespace tavis::scenarios::expert {
namespace {

constexpr double kMargin = 0.005;
const Vec3 kCube(0.4, 0.0, 1.0275);

// GR1T2's gripper, the target cube (object 0) and one neighbour box (object 1) of `size`.
struct Scene {
  engine::WorldModel model;
  engine::BatchState state;

  Scene(const Vec3& neighbour_position, const Vec3& neighbour_size) {
    model.robot = tavis::testing::LoadRobot("gr1t2");
    model.objects.push_back(
        {"cube", {ShapeKind::kBox, Vec3::Constant(0.055)}, 0.1, engine::Material::kObject, "red_cube"});
    model.objects.push_back(
        {"neighbour", {ShapeKind::kBox, neighbour_size}, 0.1, engine::Material::kObject, "gelatin_box"});
    state.Allocate(1, model.robot.num_joints(), 2);
    Place(0, kCube);
    Place(1, neighbour_position);
  }
  void Place(int object, const Vec3& p, const Quat& q = Quat::Identity()) {
    double* pose = state.object_pose_row(0, object);
    pose[0] = p.x();
    pose[1] = p.y();
    pose[2] = p.z();
    pose[3] = q.w();
    pose[4] = q.x();
    pose[5] = q.y();
    pose[6] = q.z();
    state.object_enabled_at(0, object) = 1;
  }
  // The hand straight above the cube (approach -Z down), pads' centre at the cube's centre,
  // turned `yaw` about the vertical (yaw 0: fingers close along world y).
  bool Clear(double yaw, HandParts parts) const {
    const Mat3 R = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
    const RigidTransform X_W_ik = MakeTransform(kCube - R * model.robot.gripper.pad_center, R);
    return OpenHandClearsNeighbours(model, state, 0, 0, X_W_ik, model.robot.gripper.open_gap, kMargin, parts);
  }
};

const Vec3 kSmallBox = Vec3::Constant(0.055);

TEST(GraspClearance, DistantNeighbourIsClear) {
  const Scene scene(kCube + Vec3(0.0, 0.2, 0.0), kSmallBox);
  EXPECT_TRUE(scene.Clear(0.0, HandParts::kPadsAndHousing));
}

TEST(GraspClearance, NeighbourBesideTheClosingFingerIsNotClearUntilTheHandTurns) {
  // The open finger's outer face is 5.05 cm from the cube's centre; the neighbour starts at 4.75.
  const Scene scene(kCube + Vec3(0.0, 0.075, 0.0), kSmallBox);
  EXPECT_FALSE(scene.Clear(0.0, HandParts::kPads));
  EXPECT_TRUE(scene.Clear(M_PI / 2, HandParts::kPadsAndHousing));
}

TEST(GraspClearance, TallNeighbourUnderThePalmOnlyCountsWithTheHousing) {
  // A post 5 cm in front of the cube, outside the pads (1.1 cm half-width) but under the 7.5 cm
  // wide housing.
  const Scene scene(kCube + Vec3(0.05, 0.0, 0.1), Vec3(0.03, 0.03, 0.3));
  EXPECT_TRUE(scene.Clear(0.0, HandParts::kPads));
  EXPECT_FALSE(scene.Clear(0.0, HandParts::kPadsAndHousing));
}

TEST(GraspClearance, DisabledNeighbourIsIgnored) {
  Scene scene(kCube + Vec3(0.0, 0.075, 0.0), kSmallBox);
  scene.state.object_enabled_at(0, 1) = 0;
  EXPECT_TRUE(scene.Clear(0.0, HandParts::kPadsAndHousing));
}

TEST(GraspClearance, HalfExtentFollowsTheObjectsYaw) {
  Scene scene(kCube + Vec3(0.0, 0.2, 0.0), kSmallBox);
  EXPECT_NEAR(HalfExtentAlong(scene.model, scene.state, 0, 0, Vec3::UnitX()), 0.0275, 1e-12);
  scene.Place(0, kCube, Quat(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ())));
  EXPECT_NEAR(HalfExtentAlong(scene.model, scene.state, 0, 0, Vec3::UnitX()), 0.0275 * std::sqrt(2.0), 1e-12);
}

}  // namespace
}  // namespace tavis::scenarios::expert
