// A robot compiled from its YAML description: a kinematic tree of links, the actuated joints,
// shapes, camera mounts, gripper and IK settings. Immutable after loading; every name is
// resolved to an index here so the hot loop never sees a string.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "kinematics/action.h"
#include "kinematics/pose.h"
#include "kinematics/shape.h"

namespace tavis::kinematics {

// kg, the lightest body the physics accepts for a link or a finger: lighter bodies next to the
// arm's make ODE's solver stall (the fingers chatter). The robot loader rejects anything lighter.
inline constexpr double kMinBodyMass = 0.05;

// A link is placed relative to its parent by a fixed origin, then (if actuated) rotated by its
// joint about `axis`: X_PL(q) = origin * Rot(axis, q). Links are stored parents-first.
struct Link {
  std::string name;
  int parent = -1;  // -1 (kBaseLink): the robot's base link
  RigidTransform origin = RigidTransform::Identity();
  int joint = -1;     // index into the joint vector, -1 for a fixed frame
  double mass = 0.0;  // kg, actuated links only; at least kMinBodyMass
};

struct Joint {
  std::string name;
  int link = -1;              // the child link this joint moves
  Vec3 axis = Vec3::UnitZ();  // unit length
  double lower = 0.0;
  double upper = 0.0;
  double default_position = 0.0;
};

// The robot's base link (root) is not in `links`; shapes and frames on it use this index.
constexpr int kBaseLink = -1;

struct LinkShape {
  int link = kBaseLink;
  Shape shape;
  RigidTransform X_LS = RigidTransform::Identity();  // shape frame in the link frame
};

struct CameraMount {
  std::string name;
  int link = -1;
  // Camera frame in the link frame, IsaacLab "world" convention: +X optical axis, +Z image up.
  RigidTransform X_LC = RigidTransform::Identity();
  double focal_length_mm = 0.0;
  double near_m = 0.0;
  double far_m = 0.0;
};

struct ActuatorLimits {
  double velocity_limit = 0.0;  // rad/s
  double effort_limit = 0.0;    // N m
  double position_gain = 0.0;   // 1/s, joint-space servo gain
};

// Parallel-jaw gripper attached to the IK link, described in that link's frame.
struct GripperSpec {
  Vec3 tcp = Vec3::Zero();
  Vec3 closing_axis = Vec3::UnitY();  // fingers move along +-axis
  Vec3 pad_size = Vec3::Zero();
  Vec3 pad_center = Vec3::Zero();  // centre between the two pads
  double open_gap = 0.0;           // inner-face distance when open
  double closed_gap = 0.0;
  double max_force = 0.0;  // N per finger
  double max_speed = 0.0;  // m/s per finger
  double finger_mass = 0.0;
  Vec3 housing_center = Vec3::Zero();
  Vec3 housing_size = Vec3::Zero();
};

struct ArmSpec {
  std::array<int, kArmDof> joints{};  // joint indices, shoulder to wrist
  int ik_link = -1;
  RigidTransform rest_pose_canonical = RigidTransform::Identity();  // teleop rest target
};

// One entry of the policy's observation.state, in the order of the reference's robot_joint_pos
// (PhysX articulation order) as far as it is known: a simulated joint's position, a joint the
// reference has but this model does not simulate (locked legs and waist: a constant), or a
// gripper's measured jaw gap.
struct StateEntry {
  enum class Kind { kJoint, kUnsimulated, kGripperGap };
  Kind kind = Kind::kJoint;
  std::string name;         // the reference's joint name (kJoint: ours), for documentation and errors
  int joint = -1;           // kJoint: index in RobotModel::joints
  Side side = Side::kLeft;  // kGripperGap
  double value = 0.0;       // kUnsimulated: its constant position
};

struct RobotModel {
  std::string name;
  Vec3 root_world = Vec3::Zero();        // base link origin in the world (identity rotation)
  Vec3 canonical_offset = Vec3::Zero();  // canonical frame origin in the base frame
  std::vector<Link> links;
  std::vector<Joint> joints;
  std::vector<LinkShape> shapes;
  std::vector<CameraMount> cameras;
  std::array<ArmSpec, 2> arms;
  std::array<int, kNeckDof> neck_joints{};  // roll, pitch, yaw
  ActuatorLimits arm_actuator;
  ActuatorLimits neck_actuator;
  double ik_damping = 0.01;
  double nullspace_gain = 1.0;
  GripperSpec gripper;
  std::vector<StateEntry> observation_state;

  int num_joints() const { return static_cast<int>(joints.size()); }
  int num_links() const { return static_cast<int>(links.size()); }
  const ArmSpec& arm(Side side) const { return arms[Index(side)]; }
  // Index lookups for set-up code and tests; throw std::out_of_range naming the missing name.
  int LinkIndex(const std::string& link_name) const;
  int JointIndex(const std::string& joint_name) const;
  int CameraIndex(const std::string& camera_name) const;
  std::vector<double> DefaultPositions() const;
  // Transform between the canonical (action) frame and the base frame: pure translation.
  Vec3 CanonicalToBase(const Vec3& p_canonical) const { return p_canonical + canonical_offset; }
  Vec3 BaseToCanonical(const Vec3& p_base) const { return p_base - canonical_offset; }
};

}  // namespace tavis::kinematics
