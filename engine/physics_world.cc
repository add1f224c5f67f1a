// PhysicsWorld's public operations. What the world is made of and its parts (world building,
// contacts and broad phase, kinematic arms) are in engine/internal/ (physics_world_impl.h).
#include "engine/physics_world.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <ode/ode.h>

#include "engine/batch_state.h"
#include "engine/internal/physics_world_impl.h"
#include "engine/ode_runtime.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/servo.h"

namespace tavis::engine {
namespace {

using internal::ArmJointMotor;
using internal::ArmMode;
using internal::ArmParts;
using internal::BodyPose;
using internal::Finger;
using internal::SetBodyPose;
using internal::SetBodyPoseOnly;
using internal::SetStaticGeomPose;
using kinematics::RobotModel;

// Contacts may sink this deep before they push back, which keeps resting contacts from
// jittering; penetration is corrected no faster than kContactMaxCorrectingSpeed.
constexpr double kContactSurfaceLayer = 0.0005;     // m
constexpr double kContactMaxCorrectingSpeed = 1.0;  // m/s
constexpr int kGeomsPerGripper = 3;                 // housing and two pads

}  // namespace

PhysicsWorld::PhysicsWorld(const WorldModel& model) : impl_(std::make_unique<Impl>(model)) {
  EnsureOdeReadyOnThisThread();
  Impl& s = *impl_;
  s.world = dWorldCreate();
  dWorldSetGravity(s.world, 0, 0, model.physics.gravity);
  dWorldSetContactSurfaceLayer(s.world, kContactSurfaceLayer);
  dWorldSetContactMaxCorrectingVel(s.world, kContactMaxCorrectingSpeed);
  s.threading = dThreadingAllocateSelfThreadedImplementation();
  dWorldSetStepThreadingImplementation(s.world, dThreadingImplementationGetFunctions(s.threading), s.threading);
  s.space = dSimpleSpaceCreate(nullptr);  // owns the geoms; pairs come from CollideAllPairs
  s.contacts = dJointGroupCreate(0);
  // Every geom gets one info record; reserving keeps their addresses stable for dGeomSetData.
  s.geom_infos.reserve(model.robot.shapes.size() + 2 * kGeomsPerGripper + model.objects.size() +
                       model.static_parts.size() + 1);
  s.ClassifyLinks();
  s.BuildRobot();
  s.BuildObjects();
  s.BuildStaticScene();
  s.CollectArmParts();
  s.BuildBroadPhase();
}

PhysicsWorld::~PhysicsWorld() {
  EnsureOdeReadyOnThisThread();
  dJointGroupDestroy(impl_->contacts);
  dSpaceDestroy(impl_->space);
  dWorldDestroy(impl_->world);
  dThreadingFreeImplementation(impl_->threading);
}

void PhysicsWorld::ResetRobot(const double* q) {
  Impl& s = *impl_;
  s.solver_messages = 0;
  const RobotModel& robot = s.model.robot;
  const RigidTransform X_WB = MakeTransform(robot.root_world, Mat3::Identity());
  for (int side = 0; side < 2; ++side) s.SetArmMode(side, ArmMode::kSimulated);
  kinematics::ComputeLinkPoses(robot, q, s.X_BL.data());
  for (int i = 0; i < robot.num_links(); ++i) {
    if (s.link_body[i] != nullptr) SetBodyPose(s.link_body[i], X_WB * s.X_BL[i]);
  }
  for (int side = 0; side < 2; ++side) {
    const RigidTransform X_WP = BodyPose(s.palm_body[side]);
    for (Finger& finger : s.fingers[side]) SetBodyPose(finger.body, X_WP * finger.X_PF_open);
  }
  dJointGroupEmpty(s.contacts);
}

void PhysicsWorld::SetObject(int object, const Vec3& position, const Quat& orientation, bool enabled) {
  Impl& s = *impl_;
  const RigidTransform X_WO = MakeTransform(position, orientation.normalized().toRotationMatrix());
  dBodyID body = s.object_body[object];
  dGeomID geom = s.object_geom[object];
  if (body != nullptr) {
    SetBodyPose(body, X_WO);
    if (enabled) {
      dBodyEnable(body);
    } else {
      dBodyDisable(body);
    }
  } else if (geom != nullptr) {
    SetStaticGeomPose(geom, X_WO);
  }
  if (geom == nullptr) return;
  if (enabled) {
    dGeomEnable(geom);
  } else {
    dGeomDisable(geom);
  }
}

bool PhysicsWorld::Step(const double* q_target, const std::array<double, 2>& gripper_command, int substeps) {
  Impl& s = *impl_;
  EnsureOdeReadyOnThisThread();
  const RobotModel& robot = s.model.robot;
  const double dt = 1.0 / s.model.physics.substep_hz;
  const double max_finger_speed = s.gripper.spec().max_speed;
  const uint64_t messages_before = OdeMessagesOnThisThread();
  bool sane = true;
  for (int step = 0; step < substeps && sane; ++step) {
    s.ComputeAabbs();
    const std::array<ArmMode, 2> modes = s.ArmModes();
    for (int side = 0; side < 2; ++side) {
      const double closing_target = s.gripper.ClosingTarget(gripper_command[side]);
      ArmParts& arm = s.arms[side];
      s.SetArmMode(side, modes[side]);
      if (arm.links_kinematic()) s.AdvanceKinematicArm(side, q_target, closing_target, dt, s.X_WBody_after[side]);
      // Joint-space servo: the motor's velocity target is proportional to the position error,
      // bounded by the joint velocity limit; the motor force is bounded by the effort limit.
      // Targets stay within the joint limits, clear of the stops (see kHingeStopClearance).
      if (!arm.links_kinematic()) {
        for (int m : arm.motors) {
          const ArmJointMotor& motor = s.motors[m];
          const kinematics::Joint& joint = robot.joints[motor.joint_index];
          const double target = std::clamp(q_target[motor.joint_index], joint.lower, joint.upper);
          const double error = target - dJointGetHingeAngle(motor.joint);
          dJointSetHingeParam(motor.joint, dParamVel, kinematics::JointServoVelocity(robot.arm_actuator, error));
        }
      }
      if (arm.fingers_kinematic()) continue;
      for (Finger& finger : s.fingers[side]) {
        const double error = closing_target - dJointGetSliderPosition(finger.slider);
        dJointSetSliderParam(finger.slider, dParamVel,
                             kinematics::ServoVelocity(kinematics::kFingerServoGain, error, max_finger_speed));
      }
    }
    s.CollideAllPairs();
    // The exact solver, not QuickStep: QuickStep's iterative friction let held objects creep
    // out of the fingers, and it shuffles constraints with a process-global random seed.
    dWorldStep(s.world, dt);
    dJointGroupEmpty(s.contacts);
    for (int side = 0; side < 2; ++side) {
      const ArmParts& arm = s.arms[side];
      if (!arm.links_kinematic()) continue;
      const size_t kinematic_bodies = arm.fingers_kinematic() ? arm.bodies.size() : arm.links.size();
      for (size_t i = 0; i < kinematic_bodies; ++i) SetBodyPoseOnly(arm.bodies[i], s.X_WBody_after[side][i]);
    }
    sane = s.BodiesAreSane();
  }
  s.solver_messages += static_cast<int>(OdeMessagesOnThisThread() - messages_before);
  return sane;
}

void PhysicsWorld::ReadState(double* q, double* gripper_gap, double* object_pose, double* object_velocity) const {
  const Impl& s = *impl_;
  for (int side = 0; side < 2; ++side) {
    const ArmParts& arm = s.arms[side];
    for (int m : arm.motors) {
      const ArmJointMotor& motor = s.motors[m];
      q[motor.joint_index] =
          arm.links_kinematic() ? s.q_kinematic[motor.joint_index] : dJointGetHingeAngle(motor.joint);
    }
    gripper_gap[side] = arm.fingers_kinematic()
                            ? s.gripper.GapFromClosing(arm.closing[0], arm.closing[1])
                            : s.gripper.GapFromClosing(dJointGetSliderPosition(s.fingers[side][0].slider),
                                                       dJointGetSliderPosition(s.fingers[side][1].slider));
  }
  for (size_t i = 0; i < s.object_body.size(); ++i) {
    if (s.object_body[i] == nullptr) {  // kinematic: the task's pose stands, and it is at rest
      std::fill_n(object_velocity + i * kObjectVelocitySize, kObjectVelocitySize, 0.0);
      continue;
    }
    const dReal* p = dBodyGetPosition(s.object_body[i]);
    const dReal* r = dBodyGetQuaternion(s.object_body[i]);
    const dReal* v = dBodyGetLinearVel(s.object_body[i]);
    const dReal* w = dBodyGetAngularVel(s.object_body[i]);
    double* pose = object_pose + i * kObjectPoseSize;
    double* velocity = object_velocity + i * kObjectVelocitySize;
    for (int k = 0; k < 3; ++k) {
      pose[k] = p[k];
      velocity[k] = v[k];
      velocity[3 + k] = w[k];
    }
    for (int k = 0; k < 4; ++k) pose[3 + k] = r[k];
  }
}

int PhysicsWorld::solver_messages() const { return impl_->solver_messages; }

void PhysicsWorld::SetFriction(Material material, double friction) { impl_->materials.Friction(material) = friction; }

}  // namespace tavis::engine
