#include "bench/peer/mujoco_physics.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <mujoco/mujoco.h>

#include "engine/batch_state.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/gripper_geometry.h"
#include "kinematics/servo.h"

namespace tavis::peer {
namespace {

// Mirrors of engine/internal/world_building.cc's private constants, so both engines get the same
// bodies (the finger servo's gain is kinematics/servo.h's).
constexpr double kRobotInertiaRadius = 0.05;    // robot bodies: inertia of a sphere of this radius
constexpr double kHingeStopClearance = 0.02;    // rad
constexpr double kSliderStopClearance = 0.002;  // m
constexpr double kPadTorsionRadius = 0.01;      // m, ODE's rolling-friction radius on pads
// An ODE motor reaches its velocity target within its force limit in one step; a MuJoCo velocity
// actuator approaches it with gain kv. These make full effort flow at a small velocity error.
constexpr double kArmVelocityErrorAtFullEffort = 0.5;     // rad/s
constexpr double kFingerVelocityErrorAtFullForce = 0.05;  // m/s
// Contact filtering as in the ODE world: robot <-> objects and static; objects <-> everything.
constexpr int kRobotBit = 1;
constexpr int kObjectBit = 2;
constexpr int kStaticBit = 4;

enum class LinkRole { kStatic, kArmBody, kNeck };

std::string Vec(const Vec3& v) {
  std::ostringstream s;
  s.precision(9);
  s << v.x() << ' ' << v.y() << ' ' << v.z();
  return s.str();
}

std::string PoseAttributes(const RigidTransform& X) {
  const Quat q(X.linear());
  std::ostringstream s;
  s.precision(9);
  s << "pos=\"" << Vec(X.translation()) << "\" quat=\"" << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << '"';
  return s.str();
}

// MuJoCo sizes: half extents (box), radius and half length (cylinder, capsule), radius (sphere).
std::string GeomShape(const Shape& shape) {
  std::ostringstream s;
  s.precision(9);
  switch (shape.kind) {
    case ShapeKind::kBox: s << "type=\"box\" size=\"" << Vec(0.5 * shape.size) << '"'; break;
    case ShapeKind::kCylinder:
      s << "type=\"cylinder\" size=\"" << shape.Radius() << ' ' << 0.5 * shape.Length() << '"';
      break;
    case ShapeKind::kCapsule:
      s << "type=\"capsule\" size=\"" << shape.Radius() << ' ' << 0.5 * shape.Length() << '"';
      break;
    case ShapeKind::kSphere: s << "type=\"sphere\" size=\"" << shape.Radius() << '"'; break;
  }
  return s.str();
}

std::string Filter(int type, int affinity) {
  return "contype=\"" + std::to_string(type) + "\" conaffinity=\"" + std::to_string(affinity) + '"';
}

std::string SphereInertial(double mass) {
  const double inertia = 0.4 * mass * kRobotInertiaRadius * kRobotInertiaRadius;
  std::ostringstream s;
  s.precision(9);
  s << "<inertial pos=\"0 0 0\" mass=\"" << mass << "\" diaginertia=\"" << inertia << ' ' << inertia << ' ' << inertia
    << "\"/>";
  return s.str();
}

struct RobotLayout {
  std::vector<LinkRole> role;        // [link]
  std::vector<int> owner;            // [link] the arm body link that carries it, -1 if none
  std::vector<RigidTransform> X_WL;  // [link] at q = 0
};

// The same roles as the ODE world: arm-joint links are bodies, fixed links ride on their parent's
// body, the neck is not simulated, everything else is static.
RobotLayout LayOut(const kinematics::RobotModel& robot) {
  RobotLayout layout;
  std::vector<bool> arm_joint(static_cast<std::size_t>(robot.num_joints()), false);
  for (const kinematics::ArmSpec& arm : robot.arms) {
    for (int j : arm.joints) arm_joint[static_cast<std::size_t>(j)] = true;
  }
  const int n = robot.num_links();
  layout.role.assign(static_cast<std::size_t>(n), LinkRole::kStatic);
  layout.owner.assign(static_cast<std::size_t>(n), -1);
  for (int i = 0; i < n; ++i) {
    const kinematics::Link& link = robot.links[static_cast<std::size_t>(i)];
    const LinkRole parent_role =
        link.parent < 0 ? LinkRole::kStatic : layout.role[static_cast<std::size_t>(link.parent)];
    LinkRole& role = layout.role[static_cast<std::size_t>(i)];
    if (link.joint >= 0) {
      role = arm_joint[static_cast<std::size_t>(link.joint)] ? LinkRole::kArmBody : LinkRole::kNeck;
      if (parent_role == LinkRole::kNeck) role = LinkRole::kNeck;
      if (role == LinkRole::kArmBody) layout.owner[static_cast<std::size_t>(i)] = i;
    } else {
      role = parent_role;
      if (parent_role == LinkRole::kArmBody)
        layout.owner[static_cast<std::size_t>(i)] = layout.owner[static_cast<std::size_t>(link.parent)];
    }
  }
  std::vector<RigidTransform> X_BL(static_cast<std::size_t>(n));
  const std::vector<double> zeros(static_cast<std::size_t>(robot.num_joints()), 0.0);
  kinematics::ComputeLinkPoses(robot, zeros.data(), X_BL.data());
  const RigidTransform X_WB = MakeTransform(robot.root_world, Mat3::Identity());
  for (const RigidTransform& X : X_BL) layout.X_WL.push_back(X_WB * X);
  return layout;
}

std::string MaterialFriction(const engine::WorldModel& model, engine::Material material) {
  std::ostringstream s;
  s << "friction=\"" << model.materials.Friction(material) << " 0.005 0.0001\"";
  return s.str();
}

}  // namespace

// long: one MJCF document, written top to bottom in the order of its XML; split into parts, each
// would take the same robot layout and stream and only hide where in the document it writes.
std::string PhysicsMjcf(const engine::WorldModel& model, bool sparse_jacobian) {
  const kinematics::RobotModel& robot = model.robot;
  const kinematics::GripperGeometry gripper(robot.gripper);
  const kinematics::GripperSpec& g = gripper.spec();
  const RobotLayout layout = LayOut(robot);
  const std::string robot_filter = Filter(kRobotBit, kObjectBit | kStaticBit);
  const std::string static_filter = Filter(kStaticBit, kRobotBit | kObjectBit);
  // ODE averages the two materials' friction, MuJoCo takes the larger: pads carry the average of
  // pad and object friction, so a pad-object pair gets ODE's value.
  const double pad_friction = 0.5 * (model.materials.Friction(engine::Material::kFingerPad) +
                                     model.materials.Friction(engine::Material::kObject));

  std::ostringstream xml;
  xml.precision(9);
  xml << "<mujoco model=\"tavis_peer\">\n";
  xml << "  <compiler angle=\"radian\" inertiafromgeom=\"auto\"/>\n";
  xml << "  <option timestep=\"" << 1.0 / model.physics.substep_hz << "\" gravity=\"0 0 " << model.physics.gravity
      << "\" integrator=\"implicit\" cone=\"elliptic\" impratio=\"10\" jacobian=\""
      << (sparse_jacobian ? "sparse" : "dense") << "\"/>\n";
  xml << "  <size njmax=\"3000\" nconmax=\"600\"/>\n";
  xml << "  <default><geom solref=\"0.01 1\"/></default>\n";
  xml << "  <worldbody>\n";
  xml << "    <geom name=\"floor\" type=\"plane\" size=\"0 0 1\" " << static_filter << ' '
      << MaterialFriction(model, engine::Material::kDefault) << "/>\n";
  for (const engine::StaticPart& part : model.static_parts) {
    if (!part.collides) continue;
    xml << "    <geom " << GeomShape(part.shape) << ' ' << PoseAttributes(part.X_WS) << ' ' << static_filter << ' '
        << MaterialFriction(model, part.material) << "/>\n";
  }
  const RigidTransform X_WB = MakeTransform(robot.root_world, Mat3::Identity());
  for (const kinematics::LinkShape& s : robot.shapes) {
    const bool on_base = s.link == kinematics::kBaseLink;
    if (!on_base && layout.role[static_cast<std::size_t>(s.link)] != LinkRole::kStatic) continue;
    const RigidTransform X_WS = on_base ? X_WB * s.X_LS : layout.X_WL[static_cast<std::size_t>(s.link)] * s.X_LS;
    xml << "    <geom " << GeomShape(s.shape) << ' ' << PoseAttributes(X_WS) << ' ' << robot_filter << ' '
        << MaterialFriction(model, engine::Material::kRobot) << "/>\n";
  }

  // Arm bodies, nested as in the tree.
  std::function<void(int, const RigidTransform&, int)> emit_body = [&](int link, const RigidTransform& X_W_parent,
                                                                       int depth) {
    const std::string indent(static_cast<std::size_t>(2 * depth + 4), ' ');
    const RigidTransform& X_WL = layout.X_WL[static_cast<std::size_t>(link)];
    const kinematics::Link& l = robot.links[static_cast<std::size_t>(link)];
    const kinematics::Joint& joint = robot.joints[static_cast<std::size_t>(l.joint)];
    xml << indent << "<body name=\"" << l.name << "\" " << PoseAttributes(X_W_parent.inverse() * X_WL) << ">\n";
    xml << indent << "  " << SphereInertial(l.mass) << "\n";
    xml << indent << "  <joint name=\"" << joint.name << "\" type=\"hinge\" axis=\"" << Vec(joint.axis)
        << "\" limited=\"true\" range=\"" << joint.lower - kHingeStopClearance << ' '
        << joint.upper + kHingeStopClearance << "\"/>\n";
    for (const kinematics::LinkShape& s : robot.shapes) {
      if (s.link == kinematics::kBaseLink || layout.owner[static_cast<std::size_t>(s.link)] != link) continue;
      xml << indent << "  <geom " << GeomShape(s.shape) << ' '
          << PoseAttributes(X_WL.inverse() * layout.X_WL[static_cast<std::size_t>(s.link)] * s.X_LS) << ' '
          << robot_filter << ' ' << MaterialFriction(model, engine::Material::kRobot) << "/>\n";
    }
    for (kinematics::Side side : kinematics::kSides) {
      const int ik_link = robot.arm(side).ik_link;
      if (layout.owner[static_cast<std::size_t>(ik_link)] != link) continue;
      const RigidTransform X_BodyIk = X_WL.inverse() * layout.X_WL[static_cast<std::size_t>(ik_link)];
      xml << indent << "  <geom " << GeomShape({ShapeKind::kBox, g.housing_size}) << ' '
          << PoseAttributes(X_BodyIk * gripper.X_IkHousing()) << ' ' << robot_filter << ' '
          << MaterialFriction(model, engine::Material::kRobot) << "/>\n";
      for (int f = 0; f < 2; ++f) {
        const double sign = kinematics::kJawSigns[static_cast<std::size_t>(f)];
        const RigidTransform X_BodyPad = X_BodyIk * gripper.X_IkPad(sign, g.open_gap);
        const Vec3 inward_in_pad = X_BodyPad.linear().transpose() * (-sign * (X_BodyIk.linear() * g.closing_axis));
        const std::string name =
            std::string(side == kinematics::Side::kLeft ? "left" : "right") + "_finger" + std::to_string(f);
        xml << indent << "  <body name=\"" << name << "\" " << PoseAttributes(X_BodyPad) << ">\n";
        xml << indent << "    " << SphereInertial(g.finger_mass) << "\n";
        xml << indent << "    <joint name=\"" << name << "\" type=\"slide\" axis=\"" << Vec(inward_in_pad)
            << "\" limited=\"true\" range=\"" << -kSliderStopClearance << ' '
            << gripper.finger_travel() + kSliderStopClearance << "\"/>\n";
        xml << indent << "    <geom " << GeomShape({ShapeKind::kBox, g.pad_size}) << ' ' << robot_filter
            << " condim=\"4\" friction=\"" << pad_friction << ' ' << pad_friction * kPadTorsionRadius
            << " 0.0001\"/>\n";
        xml << indent << "  </body>\n";
      }
    }
    for (int child = 0; child < robot.num_links(); ++child) {
      const kinematics::Link& c = robot.links[static_cast<std::size_t>(child)];
      if (layout.owner[static_cast<std::size_t>(child)] == child && c.parent >= 0 &&
          layout.owner[static_cast<std::size_t>(c.parent)] == link) {
        emit_body(child, X_WL, depth + 1);
      }
    }
    xml << indent << "</body>\n";
  };
  for (int i = 0; i < robot.num_links(); ++i) {
    const kinematics::Link& l = robot.links[static_cast<std::size_t>(i)];
    const bool root_body = layout.owner[static_cast<std::size_t>(i)] == i &&
                           (l.parent < 0 || layout.owner[static_cast<std::size_t>(l.parent)] < 0);
    if (root_body) emit_body(i, RigidTransform::Identity(), 0);
  }

  for (const engine::ObjectSpec& object : model.objects) {
    const std::string filter = object.collides ? Filter(kObjectBit, kRobotBit | kObjectBit | kStaticBit) : Filter(0, 0);
    if (object.motion == engine::ObjectMotion::kKinematic) {
      xml << "    <body name=\"" << object.name << "\" mocap=\"true\">\n";
      xml << "      <geom " << GeomShape(object.shape) << ' ' << filter << ' '
          << MaterialFriction(model, object.material) << "/>\n";
    } else {
      xml << "    <body name=\"" << object.name << "\">\n      <freejoint/>\n";
      xml << "      <geom " << GeomShape(object.shape) << " mass=\"" << object.mass << "\" " << filter << ' '
          << MaterialFriction(model, object.material) << "/>\n";
    }
    xml << "    </body>\n";
  }
  xml << "  </worldbody>\n  <actuator>\n";
  for (const kinematics::ArmSpec& arm : robot.arms) {
    for (int j : arm.joints) {
      const double effort = robot.arm_actuator.effort_limit;
      xml << "    <velocity joint=\"" << robot.joints[static_cast<std::size_t>(j)].name << "\" kv=\""
          << effort / kArmVelocityErrorAtFullEffort << "\" forcelimited=\"true\" forcerange=\"" << -effort << ' '
          << effort << "\"/>\n";
    }
  }
  for (const char* side : {"left", "right"}) {
    for (int f = 0; f < 2; ++f) {
      xml << "    <velocity joint=\"" << side << "_finger" << f << "\" kv=\""
          << g.max_force / kFingerVelocityErrorAtFullForce << "\" forcelimited=\"true\" forcerange=\"" << -g.max_force
          << ' ' << g.max_force << "\"/>\n";
    }
  }
  xml << "  </actuator>\n</mujoco>\n";
  return xml.str();
}

struct MujocoPhysics::Impl {
  const engine::WorldModel& world;
  kinematics::GripperGeometry gripper;
  mjModel* model = nullptr;
  std::vector<mjData*> data;
  std::vector<int> arm_qpos;                        // [actuator] qpos address of arm joint actuator a
  std::vector<int> arm_joint;                       // [actuator] our joint index
  std::array<std::array<int, 2>, 2> finger_qpos{};  // [side][jaw]
  std::vector<int> object_body;                     // [object]
  std::vector<int> object_qpos;                     // [object] free-joint qpos address, -1 for mocap
  std::vector<int> robot_bodies;                    // gravity-free bodies

  Impl(const engine::WorldModel& w, int num_envs, bool sparse) : world(w), gripper(w.robot.gripper) {
    const std::string xml = PhysicsMjcf(w, sparse);
    mjVFS vfs;
    mj_defaultVFS(&vfs);
    mj_makeEmptyFileVFS(&vfs, "peer.xml", static_cast<int>(xml.size()));
    std::memcpy(vfs.filedata[mj_findFileVFS(&vfs, "peer.xml")], xml.data(), xml.size());
    char error[1000] = "";
    model = mj_loadXML("peer.xml", &vfs, error, sizeof(error));
    mj_deleteVFS(&vfs);
    if (model == nullptr) throw std::runtime_error(std::string("MuJoCo rejected the peer model: ") + error);
    const kinematics::RobotModel& robot = w.robot;
    for (const kinematics::ArmSpec& arm : robot.arms) {
      for (int j : arm.joints) {
        const int id = mj_name2id(model, mjOBJ_JOINT, robot.joints[static_cast<std::size_t>(j)].name.c_str());
        arm_qpos.push_back(model->jnt_qposadr[id]);
        arm_joint.push_back(j);
      }
    }
    for (int s = 0; s < 2; ++s) {
      for (int f = 0; f < 2; ++f) {
        const std::string name = std::string(s == 0 ? "left" : "right") + "_finger" + std::to_string(f);
        finger_qpos[static_cast<std::size_t>(s)][static_cast<std::size_t>(f)] =
            model->jnt_qposadr[mj_name2id(model, mjOBJ_JOINT, name.c_str())];
      }
    }
    for (const engine::ObjectSpec& object : w.objects) {
      const int body = mj_name2id(model, mjOBJ_BODY, object.name.c_str());
      object_body.push_back(body);
      object_qpos.push_back(model->body_jntnum[body] > 0 ? model->jnt_qposadr[model->body_jntadr[body]] : -1);
    }
    for (int b = 1; b < model->nbody; ++b) {
      if (std::find(object_body.begin(), object_body.end(), b) == object_body.end()) robot_bodies.push_back(b);
    }
    for (int e = 0; e < num_envs; ++e) data.push_back(mj_makeData(model));
  }
  ~Impl() {
    for (mjData* d : data) mj_deleteData(d);
    mj_deleteModel(model);
  }
};

MujocoPhysics::MujocoPhysics(const engine::WorldModel& model, int num_envs, bool sparse_jacobian)
    : impl_(std::make_unique<Impl>(model, num_envs, sparse_jacobian)) {}

MujocoPhysics::~MujocoPhysics() = default;

void MujocoPhysics::Reset(int env, const EpisodeTrajectory& episode) {
  Impl& s = *impl_;
  mjData* d = s.data[static_cast<std::size_t>(env)];
  mj_resetData(s.model, d);
  for (std::size_t a = 0; a < s.arm_qpos.size(); ++a) {
    d->qpos[s.arm_qpos[a]] = episode.q0[static_cast<std::size_t>(s.arm_joint[a])];
  }
  for (std::size_t o = 0; o < s.object_body.size(); ++o) {
    const double* pose = &episode.object_pose0[o * engine::kObjectPoseSize];
    double* target = s.object_qpos[o] >= 0 ? d->qpos + s.object_qpos[o] : nullptr;
    if (target == nullptr) {
      const int mocap = s.model->body_mocapid[s.object_body[o]];
      std::copy(pose, pose + 3, d->mocap_pos + 3 * mocap);
      std::copy(pose + 3, pose + 7, d->mocap_quat + 4 * mocap);
    } else {
      std::copy(pose, pose + 7, target);
    }
    if (episode.object_enabled[o] == 0 && target != nullptr) {
      // A disabled object leaves the scene: parked far away, high up, where it falls alone.
      target[0] = 1000.0 + 10.0 * static_cast<double>(o);
      target[2] = 1000.0;
    }
  }
  // Robot bodies are gravity-free in the reference: an applied force cancels their weight.
  const double g = -s.world.physics.gravity;
  for (int b : s.robot_bodies) d->xfrc_applied[6 * b + 2] = s.model->body_mass[b] * g;
  mj_forward(s.model, d);
}

void MujocoPhysics::StepTick(int env, const EpisodeTrajectory& episode, int tick) {
  Impl& s = *impl_;
  mjData* d = s.data[static_cast<std::size_t>(env)];
  const kinematics::RobotModel& robot = s.world.robot;
  const int nj = robot.num_joints();
  const double* q_target = &episode.q_target[static_cast<std::size_t>(tick) * static_cast<std::size_t>(nj)];
  const double* command = &episode.gripper_command[static_cast<std::size_t>(tick) * 2];
  const double max_finger_speed = s.gripper.spec().max_speed;
  const int fingers = static_cast<int>(s.arm_qpos.size());
  for (int step = 0; step < s.world.physics.substeps_per_control(); ++step) {
    for (std::size_t a = 0; a < s.arm_qpos.size(); ++a) {
      const kinematics::Joint& joint = robot.joints[static_cast<std::size_t>(s.arm_joint[a])];
      const double target = std::clamp(q_target[s.arm_joint[a]], joint.lower, joint.upper);
      d->ctrl[a] = kinematics::JointServoVelocity(robot.arm_actuator, target - d->qpos[s.arm_qpos[a]]);
    }
    for (int side = 0; side < 2; ++side) {
      const double closing = s.gripper.ClosingTarget(command[side]);
      for (int f = 0; f < 2; ++f) {
        const double error =
            closing - d->qpos[s.finger_qpos[static_cast<std::size_t>(side)][static_cast<std::size_t>(f)]];
        d->ctrl[fingers + 2 * side + f] =
            kinematics::ServoVelocity(kinematics::kFingerServoGain, error, max_finger_speed);
      }
    }
    mj_step(s.model, d);
  }
}

void MujocoPhysics::ObjectPosition(int env, int object, double* xyz) const {
  const mjData* d = impl_->data[static_cast<std::size_t>(env)];
  std::copy(d->xpos + 3 * impl_->object_body[static_cast<std::size_t>(object)],
            d->xpos + 3 * impl_->object_body[static_cast<std::size_t>(object)] + 3, xyz);
}

}  // namespace tavis::peer
