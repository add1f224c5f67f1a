#include "engine/physics_world.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "engine/batch_state.h"
#include "engine/internal/arm_proximity.h"
#include "engine/object_catalog.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/inverse_kinematics.h"
#include "scenarios/expert/arm_planner.h"
#include "scenarios/expert/arm_reach.h"
#include "tests/support/robot_loading.h"

namespace tavis::engine {
namespace {

using kinematics::Side;

constexpr int kCube = 0;
const Vec3 kCubeOnTable(0.40, 0.20, kTableHeight + 0.0275);

WorldModel CubeOnTableWorld() {
  WorldModel model;
  model.robot = tavis::testing::LoadRobot("gr1t2");
  model.objects.push_back(MakeCatalogObject("red_cube"));
  model.static_parts.push_back(MakeTable());
  return model;
}

// Joint positions that put the left gripper's TCP at `tcp_world` with a reachable grasp
// orientation (approach tilted 0.8 rad forward, fingers closing along world y), via the
// experts' planner, starting from `q_start`.
std::vector<double> LeftArmAt(const kinematics::RobotModel& robot, const Vec3& tcp_world,
                              const std::vector<double>& q_start) {
  const Mat3 R = Eigen::AngleAxisd(-0.8, Vec3::UnitY()).toRotationMatrix();
  const kinematics::PoseTarget target{tcp_world - robot.root_world - R * robot.gripper.tcp, Quat(R)};
  const auto q = scenarios::expert::SolveArmConfiguration(robot, Side::kLeft, q_start, target);
  EXPECT_TRUE(q.has_value()) << "no arm configuration for the test pose";
  return q ? *q : q_start;
}

// Object 0 first; ReadState writes every object of the world, so the buffers are sized by it.
struct Observed {
  explicit Observed(const WorldModel& model)
      : pose(model.objects.size() * kObjectPoseSize), velocity(model.objects.size() * kObjectVelocitySize) {}

  std::vector<double> q;
  double gap[2] = {0, 0};
  std::vector<double> pose;
  std::vector<double> velocity;
};

// Servos the joints along a straight joint-space path from q_from to q_to over `seconds`
// (the left gripper held at `gripper`), then reads the world.
Observed StepAlong(PhysicsWorld& world, const std::vector<double>& q_from, const std::vector<double>& q_to,
                   double gripper, double seconds, const WorldModel& model) {
  Observed o(model);
  o.q = q_to;
  const int ticks = static_cast<int>(seconds * model.physics.control_hz);
  std::vector<double> q_target(q_to.size());
  for (int t = 1; t <= ticks; ++t) {
    const double s = std::min(1.0, 1.5 * t / ticks);  // the last third holds the goal
    for (size_t j = 0; j < q_to.size(); ++j) q_target[j] = q_from[j] + s * (q_to[j] - q_from[j]);
    EXPECT_TRUE(world.Step(q_target.data(), {gripper, -1.0}, model.physics.substeps_per_control()));
  }
  world.ReadState(o.q.data(), o.gap, o.pose.data(), o.velocity.data());
  return o;
}

Observed StepFor(PhysicsWorld& world, const std::vector<double>& q_target, double gripper, double seconds,
                 const WorldModel& model) {
  return StepAlong(world, q_target, q_target, gripper, seconds, model);
}

// Grasps the cube on the table from above, closes, lifts the hand 15 cm; returns the cube height.
double CubeHeightAfterLift(double friction) {
  const WorldModel model = CubeOnTableWorld();
  PhysicsWorld world(model);
  world.SetFriction(Material::kFingerPad, friction);
  world.SetFriction(Material::kObject, friction);
  const std::vector<double> q_grasp =
      LeftArmAt(model.robot, kCubeOnTable + Vec3(0, 0, 0.005), model.robot.DefaultPositions());
  world.ResetRobot(q_grasp.data());
  world.SetObject(kCube, kCubeOnTable, Quat::Identity(), true);
  const Observed closed = StepFor(world, q_grasp, 1.0, 0.8, model);
  EXPECT_NEAR(closed.pose[2], kCubeOnTable.z(), 0.005) << "closing should not move the cube";
  EXPECT_NEAR(closed.gap[0], 0.055, 0.004) << "the fingers should stop on the cube's faces";
  const std::vector<double> q_lift = LeftArmAt(model.robot, kCubeOnTable + Vec3(0, 0, 0.15), q_grasp);
  return StepAlong(world, q_grasp, q_lift, 1.0, 1.5, model).pose[2];
}

TEST(PhysicsWorld, FrictionGraspLiftsTheCube) { EXPECT_GT(CubeHeightAfterLift(1.0), kCubeOnTable.z() + 0.10); }

// An arm leaves the solver only while none of its boxes is within the kinematic-arm margin of
// anything, so the margin must exceed how far an arm point can move in one substep: one joint at
// the velocity limit swinging everything from the shoulder to past the pads (docs/fidelity.md,
// "Kinematic arms"). A faster servo or a lower substep rate would let a contact begin with the arm
// outside the solver.
TEST(PhysicsWorld, TheKinematicArmMarginExceedsASubstepsSwingOfEitherArm) {
  for (const char* name : {"gr1t2", "reachy2"}) {
    const kinematics::RobotModel robot = tavis::testing::LoadRobot(name);
    const std::vector<double> q = robot.DefaultPositions();
    std::vector<RigidTransform> X_BL(robot.links.size());
    kinematics::ComputeLinkPoses(robot, q.data(), X_BL.data());
    for (const Side side : {Side::kLeft, Side::kRight}) {
      const double lever = scenarios::expert::ArmReachOf(robot, side, X_BL.data()).radius + robot.gripper.tcp.norm() +
                           robot.gripper.pad_size.norm();
      EXPECT_GT(lever, 0.3) << name;  // an arm, not an empty chain
      const double swing = robot.arm_actuator.velocity_limit * lever / PhysicsSettings{}.substep_hz;
      EXPECT_LT(swing, internal::kKinematicArmMargin) << name << ": lever " << lever << " m";
    }
  }
}

TEST(PhysicsWorld, FrictionlessGraspLetsTheCubeSlip) { EXPECT_LT(CubeHeightAfterLift(0.0), kCubeOnTable.z() + 0.02); }

TEST(PhysicsWorld, MotionCommandedIntoTheTableStopsAtTheTable) {
  const WorldModel model = CubeOnTableWorld();
  PhysicsWorld world(model);
  const Vec3 above(0.45, 0.15, kTableHeight + 0.10);
  const std::vector<double> q_above = LeftArmAt(model.robot, above, model.robot.DefaultPositions());
  world.ResetRobot(q_above.data());
  const std::vector<double> q_through = LeftArmAt(model.robot, above - Vec3(0, 0, 0.20), q_above);
  const Observed o = StepAlong(world, q_above, q_through, -1.0, 2.0, model);
  std::vector<RigidTransform> X_BL(model.robot.links.size());
  kinematics::ComputeLinkPoses(model.robot, o.q.data(), X_BL.data());
  const RigidTransform& X_BH = X_BL[model.robot.arm(Side::kLeft).ik_link];
  const double tcp_z = (X_BH * model.robot.gripper.tcp + model.robot.root_world).z();
  // Unobstructed, the TCP would end 10 cm below the table top; the pads (whose tips reach
  // about 1.5 cm past the TCP) stop on it.
  EXPECT_GT(tcp_z, kTableHeight - 0.01) << "the hand went through the table";
  EXPECT_LT(tcp_z, kTableHeight + 0.06) << "the hand should have come down to the table";
}

TEST(PhysicsWorld, DisabledObjectsDoNotMove) {
  const WorldModel model = CubeOnTableWorld();
  PhysicsWorld world(model);
  const std::vector<double> q = model.robot.DefaultPositions();
  world.ResetRobot(q.data());
  world.SetObject(kCube, Vec3(0.4, 0.0, 1.5), Quat::Identity(), false);
  EXPECT_NEAR(StepFor(world, q, -1.0, 0.5, model).pose[2], 1.5, 1e-12);
}

// The fingers are built where kinematics::GripperGeometry puts the open pads, and their slider
// stroke spans the open to the closed gap.
TEST(PhysicsWorld, FreeFingersMeasureTheOpenAndClosedGaps) {
  for (const char* robot : {"gr1t2", "reachy2"}) {
    WorldModel model = CubeOnTableWorld();
    model.robot = tavis::testing::LoadRobot(robot);
    const kinematics::GripperSpec& gripper = model.robot.gripper;
    PhysicsWorld world(model);
    const std::vector<double> q = model.robot.DefaultPositions();
    world.ResetRobot(q.data());
    Observed o(model);
    o.q = q;
    world.ReadState(o.q.data(), o.gap, o.pose.data(), o.velocity.data());
    EXPECT_NEAR(o.gap[0], gripper.open_gap, 1e-9) << robot << ": gap at rest";
    EXPECT_NEAR(o.gap[1], gripper.open_gap, 1e-9) << robot << ": gap at rest";
    o = StepFor(world, q, 1.0, 1.0, model);  // the left gripper closes on nothing, the right stays open
    EXPECT_NEAR(o.gap[0], gripper.closed_gap, 1e-4) << robot << ": closed gap";
    EXPECT_NEAR(o.gap[1], gripper.open_gap, 1e-4) << robot << ": open gap";
  }
}

// A kinematic shelf board with a dynamic cube dropped on it; the board may be visual only.
WorldModel CubeOverKinematicBoard(bool board_collides) {
  WorldModel model = CubeOnTableWorld();
  ObjectSpec board;
  board.name = "board";
  board.shape = {ShapeKind::kBox, Vec3(0.2, 0.2, 0.02)};
  board.motion = ObjectMotion::kKinematic;
  board.collides = board_collides;
  board.appearance = "wood";
  model.objects.push_back(board);
  return model;
}

double CubeHeightOverBoard(bool board_collides) {
  const WorldModel model = CubeOverKinematicBoard(board_collides);
  PhysicsWorld world(model);
  const std::vector<double> q = model.robot.DefaultPositions();
  world.ResetRobot(q.data());
  world.SetObject(kCube, Vec3(0.5, -0.3, 1.25), Quat::Identity(), true);
  world.SetObject(1, Vec3(0.5, -0.3, 1.15), Quat::Identity(), true);
  Observed o = StepFor(world, q, -1.0, 1.0, model);
  // The board's pose and velocity are the task's: ReadState leaves the pose and reports rest.
  double poses[2 * kObjectPoseSize] = {};
  poses[kObjectPoseSize] = 123.0;
  double velocities[2 * kObjectVelocitySize];
  std::fill_n(velocities, 2 * kObjectVelocitySize, 9.0);
  world.ReadState(o.q.data(), o.gap, poses, velocities);
  EXPECT_EQ(poses[kObjectPoseSize], 123.0);
  for (int k = 0; k < kObjectVelocitySize; ++k) EXPECT_EQ(velocities[kObjectVelocitySize + k], 0.0);
  return poses[2];
}

TEST(PhysicsWorld, KinematicObjectHoldsWhatFallsOnIt) {
  // Board top at 1.16: the cube (5.5 cm) rests with its centre at 1.1875.
  EXPECT_NEAR(CubeHeightOverBoard(true), 1.1875, 0.003);
}

TEST(PhysicsWorld, VisualOnlyKinematicObjectLetsThingsThrough) {
  EXPECT_NEAR(CubeHeightOverBoard(false), kCubeOnTable.z(), 0.003);
}

}  // namespace
}  // namespace tavis::engine
