#include "engine/physics_world.h"

#include <gtest/gtest.h>

#include "configs/robot_config.h"
#include "engine/batch_state.h"
#include "engine/object_catalog.h"
#include "kinematics/inverse_kinematics.h"

namespace tavis::engine {
namespace {

using kinematics::Side;

constexpr int kCube = 0;
const Vec3 kCubeOnTable(0.40, 0.20, kTableHeight + 0.0275);

WorldModel CubeOnTableWorld() {
  WorldModel model;
  model.robot = configs::LoadRobotModel(configs::RobotConfigPath(TAVIS_CONFIG_DIR, "gr1t2"));
  model.objects.push_back(MakeCatalogObject("red_cube"));
  model.static_parts.push_back(MakeTable());
  return model;
}

// Joint positions that put the left gripper's TCP at `tcp_world`, approach tilted 0.35 rad
// forward from vertical (kinematic IK iterations from the default pose).
std::vector<double> LeftArmAt(const kinematics::RobotModel& robot, const Vec3& tcp_world) {
  const Mat3 R = Eigen::AngleAxisd(-0.35, Vec3::UnitY()).toRotationMatrix();
  const kinematics::PoseTarget target{tcp_world - robot.root_world - R * robot.gripper.tcp, Quat(R)};
  std::vector<double> q = robot.DefaultPositions();
  std::vector<RigidTransform> X_BL(robot.links.size());
  for (int i = 0; i < 400; ++i) {
    kinematics::ComputeLinkPoses(robot, q.data(), X_BL.data());
    const auto next = kinematics::IkStep(robot, Side::kLeft, q.data(), X_BL.data(), target);
    for (int k = 0; k < kinematics::kArmDof; ++k) q[robot.arm(Side::kLeft).joints[k]] = next[k];
  }
  return q;
}

struct Observed {
  std::vector<double> q;
  double gap[2] = {0, 0};
  double pose[kObjectPoseSize] = {};
  double velocity[kObjectVelocitySize] = {};
};

Observed StepFor(PhysicsWorld& world, const std::vector<double>& q_target, double gripper, double seconds,
                 const WorldModel& model) {
  Observed o;
  o.q = q_target;
  const int ticks = static_cast<int>(seconds * model.physics.control_hz);
  for (int t = 0; t < ticks; ++t) {
    EXPECT_TRUE(world.Step(q_target.data(), {gripper, -1.0}, model.physics.substeps_per_control()));
  }
  world.ReadState(o.q.data(), o.gap, o.pose, o.velocity);
  return o;
}

// Grasps the cube on the table from above, closes, lifts the hand 15 cm; returns the cube height.
double CubeHeightAfterLift(double friction) {
  const WorldModel model = CubeOnTableWorld();
  PhysicsWorld world(model);
  world.SetFriction(Material::kFingerPad, friction);
  world.SetFriction(Material::kObject, friction);
  const std::vector<double> q_grasp = LeftArmAt(model.robot, kCubeOnTable + Vec3(0, 0, 0.005));
  world.ResetRobot(q_grasp.data(), 1);
  world.SetObject(kCube, kCubeOnTable, Quat::Identity(), true);
  const Observed closed = StepFor(world, q_grasp, 1.0, 0.8, model);
  EXPECT_NEAR(closed.gap[0], 0.055, 0.004) << "the fingers should stop on the cube's faces";
  const std::vector<double> q_lift = LeftArmAt(model.robot, kCubeOnTable + Vec3(0, 0, 0.15));
  return StepFor(world, q_lift, 1.0, 1.5, model).pose[2];
}

// DISABLED: these fail today (issue 2 stays open): the gripper pads and hand boxes make no
// contact with the cube or the table, so the fingers close through the cube and the hand
// passes through the table. They are the acceptance checks for the fix.
TEST(PhysicsWorld, DISABLED_FrictionGraspLiftsTheCube) {
  EXPECT_GT(CubeHeightAfterLift(1.0), kCubeOnTable.z() + 0.10);
}

// DISABLED: these fail today (issue 2 stays open): the gripper pads and hand boxes make no
// contact with the cube or the table, so the fingers close through the cube and the hand
// passes through the table. They are the acceptance checks for the fix.
TEST(PhysicsWorld, DISABLED_FrictionlessGraspLetsTheCubeSlip) {
  EXPECT_LT(CubeHeightAfterLift(0.0), kCubeOnTable.z() + 0.02);
}

// DISABLED: these fail today (issue 2 stays open): the gripper pads and hand boxes make no
// contact with the cube or the table, so the fingers close through the cube and the hand
// passes through the table. They are the acceptance checks for the fix.
TEST(PhysicsWorld, DISABLED_MotionCommandedIntoTheTableStopsAtTheTable) {
  const WorldModel model = CubeOnTableWorld();
  PhysicsWorld world(model);
  const Vec3 above(0.45, 0.15, kTableHeight + 0.10);
  const std::vector<double> q_above = LeftArmAt(model.robot, above);
  world.ResetRobot(q_above.data(), 1);
  const std::vector<double> q_through = LeftArmAt(model.robot, above - Vec3(0, 0, 0.20));
  const Observed o = StepFor(world, q_through, -1.0, 2.0, model);
  std::vector<RigidTransform> X_BL(model.robot.links.size());
  kinematics::ComputeLinkPoses(model.robot, o.q.data(), X_BL.data());
  const RigidTransform& X_BH = X_BL[model.robot.arm(Side::kLeft).ik_link];
  const double tcp_z = (X_BH * model.robot.gripper.tcp + model.robot.root_world).z();
  // Unobstructed, the TCP would end 10 cm below the table top; the pads stop on it.
  EXPECT_GT(tcp_z, kTableHeight) << "TCP went through the table";
  EXPECT_LT(tcp_z, kTableHeight + 0.06) << "the hand should have come down to the table";
}

TEST(PhysicsWorld, DisabledObjectsDoNotMove) {
  const WorldModel model = CubeOnTableWorld();
  PhysicsWorld world(model);
  const std::vector<double> q = model.robot.DefaultPositions();
  world.ResetRobot(q.data(), 1);
  world.SetObject(kCube, Vec3(0.4, 0.0, 1.5), Quat::Identity(), false);
  EXPECT_NEAR(StepFor(world, q, -1.0, 0.5, model).pose[2], 1.5, 1e-12);
}

}  // namespace
}  // namespace tavis::engine
