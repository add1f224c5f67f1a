#include "engine/physics_world.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <ode/ode.h>

#include "engine/batch_state.h"
#include "engine/ode_runtime.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/gripper_geometry.h"
#include "kinematics/invariant.h"

namespace tavis::engine {
namespace {

using kinematics::RobotModel;
using kinematics::Side;

constexpr double kPadContactRadius = 0.01;  // m, effective radius of a finger pad's contact
// Robot bodies (links and fingers) get the inertia of a sphere of this radius: a pad's true
// inertia is tiny next to the arm's, and that ratio stalls the solver (the fingers chatter).
constexpr double kRobotInertiaRadius = 0.05;  // m
// Finger servo: the slider's velocity target per metre of closing-position error, bounded by
// the gripper's speed limit.
constexpr double kFingerServoGain = 40.0;  // 1/s
// Contacts may sink this deep before they push back, which keeps resting contacts from
// jittering; penetration is corrected no faster than kContactMaxCorrectingSpeed.
constexpr double kContactSurfaceLayer = 0.0005;     // m
constexpr double kContactMaxCorrectingSpeed = 1.0;  // m/s
constexpr int kGeomsPerGripper = 3;                 // housing and two pads
constexpr int kOdeAxisZ = 3;  // ODE's code for a body's local z axis, Shape's long axis
// Joint stops sit this far outside the limits the servo targets respect. A joint driven by its
// motor while resting on a stop gets ODE's stop/motor fallback, a full-force impulse for one
// step (scaled by the fudge factor), which kicked wrists by 0.1-0.2 rad and fingers by 2 cm
// mid-grasp. Servoed within its limits a joint never reaches the stops; they remain hard limits.
constexpr double kHingeStopClearance = 0.02;   // rad
constexpr double kSliderStopClearance = 0.002;  // m
// An arm none of whose geoms comes within this distance of an object or the static scene
// follows its servo kinematically: its bodies leave the LCP (docs/fidelity.md). The margin
// exceeds a substep's motion of any arm point (5 rad/s joints, under 1 m of arm: 2 cm at
// 240 Hz), so every contact begins with the arm already simulated.
constexpr double kKinematicArmMargin = 0.03;  // m

// Collision categories: the robot does not collide with itself (reference: self-collisions off).
enum CategoryBits : unsigned long { kRobotBit = 1, kObjectBit = 2, kStaticBit = 4 };

struct GeomInfo {
  Material material = Material::kDefault;
};

// Links moved by arm joints are bodies; links whose chain has no moving joint are static;
// links moved by the neck are servoed outside the physics and take no part here.
enum class LinkRole { kStatic, kArmBody, kNeck };

// Places the body, keeping its velocities (a kinematic body's carry its motion).
void SetBodyPoseOnly(dBodyID body, const RigidTransform& X_WB) {
  const Vec3& p = X_WB.translation();
  dBodySetPosition(body, p.x(), p.y(), p.z());
  const Quat q(X_WB.linear());
  const dQuaternion ode_q = {q.w(), q.x(), q.y(), q.z()};
  dBodySetQuaternion(body, ode_q);
}

// Places the body at rest.
void SetBodyPose(dBodyID body, const RigidTransform& X_WB) {
  SetBodyPoseOnly(body, X_WB);
  dBodySetLinearVel(body, 0, 0, 0);
  dBodySetAngularVel(body, 0, 0, 0);
}

RigidTransform BodyPose(dBodyID body) {
  const dReal* p = dBodyGetPosition(body);
  const dReal* q = dBodyGetQuaternion(body);
  return MakeTransform(Vec3(p[0], p[1], p[2]), Quat(q[0], q[1], q[2], q[3]).toRotationMatrix());
}

void SetGeomOffset(dGeomID geom, const RigidTransform& X_BG) {
  dGeomSetOffsetPosition(geom, X_BG.translation().x(), X_BG.translation().y(), X_BG.translation().z());
  const Quat q(X_BG.linear());
  const dQuaternion ode_q = {q.w(), q.x(), q.y(), q.z()};
  dGeomSetOffsetQuaternion(geom, ode_q);
}

void SetStaticGeomPose(dGeomID geom, const RigidTransform& X_WG) {
  dGeomSetPosition(geom, X_WG.translation().x(), X_WG.translation().y(), X_WG.translation().z());
  const Quat q(X_WG.linear());
  const dQuaternion ode_q = {q.w(), q.x(), q.y(), q.z()};
  dGeomSetQuaternion(geom, ode_q);
}


void SetMass(dBodyID body, const Shape& shape, double mass) {
  dMass m;
  switch (shape.kind) {
    case ShapeKind::kBox: dMassSetBoxTotal(&m, mass, shape.size.x(), shape.size.y(), shape.size.z()); break;
    case ShapeKind::kCylinder: dMassSetCylinderTotal(&m, mass, kOdeAxisZ, shape.Radius(), shape.Length()); break;
    case ShapeKind::kCapsule: dMassSetCapsuleTotal(&m, mass, kOdeAxisZ, shape.Radius(), shape.Length()); break;
    case ShapeKind::kSphere: dMassSetSphereTotal(&m, mass, shape.Radius()); break;
  }
  dBodySetMass(body, &m);
}

struct ArmJointMotor {
  dJointID joint = nullptr;
  int joint_index = -1;
};

struct Finger {
  dBodyID body = nullptr;
  dJointID slider = nullptr;
  RigidTransform X_PF_open;  // finger pose in the palm body frame when open
  Vec3 inward_P = Vec3::Zero();  // the slider's closing direction in the palm body frame
};

// How an arm moves in a substep (docs/fidelity.md, "kinematic arms"). kSimulated: links and
// fingers are bodies in the solver. kGrip: the links follow their servo kinematically, the
// fingers are simulated against the moving palm (a held object away from everything else).
// kKinematic: links and fingers follow their servos (nothing near the arm).
enum class ArmMode { kSimulated, kGrip, kKinematic };

// One arm's bodies and joints, for switching it between modes.
struct ArmParts {
  std::vector<int> motors;  // indices into Impl::motors
  std::vector<int> links;   // links owning a body
  std::vector<int> chain;   // ascending: every link whose pose depends on the arm's joints
  std::vector<dBodyID> bodies;  // link bodies, then the two fingers
  std::vector<int> geoms;   // indices into Impl::all_geoms attached to these bodies
  ArmMode mode = ArmMode::kSimulated;
  std::array<double, 2> closing{};  // finger slider positions while kKinematic
  bool links_kinematic() const { return mode != ArmMode::kSimulated; }
  bool fingers_kinematic() const { return mode == ArmMode::kKinematic; }
};

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

struct PhysicsWorld::Impl {
  const WorldModel& model;
  const kinematics::GripperGeometry gripper;
  int solver_messages = 0;
  dWorldID world = nullptr;
  dSpaceID space = nullptr;
  dJointGroupID contacts = nullptr;
  dThreadingImplementationID threading = nullptr;
  MaterialTable materials;

  std::vector<LinkRole> link_role;
  std::vector<int> link_body_link;  // for kArmBody links: the link that owns their body
  std::vector<dBodyID> link_body;   // body per owning link (nullptr otherwise)
  std::vector<ArmJointMotor> motors;
  std::array<std::array<Finger, 2>, 2> fingers{};  // [side][+axis, -axis]
  std::array<dBodyID, 2> palm_body{};
  std::array<RigidTransform, 2> X_BodyIk;  // IK link frame in its body's frame
  std::vector<dBodyID> object_body;
  std::vector<dGeomID> object_geom;
  std::vector<dBodyID> all_bodies;
  std::vector<dGeomID> all_geoms;  // creation order
  std::vector<double> aabbs;        // (geoms x 6) broad-phase scratch
  std::vector<GeomInfo> geom_infos;  // stable storage: reserved up front, never reallocated
  std::vector<RigidTransform> X_BL;  // FK scratch
  std::array<ArmParts, 2> arms;
  std::vector<double> q_kinematic;   // (num_joints) joint positions of kinematic arms
  std::array<std::vector<RigidTransform>, 2> X_WBody_after;  // scratch: kinematic arms' next poses
  std::vector<uint8_t> object_supported;  // (geoms) scratch for ArmModes

  dBodyID NewBody() {
    all_bodies.push_back(dBodyCreate(world));
    return all_bodies.back();
  }

  explicit Impl(const WorldModel& m) : model(m), gripper(m.robot.gripper), materials(m.materials) {}

  // ODE capsules take (radius, length) along their local z axis, as Shape does. Cylinders
  // collide as boxes: Debian's ODE has no libccd, its cylinder-box test asserts on parallel
  // axes (an upright can on a table), and its convex-polytope tests produced NaNs in our
  // grasps (docs/fidelity.md).
  dGeomID CreateGeom(dSpaceID geom_space, const Shape& shape) {
    switch (shape.kind) {
      case ShapeKind::kBox: return dCreateBox(geom_space, shape.size.x(), shape.size.y(), shape.size.z());
      case ShapeKind::kCylinder: {
        // The circumscribed square prism: see the note above.
        const double side = 2.0 * shape.Radius();
        return dCreateBox(geom_space, side, side, shape.Length());
      }
      case ShapeKind::kCapsule: return dCreateCapsule(geom_space, shape.Radius(), shape.Length());
      case ShapeKind::kSphere: return dCreateSphere(geom_space, shape.Radius());
    }
    return nullptr;
  }

  GeomInfo* NewGeomInfo(Material material) {
    geom_infos.push_back({material});
    return &geom_infos.back();
  }

  void Tag(dGeomID geom, Material material, unsigned long category, unsigned long collides_with) {
    all_geoms.push_back(geom);
    dGeomSetData(geom, NewGeomInfo(material));
    dGeomSetCategoryBits(geom, category);
    dGeomSetCollideBits(geom, collides_with);
  }

  void ClassifyLinks() {
    const RobotModel& robot = model.robot;
    std::vector<bool> is_arm_joint(robot.num_joints(), false);
    for (const auto& arm : robot.arms) {
      for (int j : arm.joints) is_arm_joint[j] = true;
    }
    link_role.assign(robot.num_links(), LinkRole::kStatic);
    link_body_link.assign(robot.num_links(), -1);
    for (int i = 0; i < robot.num_links(); ++i) {
      const kinematics::Link& link = robot.links[i];
      const LinkRole parent_role = link.parent < 0 ? LinkRole::kStatic : link_role[link.parent];
      if (link.joint >= 0) {
        link_role[i] = is_arm_joint[link.joint] ? LinkRole::kArmBody : LinkRole::kNeck;
        if (parent_role == LinkRole::kNeck) link_role[i] = LinkRole::kNeck;
        if (link_role[i] == LinkRole::kArmBody) link_body_link[i] = i;
      } else {
        link_role[i] = parent_role;
        if (parent_role == LinkRole::kArmBody) link_body_link[i] = link_body_link[link.parent];
      }
    }
  }

  void BuildRobot() {
    const RobotModel& robot = model.robot;
    const RigidTransform X_WB = MakeTransform(robot.root_world, Mat3::Identity());
    X_BL.resize(robot.num_links());
    // Bodies and joints are created at q = 0, so ODE's joint angles equal joint positions.
    const std::vector<double> zeros(robot.num_joints(), 0.0);
    kinematics::ComputeLinkPoses(robot, zeros.data(), X_BL.data());
    link_body.assign(robot.num_links(), nullptr);
    for (int i = 0; i < robot.num_links(); ++i) {
      if (link_body_link[i] != i) continue;
      dBodyID body = NewBody();
      // configs::LoadRobotModel rejects lighter links; ODE would abort on a zero mass.
      TAVIS_INVARIANT(robot.links[i].mass >= kinematics::kMinBodyMass, "link mass validated at load");
      dMass m;
      dMassSetSphereTotal(&m, robot.links[i].mass, kRobotInertiaRadius);
      dBodySetMass(body, &m);
      dBodySetGravityMode(body, 0);  // robot bodies are gravity-free in the reference
      SetBodyPose(body, X_WB * X_BL[i]);
      link_body[i] = body;
      const kinematics::Link& link = robot.links[i];
      const int parent_owner = link.parent < 0 ? -1 : link_body_link[link.parent];
      dJointID hinge = dJointCreateHinge(world, nullptr);
      dJointAttach(hinge, body, parent_owner < 0 ? nullptr : link_body[parent_owner]);
      const RigidTransform X_WL = X_WB * X_BL[i];
      const Vec3 axis = X_WL.linear() * robot.joints[link.joint].axis;
      dJointSetHingeAnchor(hinge, X_WL.translation().x(), X_WL.translation().y(), X_WL.translation().z());
      dJointSetHingeAxis(hinge, axis.x(), axis.y(), axis.z());
      dJointSetHingeParam(hinge, dParamLoStop, robot.joints[link.joint].lower - kHingeStopClearance);
      dJointSetHingeParam(hinge, dParamHiStop, robot.joints[link.joint].upper + kHingeStopClearance);
      dJointSetHingeParam(hinge, dParamFMax, robot.arm_actuator.effort_limit);
      motors.push_back({hinge, link.joint});
    }
    for (const kinematics::LinkShape& link_shape : robot.shapes) {
      const bool on_base = link_shape.link == kinematics::kBaseLink;
      const LinkRole role = on_base ? LinkRole::kStatic : link_role[link_shape.link];
      if (role == LinkRole::kNeck) continue;
      dGeomID geom = CreateGeom(space, link_shape.shape);
      Tag(geom, Material::kRobot, kRobotBit, kObjectBit | kStaticBit);
      const RigidTransform X_WS = X_WB * (on_base ? link_shape.X_LS : X_BL[link_shape.link] * link_shape.X_LS);
      if (role == LinkRole::kStatic) {
        SetStaticGeomPose(geom, X_WS);
        continue;
      }
      const int owner = link_body_link[link_shape.link];
      dGeomSetBody(geom, link_body[owner]);
      SetGeomOffset(geom, (X_WB * X_BL[owner]).inverse() * X_WS);
    }
    for (Side side : kinematics::kSides) BuildGripper(side, X_WB);
  }

  void BuildGripper(Side side, const RigidTransform& X_WB) {
    const RobotModel& robot = model.robot;
    const kinematics::GripperSpec& g = gripper.spec();
    const int ik_link = robot.arm(side).ik_link;
    // The loader requires the ik_link to be moved by the arm's joints, so it has a body.
    TAVIS_INVARIANT(ik_link >= 0 && link_body_link[ik_link] >= 0, "ik_link is on an arm body");
    const int owner = link_body_link[ik_link];
    const int s = kinematics::Index(side);
    palm_body[s] = link_body[owner];
    X_BodyIk[s] = X_BL[owner].inverse() * X_BL[ik_link];
    const RigidTransform X_WIk = X_WB * X_BL[ik_link];

    dGeomID housing = CreateGeom(space, {ShapeKind::kBox, g.housing_size});
    Tag(housing, Material::kRobot, kRobotBit, kObjectBit | kStaticBit);
    dGeomSetBody(housing, palm_body[s]);
    SetGeomOffset(housing, X_BodyIk[s] * gripper.X_IkHousing());

    for (int f = 0; f < 2; ++f) {
      const double sign = kinematics::kJawSigns[f];
      const RigidTransform X_WF = X_WIk * gripper.X_IkPad(sign, g.open_gap);
      Finger& finger = fingers[s][f];
      finger.body = NewBody();
      TAVIS_INVARIANT(g.finger_mass >= kinematics::kMinBodyMass, "finger mass validated at load");
      dMass finger_mass;
      dMassSetSphereTotal(&finger_mass, g.finger_mass, kRobotInertiaRadius);
      dBodySetMass(finger.body, &finger_mass);
      dBodySetGravityMode(finger.body, 0);
      SetBodyPose(finger.body, X_WF);
      dGeomID pad = CreateGeom(space, {ShapeKind::kBox, g.pad_size});
      Tag(pad, Material::kFingerPad, kRobotBit, kObjectBit | kStaticBit);
      dGeomSetBody(pad, finger.body);
      finger.X_PF_open = BodyPose(palm_body[s]).inverse() * X_WF;
      // A slider motor moves body1 along the axis relative to body2: (finger, palm), axis
      // pointing inward, so positive positions close the gripper.
      finger.slider = dJointCreateSlider(world, nullptr);
      dJointAttach(finger.slider, finger.body, palm_body[s]);
      const Vec3 inward = -sign * (X_WIk.linear() * g.closing_axis);
      finger.inward_P = BodyPose(palm_body[s]).linear().transpose() * inward;
      dJointSetSliderAxis(finger.slider, inward.x(), inward.y(), inward.z());
      dJointSetSliderParam(finger.slider, dParamLoStop, -kSliderStopClearance);
      dJointSetSliderParam(finger.slider, dParamHiStop, gripper.finger_travel() + kSliderStopClearance);
      dJointSetSliderParam(finger.slider, dParamFMax, g.max_force);
    }
  }

  // Dynamic objects get a body; kinematic ones only a geom without a body (if they collide),
  // which SetObject moves.
  void BuildObjects() {
    for (const ObjectSpec& spec : model.objects) {
      if (spec.motion == ObjectMotion::kKinematic) {
        dGeomID geom = nullptr;
        if (spec.collides) {
          geom = CreateGeom(space, spec.shape);
          Tag(geom, spec.material, kStaticBit, kRobotBit | kObjectBit);
          dGeomDisable(geom);
        }
        object_body.push_back(nullptr);
        object_geom.push_back(geom);
        continue;
      }
      dBodyID body = NewBody();
      SetMass(body, spec.shape, spec.mass);
      dGeomID geom = CreateGeom(space, spec.shape);
      Tag(geom, spec.material, kObjectBit, kRobotBit | kObjectBit | kStaticBit);
      dGeomSetBody(geom, body);
      dBodyDisable(body);
      dGeomDisable(geom);
      object_body.push_back(body);
      object_geom.push_back(geom);
    }
  }

  void BuildStaticScene() {
    for (const StaticPart& part : model.static_parts) {
      if (!part.collides) continue;
      dGeomID geom = CreateGeom(space, part.shape);
      Tag(geom, part.material, kStaticBit, kRobotBit | kObjectBit);
      SetStaticGeomPose(geom, part.X_WS);
    }
    dGeomID ground = dCreatePlane(space, 0, 0, 1, 0);
    Tag(ground, Material::kDefault, kStaticBit, kRobotBit | kObjectBit);
  }

  void Collide(dGeomID a, dGeomID b) {
    dBodyID body_a = dGeomGetBody(a);
    dBodyID body_b = dGeomGetBody(b);
    if (body_a == nullptr && body_b == nullptr) return;
    constexpr int kMaxContacts = 8;
    dContactGeom contact_geoms[kMaxContacts];
    const int max_contacts = std::min(kMaxContacts, model.physics.max_contacts_per_pair);
    const int n = dCollide(a, b, max_contacts, contact_geoms, sizeof(dContactGeom));
    if (n == 0) return;
    const auto* info_a = static_cast<const GeomInfo*>(dGeomGetData(a));
    const auto* info_b = static_cast<const GeomInfo*>(dGeomGetData(b));
    const double mu = 0.5 * (materials.Friction(info_a->material) + materials.Friction(info_b->material));
    // Point contacts carry no torsional friction, so a held object would pivot about the line
    // through its few pad contacts. A pad's area contact resists that twist: spinning friction
    // over the pad's effective radius.
    const bool pad_contact = info_a->material == Material::kFingerPad || info_b->material == Material::kFingerPad;
    for (int i = 0; i < n; ++i) {
      dContact contact{};
      contact.surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
      if (pad_contact) {
        contact.surface.mode |= dContactRolling;
        contact.surface.rhoN = mu * kPadContactRadius;
      }
      contact.surface.mu = mu;
      contact.surface.soft_erp = model.physics.contact_erp;
      contact.surface.soft_cfm = model.physics.contact_cfm;
      contact.geom = contact_geoms[i];
      dJointID joint = dJointCreateContact(world, contacts, &contact);
      dJointAttach(joint, body_a, body_b);
    }
  }

  // Which bodies, joints and geoms make up each arm; called once everything is built.
  void CollectArmParts() {
    const RobotModel& robot = model.robot;
    for (Side side : kinematics::kSides) {
      ArmParts& arm = arms[kinematics::Index(side)];
      const std::array<int, kinematics::kArmDof>& joints = robot.arm(side).joints;
      for (size_t m = 0; m < motors.size(); ++m) {
        if (std::find(joints.begin(), joints.end(), motors[m].joint_index) == joints.end()) continue;
        arm.motors.push_back(static_cast<int>(m));
        const int link = robot.joints[motors[m].joint_index].link;
        arm.links.push_back(link);
        arm.bodies.push_back(link_body[link]);
      }
      for (const Finger& finger : fingers[kinematics::Index(side)]) arm.bodies.push_back(finger.body);
      for (size_t g = 0; g < all_geoms.size(); ++g) {
        dBodyID body = dGeomGetBody(all_geoms[g]);
        if (body != nullptr && std::find(arm.bodies.begin(), arm.bodies.end(), body) != arm.bodies.end()) {
          arm.geoms.push_back(static_cast<int>(g));
        }
      }
    }
    for (int i = 0; i < robot.num_links(); ++i) {
      const int owner = link_body_link[i];
      if (owner < 0) continue;
      for (Side side : kinematics::kSides) {
        ArmParts& arm = arms[kinematics::Index(side)];
        if (std::find(arm.links.begin(), arm.links.end(), owner) != arm.links.end()) arm.chain.push_back(i);
      }
    }
    q_kinematic.assign(robot.num_joints(), 0.0);
  }

  void ComputeAabbs() {
    for (size_t i = 0; i < all_geoms.size(); ++i) dGeomGetAABB(all_geoms[i], &aabbs[6 * i]);
  }

  // Whether the boxes of geoms i and j come within kKinematicArmMargin of each other; the
  // ground plane, whose box is unbounded, by the height of the other box.
  bool Near(size_t i, size_t j) const {
    const double* box_a = &aabbs[6 * i];
    const double* box_b = &aabbs[6 * j];
    constexpr double m = kKinematicArmMargin;
    if (dGeomGetClass(all_geoms[j]) == dPlaneClass) return box_a[4] < m;
    if (dGeomGetClass(all_geoms[i]) == dPlaneClass) return box_b[4] < m;
    return !(box_a[0] > box_b[1] + m || box_b[0] > box_a[1] + m || box_a[2] > box_b[3] + m || box_b[2] > box_a[3] + m ||
             box_a[4] > box_b[5] + m || box_b[4] > box_a[5] + m);
  }

  // The mode of each arm this substep (needs ComputeAabbs). An object near the static scene or
  // another object is supported: an arm near it, or near the static scene, is simulated, so
  // that what it presses on pushes back through its effort-limited motors. An arm near only
  // unsupported objects (what it holds in the air) grips them with simulated fingers.
  std::array<ArmMode, 2> ArmModes() {
    const size_t n = all_geoms.size();
    object_supported.assign(n, 0);
    for (size_t i = 0; i < n; ++i) {
      if (dGeomGetCategoryBits(all_geoms[i]) != kObjectBit || !dGeomIsEnabled(all_geoms[i])) continue;
      for (size_t j = 0; j < n && !object_supported[i]; ++j) {
        if (j == i || (dGeomGetCategoryBits(all_geoms[j]) & (kObjectBit | kStaticBit)) == 0) continue;
        if (dGeomIsEnabled(all_geoms[j]) && Near(i, j)) object_supported[i] = 1;
      }
    }
    std::array<ArmMode, 2> modes{};
    for (int side = 0; side < 2; ++side) {
      ArmMode mode = ArmMode::kKinematic;
      for (int a : arms[side].geoms) {
        for (size_t j = 0; j < n && mode != ArmMode::kSimulated; ++j) {
          const unsigned long category = dGeomGetCategoryBits(all_geoms[j]);
          if ((category & (kObjectBit | kStaticBit)) == 0 || !dGeomIsEnabled(all_geoms[j]) || !Near(a, j)) continue;
          mode = (category == kObjectBit && !object_supported[j]) ? ArmMode::kGrip : ArmMode::kSimulated;
        }
      }
      modes[side] = mode;
    }
    return modes;
  }

  // Kinematic bodies leave the solver: infinite mass, their joints off. Joint positions and
  // finger slides are taken from the simulation when they become kinematic; bodies simulated
  // again keep the velocities their kinematic motion gave them.
  void SetArmMode(int side, ArmMode mode) {
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

  // The poses of a kinematic arm's bodies (links, and fingers if kinematic) at q_kinematic and
  // its finger slides, into X_WBody.
  void KinematicArmPoses(int side, std::vector<RigidTransform>& X_WBody) {
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

  // The kinematic servo: joints (and finger slides if kinematic) move at their servo velocities
  // for dt, exactly, where a simulated arm's motion is bounded by its motors' effort. Sets the
  // kinematic bodies' velocities toward their new poses (in next_poses), which Step places
  // after the solver step.
  void AdvanceKinematicArm(int side, const double* q_target, double closing_target, double dt,
                           std::vector<RigidTransform>& next_poses) {
    const RobotModel& robot = model.robot;
    ArmParts& arm = arms[side];
    for (int m : arm.motors) {
      const int j = motors[m].joint_index;
      const kinematics::Joint& joint = robot.joints[j];
      const double target = std::clamp(q_target[j], joint.lower, joint.upper);
      q_kinematic[j] += dt * std::clamp(robot.arm_actuator.position_gain * (target - q_kinematic[j]),
                                        -robot.arm_actuator.velocity_limit, robot.arm_actuator.velocity_limit);
    }
    if (arm.fingers_kinematic()) {
      const double max_finger_speed = gripper.spec().max_speed;
      for (double& closing : arm.closing) {
        closing += dt * std::clamp(kFingerServoGain * (closing_target - closing), -max_finger_speed, max_finger_speed);
      }
    }
    KinematicArmPoses(side, next_poses);
    const size_t kinematic_bodies = arm.fingers_kinematic() ? arm.bodies.size() : arm.links.size();
    for (size_t i = 0; i < kinematic_bodies; ++i) SetBodyMotion(arm.bodies[i], BodyPose(arm.bodies[i]), next_poses[i], dt);
  }

  // Broad phase over all geom pairs in creation order. ODE's spaces move each geom that moved
  // to the front of their lists, so the order of contact pairs (and, through floating-point
  // summation order, the solution) would depend on the world's past episodes; a fixed order
  // makes an episode depend on its own inputs only. A few dozen geoms make this cheap.
  // Needs ComputeAabbs.
  void CollideAllPairs() {
    const size_t n = all_geoms.size();
    for (size_t i = 0; i < n; ++i) {
      dGeomID a = all_geoms[i];
      if (!dGeomIsEnabled(a)) continue;
      const double* box_a = &aabbs[6 * i];
      for (size_t j = i + 1; j < n; ++j) {
        dGeomID b = all_geoms[j];
        if (!dGeomIsEnabled(b)) continue;
        if (!(dGeomGetCategoryBits(a) & dGeomGetCollideBits(b)) && !(dGeomGetCategoryBits(b) & dGeomGetCollideBits(a))) continue;
        const double* box_b = &aabbs[6 * j];
        if (box_a[0] > box_b[1] || box_b[0] > box_a[1] || box_a[2] > box_b[3] || box_b[2] > box_a[3] ||
            box_a[4] > box_b[5] || box_b[4] > box_a[5]) {
          continue;
        }
        Collide(a, b);
      }
    }
  }

  bool BodiesAreSane() const {
    const double max_linear = model.physics.runaway_linear_speed;
    const double max_angular = model.physics.runaway_angular_speed;
    for (dBodyID body : all_bodies) {
      const dReal* p = dBodyGetPosition(body);
      const dReal* v = dBodyGetLinearVel(body);
      const dReal* w = dBodyGetAngularVel(body);
      const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      const double spin = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
      if (!std::isfinite(p[0] + p[1] + p[2]) || !(speed < max_linear) || !(spin < max_angular)) return false;
    }
    return true;
  }
};

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
  s.aabbs.resize(6 * s.all_geoms.size());
  s.CollectArmParts();
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
          const double velocity = std::clamp(robot.arm_actuator.position_gain * error,
                                             -robot.arm_actuator.velocity_limit, robot.arm_actuator.velocity_limit);
          dJointSetHingeParam(motor.joint, dParamVel, velocity);
        }
      }
      if (arm.fingers_kinematic()) continue;
      for (Finger& finger : s.fingers[side]) {
        const double error = closing_target - dJointGetSliderPosition(finger.slider);
        dJointSetSliderParam(finger.slider, dParamVel,
                             std::clamp(kFingerServoGain * error, -max_finger_speed, max_finger_speed));
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
      q[motor.joint_index] = arm.links_kinematic() ? s.q_kinematic[motor.joint_index] : dJointGetHingeAngle(motor.joint);
    }
    gripper_gap[side] = arm.fingers_kinematic() ? s.gripper.GapFromClosing(arm.closing[0], arm.closing[1])
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
