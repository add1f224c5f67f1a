// PhysicsWorld's kinematic arms (docs/fidelity.md): an arm with nothing near it follows its
// servo outside the solver, and is handed back to the solver before anything touches it.
#include <algorithm>
#include <vector>

#include <ode/ode.h>

#include "engine/internal/physics_world_impl.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/servo.h"

namespace tavis::engine {

using internal::ArmJointMotor;
using internal::ArmParts;
using internal::BodyPose;
using internal::Finger;
using kinematics::RobotModel;

namespace {

// Velocity that carries a body from `from` to `to` in dt, for a kinematic body's contacts and
// for the moment it is simulated again.
void SetBodyMotion(dBodyID body, const RigidTransform& from, const RigidTransform& to, double dt) {
  const Vec3 v = (to.translation() - from.translation()) / dt;
  const Eigen::AngleAxisd turn(to.linear() * from.linear().transpose());
  const Vec3 w = turn.axis() * (turn.angle() / dt);
  dBodySetLinearVel(body, v.x(), v.y(), v.z());
  dBodySetAngularVel(body, w.x(), w.y(), w.z());
}

}  // namespace

std::array<internal::ArmMode, 2> PhysicsWorld::Impl::ArmModes() {
  return arm_proximity->Modes(aabbs.data(), geom_enabled.data());
}

void PhysicsWorld::Impl::SetArmMode(int side, ArmMode mode) {
  ArmParts& arm = arms[side];
  const bool links_were = arm.links_kinematic();
  const bool fingers_were = arm.fingers_kinematic();
  arm.mode = mode;
  if (arm.links_kinematic() != links_were) {
    const bool kinematic = arm.links_kinematic();
    for (size_t i = 0; i < arm.motors.size(); ++i) {
      const ArmJointMotor& motor = motors[arm.motors[i]];
      if (kinematic) {
        q_kinematic[motor.joint_index] = dJointGetHingeAngle(motor.joint);
        dJointDisable(motor.joint);
        dBodySetKinematic(arm.bodies[i]);
      } else {
        dJointEnable(motor.joint);
        dBodySetDynamic(arm.bodies[i]);
      }
    }
  }
  if (arm.fingers_kinematic() != fingers_were) {
    const bool kinematic = arm.fingers_kinematic();
    for (int f = 0; f < 2; ++f) {
      const Finger& finger = fingers[side][f];
      if (kinematic) {
        arm.closing[f] = dJointGetSliderPosition(finger.slider);
        dJointDisable(finger.slider);
        dBodySetKinematic(finger.body);
      } else {
        dJointEnable(finger.slider);
        dBodySetDynamic(finger.body);
      }
    }
  }
}

void PhysicsWorld::Impl::KinematicArmPoses(int side, std::vector<RigidTransform>& X_WBody) {
  const RobotModel& robot = model.robot;
  const RigidTransform X_WB = MakeTransform(robot.root_world, Mat3::Identity());
  const ArmParts& arm = arms[side];
  // The links before the arm's chain are static, and X_BL always holds their poses.
  kinematics::ComputeLinkPosesOf(robot, q_kinematic.data(), arm.chain, X_BL.data());
  X_WBody.resize(arm.bodies.size());
  for (size_t i = 0; i < arm.links.size(); ++i) X_WBody[i] = X_WB * X_BL[arm.links[i]];
  if (!arm.fingers_kinematic()) return;
  const RigidTransform X_WP = X_WB * X_BL[link_body_link[robot.arm(kinematics::kSides[side]).ik_link]];
  for (int f = 0; f < 2; ++f) {
    const Finger& finger = fingers[side][f];
    RigidTransform X_PF = finger.X_PF_open;
    X_PF.translation() += arm.closing[f] * finger.inward_P;
    X_WBody[arm.links.size() + f] = X_WP * X_PF;
  }
}

void PhysicsWorld::Impl::AdvanceKinematicArm(int side, const double* q_target, double closing_target, double dt,
                                             std::vector<RigidTransform>& next_poses) {
  const RobotModel& robot = model.robot;
  ArmParts& arm = arms[side];
  for (int m : arm.motors) {
    const int j = motors[m].joint_index;
    const kinematics::Joint& joint = robot.joints[j];
    const double target = std::clamp(q_target[j], joint.lower, joint.upper);
    q_kinematic[j] += dt * kinematics::JointServoVelocity(robot.arm_actuator, target - q_kinematic[j]);
  }
  if (arm.fingers_kinematic()) {
    const double max_finger_speed = gripper.spec().max_speed;
    for (double& closing : arm.closing) {
      closing +=
          dt * kinematics::ServoVelocity(kinematics::kFingerServoGain, closing_target - closing, max_finger_speed);
    }
  }
  KinematicArmPoses(side, next_poses);
  const size_t kinematic_bodies = arm.fingers_kinematic() ? arm.bodies.size() : arm.links.size();
  for (size_t i = 0; i < kinematic_bodies; ++i)
    SetBodyMotion(arm.bodies[i], BodyPose(arm.bodies[i]), next_poses[i], dt);
}

}  // namespace tavis::engine
