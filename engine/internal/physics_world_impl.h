// The inside of PhysicsWorld (engine/physics_world.h): the ODE world of one env and the parts it
// is made of, shared by the files that implement it at their seams:
//   engine/physics_world.cc            the public class: reset, placing objects, the step, reads
//   engine/internal/world_building.cc  bodies, joints and geoms built once from the WorldModel
//   engine/internal/contacts.cc        broad phase in a fixed order, contact joints, blow-up check
//   engine/internal/kinematic_arms.cc  which arm follows its servo outside the solver, and how
// and the ODE-free parts they use: engine/internal/broad_phase.h (the pairs that may touch) and
// engine/internal/arm_proximity.h (which arm is near what).
// Only these files include it: ODE types stay out of the engine's public headers.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <ode/ode.h>

#include "engine/internal/arm_proximity.h"
#include "engine/internal/broad_phase.h"
#include "engine/physics_world.h"
#include "engine/world_model.h"
#include "kinematics/gripper_geometry.h"

namespace tavis::engine {
namespace internal {

struct GeomInfo {
  Material material = Material::kDefault;
};

// Links moved by arm joints are bodies; links whose chain has no moving joint are static;
// links moved by the neck are servoed outside the physics and take no part here.
enum class LinkRole { kStatic, kArmBody, kNeck };

// Places the body, keeping its velocities (a kinematic body's carry its motion).
inline void SetBodyPoseOnly(dBodyID body, const RigidTransform& X_WB) {
  const Vec3& p = X_WB.translation();
  dBodySetPosition(body, p.x(), p.y(), p.z());
  const Quat q(X_WB.linear());
  const dQuaternion ode_q = {q.w(), q.x(), q.y(), q.z()};
  dBodySetQuaternion(body, ode_q);
}

// Places the body at rest.
inline void SetBodyPose(dBodyID body, const RigidTransform& X_WB) {
  SetBodyPoseOnly(body, X_WB);
  dBodySetLinearVel(body, 0, 0, 0);
  dBodySetAngularVel(body, 0, 0, 0);
}

inline RigidTransform BodyPose(dBodyID body) {
  const dReal* p = dBodyGetPosition(body);
  const dReal* q = dBodyGetQuaternion(body);
  return MakeTransform(Vec3(p[0], p[1], p[2]), Quat(q[0], q[1], q[2], q[3]).toRotationMatrix());
}

inline void SetStaticGeomPose(dGeomID geom, const RigidTransform& X_WG) {
  dGeomSetPosition(geom, X_WG.translation().x(), X_WG.translation().y(), X_WG.translation().z());
  const Quat q(X_WG.linear());
  const dQuaternion ode_q = {q.w(), q.x(), q.y(), q.z()};
  dGeomSetQuaternion(geom, ode_q);
}

struct ArmJointMotor {
  dJointID joint = nullptr;
  int joint_index = -1;
};

struct Finger {
  dBodyID body = nullptr;
  dJointID slider = nullptr;
  RigidTransform X_PF_open;      // finger pose in the palm body frame when open
  Vec3 inward_P = Vec3::Zero();  // the slider's closing direction in the palm body frame
};

// One arm's bodies and joints, for switching it between modes.
struct ArmParts {
  std::vector<int> motors;      // indices into Impl::motors
  std::vector<int> links;       // links owning a body
  std::vector<int> chain;       // ascending: every link whose pose depends on the arm's joints
  std::vector<dBodyID> bodies;  // link bodies, then the two fingers
  std::vector<int> geoms;       // indices into Impl::all_geoms attached to these bodies
  ArmMode mode = ArmMode::kSimulated;
  std::array<double, 2> closing{};  // finger slider positions while kKinematic
  bool links_kinematic() const { return mode != ArmMode::kSimulated; }
  bool fingers_kinematic() const { return mode == ArmMode::kKinematic; }
};

}  // namespace internal

struct PhysicsWorld::Impl {
  using ArmMode = internal::ArmMode;

  const WorldModel& model;
  const kinematics::GripperGeometry gripper;
  int solver_messages = 0;
  dWorldID world = nullptr;
  dSpaceID space = nullptr;
  dJointGroupID contacts = nullptr;
  dThreadingImplementationID threading = nullptr;
  MaterialTable materials;

  std::vector<internal::LinkRole> link_role;
  std::vector<int> link_body_link;  // for kArmBody links: the link that owns their body
  std::vector<dBodyID> link_body;   // body per owning link (nullptr otherwise)
  std::vector<internal::ArmJointMotor> motors;
  std::array<std::array<internal::Finger, 2>, 2> fingers{};  // [side][+axis, -axis]
  std::array<dBodyID, 2> palm_body{};
  std::array<RigidTransform, 2> X_BodyIk;  // IK link frame in its body's frame
  std::vector<dBodyID> object_body;
  std::vector<dGeomID> object_geom;
  std::vector<dBodyID> all_bodies;
  std::vector<dGeomID> all_geoms;                           // creation order
  std::vector<double> aabbs;                                // (geoms x 6) this substep's boxes
  std::vector<uint8_t> geom_enabled;                        // (geoms) this substep's enabled flags
  std::optional<internal::CandidatePairs> candidate_pairs;  // built once the world is
  std::optional<internal::ArmProximity> arm_proximity;      // built once the world is
  std::vector<internal::GeomInfo> geom_infos;               // stable storage: reserved up front, never reallocated
  std::vector<RigidTransform> X_BL;                         // FK scratch
  std::array<internal::ArmParts, 2> arms;
  std::vector<double> q_kinematic;                           // (num_joints) joint positions of kinematic arms
  std::array<std::vector<RigidTransform>, 2> X_WBody_after;  // scratch: kinematic arms' next poses

  explicit Impl(const WorldModel& m) : model(m), gripper(m.robot.gripper), materials(m.materials) {}

  // World building (engine/internal/world_building.cc), in the order the constructor calls them.
  void ClassifyLinks();
  void BuildRobot();
  void BuildGripper(kinematics::Side side, const RigidTransform& X_WB);
  // Dynamic objects get a body; kinematic ones only a geom without a body (if they collide),
  // which SetObject moves.
  void BuildObjects();
  void BuildStaticScene();
  // Which bodies, joints and geoms make up each arm; called once everything is built.
  void CollectArmParts();
  // The broad phase's fixed data (candidate pairs, arm proximity); called after CollectArmParts.
  void BuildBroadPhase();
  dBodyID NewBody();
  // ODE capsules take (radius, length) along their local z axis, as Shape does. Cylinders
  // collide as boxes: Debian's ODE has no libccd, its cylinder-box test asserts on parallel
  // axes (an upright can on a table), and its convex-polytope tests produced NaNs in our
  // grasps (docs/fidelity.md).
  dGeomID CreateGeom(dSpaceID geom_space, const Shape& shape);
  internal::GeomInfo* NewGeomInfo(Material material);
  void Tag(dGeomID geom, Material material, unsigned long category, unsigned long collides_with);

  // Contacts and broad phase (engine/internal/contacts.cc).
  // Each geom's box and enabled flag for this substep, read from ODE once.
  void ComputeAabbs();
  // Broad phase over the candidate geom pairs in creation order. ODE's spaces move each geom
  // that moved to the front of their lists, so the order of contact pairs (and, through
  // floating-point summation order, the solution) would depend on the world's past episodes; a
  // fixed order makes an episode depend on its own inputs only. Needs ComputeAabbs.
  void CollideAllPairs();
  void Collide(dGeomID a, dGeomID b);
  bool BodiesAreSane() const;

  // Kinematic arm modes (engine/internal/kinematic_arms.cc).
  // The mode of each arm this substep (needs ComputeAabbs; internal::ArmProximity says how).
  std::array<ArmMode, 2> ArmModes();
  // Kinematic bodies leave the solver: infinite mass, their joints off. Joint positions and
  // finger slides are taken from the simulation when they become kinematic; bodies simulated
  // again keep the velocities their kinematic motion gave them.
  void SetArmMode(int side, ArmMode mode);
  // The poses of a kinematic arm's bodies (links, and fingers if kinematic) at q_kinematic and
  // its finger slides, into X_WBody.
  void KinematicArmPoses(int side, std::vector<RigidTransform>& X_WBody);
  // The kinematic servo: joints (and finger slides if kinematic) move at their servo velocities
  // for dt, exactly, where a simulated arm's motion is bounded by its motors' effort. Sets the
  // kinematic bodies' velocities toward their new poses (in next_poses), which Step places
  // after the solver step.
  void AdvanceKinematicArm(int side, const double* q_target, double closing_target, double dt,
                           std::vector<RigidTransform>& next_poses);
};

}  // namespace tavis::engine
