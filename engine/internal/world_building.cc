// PhysicsWorld's bodies, joints and geoms, built once from the WorldModel: the arms' links as
// hinged bodies, the grippers' sliding fingers, the objects and the static scene.
#include <algorithm>
#include <vector>

#include <ode/ode.h>

#include "engine/internal/physics_world_impl.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/invariant.h"

namespace tavis::engine {

using internal::ArmParts;
using internal::BodyPose;
using internal::Finger;
using internal::kObjectBit;
using internal::kRobotBit;
using internal::kStaticBit;
using internal::LinkRole;
using internal::SetBodyPose;
using internal::SetStaticGeomPose;
using kinematics::RobotModel;
using kinematics::Side;

namespace {

// Robot bodies (links and fingers) get the inertia of a sphere of this radius: a pad's true
// inertia is tiny next to the arm's, and that ratio stalls the solver (the fingers chatter).
constexpr double kRobotInertiaRadius = 0.05;  // m
constexpr int kOdeAxisZ = 3;                  // ODE's code for a body's local z axis, Shape's long axis
// Joint stops sit this far outside the limits the servo targets respect. A joint driven by its
// motor while resting on a stop gets ODE's stop/motor fallback, a full-force impulse for one
// step (scaled by the fudge factor), which kicked wrists by 0.1-0.2 rad and fingers by 2 cm
// mid-grasp. Servoed within its limits a joint never reaches the stops; they remain hard limits.
constexpr double kHingeStopClearance = 0.02;    // rad
constexpr double kSliderStopClearance = 0.002;  // m

void SetGeomOffset(dGeomID geom, const RigidTransform& X_BG) {
  dGeomSetOffsetPosition(geom, X_BG.translation().x(), X_BG.translation().y(), X_BG.translation().z());
  const Quat q(X_BG.linear());
  const dQuaternion ode_q = {q.w(), q.x(), q.y(), q.z()};
  dGeomSetOffsetQuaternion(geom, ode_q);
}

void SetMass(dBodyID body, const Shape& shape, double mass) {
  dMass m;
  switch (shape.kind) {
    case ShapeKind::kBox: dMassSetBoxTotal(&m, mass, shape.size.x(), shape.size.y(), shape.size.z()); break;
    case ShapeKind::kCylinder: dMassSetCylinderTotal(&m, mass, kOdeAxisZ, shape.Radius(), shape.Length()); break;
    case ShapeKind::kCapsule: dMassSetCapsuleTotal(&m, mass, kOdeAxisZ, shape.Radius(), shape.Length()); break;
    case ShapeKind::kSphere: dMassSetSphereTotal(&m, mass, shape.Radius()); break;
    case ShapeKind::kPlane: TAVIS_INVARIANT(false, "a plane has no mass: bodies are solids"); break;
  }
  dBodySetMass(body, &m);
}

}  // namespace

void PhysicsWorld::Impl::ClassifyLinks() {
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

void PhysicsWorld::Impl::BuildRobot() {
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

void PhysicsWorld::Impl::BuildGripper(kinematics::Side side, const RigidTransform& X_WB) {
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

void PhysicsWorld::Impl::BuildObjects() {
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

void PhysicsWorld::Impl::BuildStaticScene() {
  for (const StaticPart& part : model.static_parts) {
    if (!part.collides) continue;
    dGeomID geom = CreateGeom(space, part.shape);
    Tag(geom, part.material, kStaticBit, kRobotBit | kObjectBit);
    SetStaticGeomPose(geom, part.X_WS);
  }
  dGeomID ground = dCreatePlane(space, 0, 0, 1, 0);
  Tag(ground, Material::kDefault, kStaticBit, kRobotBit | kObjectBit);
}

void PhysicsWorld::Impl::CollectArmParts() {
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

void PhysicsWorld::Impl::BuildBroadPhase() {
  std::vector<internal::BroadPhaseGeom> geoms;
  for (dGeomID geom : all_geoms) {
    geoms.push_back({dGeomGetCategoryBits(geom), dGeomGetCollideBits(geom), dGeomGetBody(geom) != nullptr,
                     dGeomGetClass(geom) == dPlaneClass});
  }
  candidate_pairs.emplace(geoms);
  arm_proximity.emplace(geoms, std::array<std::vector<int>, 2>{arms[0].geoms, arms[1].geoms});
  aabbs.resize(6 * all_geoms.size());
  geom_enabled.resize(all_geoms.size());
}

dBodyID PhysicsWorld::Impl::NewBody() {
  all_bodies.push_back(dBodyCreate(world));
  return all_bodies.back();
}

dGeomID PhysicsWorld::Impl::CreateGeom(dSpaceID geom_space, const Shape& shape) {
  switch (shape.kind) {
    case ShapeKind::kBox: return dCreateBox(geom_space, shape.size.x(), shape.size.y(), shape.size.z());
    case ShapeKind::kCylinder: {
      // The circumscribed square prism: see CreateGeom's note (physics_world_impl.h).
      const double side = 2.0 * shape.Radius();
      return dCreateBox(geom_space, side, side, shape.Length());
    }
    case ShapeKind::kCapsule: return dCreateCapsule(geom_space, shape.Radius(), shape.Length());
    case ShapeKind::kSphere: return dCreateSphere(geom_space, shape.Radius());
    case ShapeKind::kPlane: TAVIS_INVARIANT(false, "a plane is not a body's geom: the floor is ODE's plane"); break;
  }
  return nullptr;
}

internal::GeomInfo* PhysicsWorld::Impl::NewGeomInfo(Material material) {
  geom_infos.push_back({material});
  return &geom_infos.back();
}

void PhysicsWorld::Impl::Tag(dGeomID geom, Material material, unsigned long category, unsigned long collides_with) {
  all_geoms.push_back(geom);
  dGeomSetData(geom, NewGeomInfo(material));
  dGeomSetCategoryBits(geom, category);
  dGeomSetCollideBits(geom, collides_with);
}

}  // namespace tavis::engine
