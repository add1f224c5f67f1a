#include "configs/robot_config.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include "configs/yaml_reader.h"

namespace tavis::configs {
namespace {

using kinematics::RobotModel;

Quat ReadQuatWxyz(const YamlValue& value) {
  const std::vector<double> c = value.AsDoubles();
  if (c.size() != 4) value.Fail("expected a quaternion w, x, y, z");
  const Quat q(c[0], c[1], c[2], c[3]);
  if (std::abs(q.norm() - 1.0) > 1e-3) value.Fail("quaternion is not normalised");
  return q.normalized();
}

RigidTransform ReadXyzRpy(const YamlValue& entry) {
  return TransformFromXyzRpy(entry.Vector3("xyz"), entry.Vector3("rpy"));
}

// Adds a link and returns its index; the parent must already be known (parents-first order).
int AddLink(RobotModel& robot, std::map<std::string, int>& link_index, const YamlValue& entry,
            const std::string& name, const std::string& parent) {
  if (link_index.count(name)) entry.Fail("link '" + name + "' is defined twice");
  kinematics::Link link;
  link.name = name;
  if (parent != "base_link") {
    auto it = link_index.find(parent);
    if (it == link_index.end()) entry.Fail("parent link '" + parent + "' is not defined before it");
    link.parent = it->second;
  }
  robot.links.push_back(link);
  link_index[name] = robot.num_links() - 1;
  return robot.num_links() - 1;
}

int LookUp(const std::map<std::string, int>& index, const std::string& name, const YamlValue& where,
           const char* what) {
  auto it = index.find(name);
  if (it == index.end()) where.Fail(std::string("unknown ") + what + " '" + name + "'");
  return it->second;
}

void ReadFramesAndJoints(const YamlValue& root, RobotModel& robot, std::map<std::string, int>& link_index) {
  link_index["base_link"] = -1;
  // Frames may hang below joint links, so both lists are merged in dependency order: a frame
  // is added as soon as its parent exists.
  std::vector<YamlValue> pending_frames = root.Required("frames").Elements();
  auto add_ready_frames = [&]() {
    for (bool progress = true; progress;) {
      progress = false;
      for (auto it = pending_frames.begin(); it != pending_frames.end();) {
        const std::string parent = it->String("parent");
        if (link_index.count(parent) == 0) {
          ++it;
          continue;
        }
        const int link = AddLink(robot, link_index, *it, it->String("name"), parent);
        robot.links[link].origin = ReadXyzRpy(*it);
        it->ExpectNoOtherKeys();
        it = pending_frames.erase(it);
        progress = true;
      }
    }
  };
  add_ready_frames();
  for (const YamlValue& entry : root.Required("joints").Elements()) {
    kinematics::Joint joint;
    joint.name = entry.String("name");
    const int link = AddLink(robot, link_index, entry, entry.String("child"), entry.String("parent"));
    robot.links[link].origin = ReadXyzRpy(entry);
    robot.links[link].mass = entry.Double("mass");
    robot.links[link].joint = robot.num_joints();
    joint.link = link;
    joint.axis = entry.Vector3("axis").normalized();
    joint.lower = entry.Double("lower");
    joint.upper = entry.Double("upper");
    joint.default_position = entry.Double("default");
    if (joint.lower > joint.upper) entry.Fail("lower limit above upper limit");
    if (joint.default_position < joint.lower || joint.default_position > joint.upper) {
      entry.Required("default").Fail("default position outside the joint limits");
    }
    entry.ExpectNoOtherKeys();
    robot.joints.push_back(joint);
    add_ready_frames();
  }
  if (!pending_frames.empty()) {
    pending_frames.front().Fail("parent link '" + pending_frames.front().String("parent") + "' is never defined");
  }
}

kinematics::ActuatorLimits ReadActuator(const YamlValue& entry) {
  kinematics::ActuatorLimits limits;
  limits.velocity_limit = entry.Double("velocity_limit");
  limits.effort_limit = entry.Double("effort_limit");
  limits.position_gain = entry.Double("position_gain");
  entry.ExpectNoOtherKeys();
  return limits;
}

kinematics::LinkShape ReadShape(const YamlValue& entry, const std::map<std::string, int>& link_index) {
  kinematics::LinkShape shape;
  shape.link = LookUp(link_index, entry.String("link"), entry, "link");
  const std::string kind = entry.String("kind");
  if (kind == "box") {
    shape.shape = {ShapeKind::kBox, entry.Vector3("size")};
    shape.X_LS.translation() = entry.Vector3("center");
  } else if (kind == "cylinder") {
    const double radius = entry.Double("radius");
    shape.shape = {ShapeKind::kCylinder, Vec3(radius, radius, entry.Double("height"))};
    shape.X_LS.translation() = entry.Vector3("center");
  } else if (kind == "capsule") {
    const Vec3 a = entry.Vector3("a");
    const Vec3 b = entry.Vector3("b");
    const double radius = entry.Double("radius");
    const double length = (b - a).norm();
    shape.shape = {ShapeKind::kCapsule, Vec3(radius, radius, length)};
    shape.X_LS.translation() = 0.5 * (a + b);
    if (length > 1e-9) shape.X_LS.linear() = Quat::FromTwoVectors(Vec3::UnitZ(), (b - a) / length).toRotationMatrix();
  } else {
    entry.Required("kind").Fail("unknown shape kind '" + kind + "' (box, cylinder, capsule)");
  }
  entry.ExpectNoOtherKeys();
  return shape;
}

kinematics::GripperSpec ReadGripper(const YamlValue& entry) {
  kinematics::GripperSpec g;
  g.tcp = entry.Vector3("tcp_xyz");
  g.closing_axis = entry.Vector3("closing_axis").normalized();
  g.pad_size = entry.Vector3("pad_size");
  g.pad_center = entry.Vector3("pad_center_xyz");
  g.open_gap = entry.Double("open_gap");
  g.closed_gap = entry.Double("closed_gap");
  g.max_force = entry.Double("max_force");
  g.max_speed = entry.Double("max_speed");
  g.finger_mass = entry.Double("finger_mass");
  const YamlValue housing = entry.Required("housing");
  g.housing_center = housing.Vector3("center");
  g.housing_size = housing.Vector3("size");
  housing.ExpectNoOtherKeys();
  if (g.closed_gap > g.open_gap) entry.Fail("closed_gap exceeds open_gap");
  entry.ExpectNoOtherKeys();
  return g;
}

// observation_state: entries {joint: NAME}, {unsimulated: NAME, value: RAD} or {gripper_gap: SIDE};
// every simulated joint appears exactly once.
std::vector<kinematics::StateEntry> ReadObservationState(const YamlValue& list,
                                                         const std::map<std::string, int>& joint_index) {
  std::vector<kinematics::StateEntry> entries;
  std::set<int> joints_seen;
  for (const YamlValue& item : list.Elements()) {
    kinematics::StateEntry entry;
    const std::optional<YamlValue> joint = item.Optional("joint");
    const std::optional<YamlValue> unsimulated = item.Optional("unsimulated");
    const std::optional<YamlValue> gripper = item.Optional("gripper_gap");
    if (int(joint.has_value()) + int(unsimulated.has_value()) + int(gripper.has_value()) != 1) {
      item.Fail("an entry is one of {joint: NAME}, {unsimulated: NAME, value: RAD}, {gripper_gap: left|right}");
    }
    if (joint) {
      entry.kind = kinematics::StateEntry::Kind::kJoint;
      entry.name = joint->AsString();
      entry.joint = LookUp(joint_index, entry.name, *joint, "joint");
      if (!joints_seen.insert(entry.joint).second) joint->Fail("joint '" + entry.name + "' appears twice");
    } else if (unsimulated) {
      entry.kind = kinematics::StateEntry::Kind::kUnsimulated;
      entry.name = unsimulated->AsString();
      entry.value = item.Double("value");
    } else {
      entry.kind = kinematics::StateEntry::Kind::kGripperGap;
      const std::string side = gripper->AsString();
      if (side != "left" && side != "right") gripper->Fail("gripper_gap is left or right, got '" + side + "'");
      entry.side = side == "left" ? kinematics::Side::kLeft : kinematics::Side::kRight;
      entry.name = side + "_gripper_gap";
    }
    item.ExpectNoOtherKeys();
    entries.push_back(entry);
  }
  if (static_cast<int>(joints_seen.size()) != static_cast<int>(joint_index.size())) {
    list.Fail("every simulated joint must appear once; " + std::to_string(joint_index.size() - joints_seen.size()) +
              " are missing");
  }
  return entries;
}

}  // namespace

RobotModel LoadRobotModel(const std::string& path) {
  const YamlValue root = YamlValue::LoadFile(path);
  RobotModel robot;
  robot.name = root.String("name");
  robot.root_world = root.Vector3("root_world_xyz");
  robot.canonical_offset = root.Vector3("canonical_offset");

  std::map<std::string, int> link_index;
  ReadFramesAndJoints(root, robot, link_index);
  std::map<std::string, int> joint_index;
  for (int i = 0; i < robot.num_joints(); ++i) joint_index[robot.joints[i].name] = i;

  const YamlValue actuators = root.Required("actuators");
  robot.arm_actuator = ReadActuator(actuators.Required("arm"));
  robot.neck_actuator = ReadActuator(actuators.Required("neck"));
  actuators.ExpectNoOtherKeys();

  const YamlValue arms = root.Required("arms");
  const YamlValue rest = root.Required("rest_pose");
  for (kinematics::Side side : kinematics::kSides) {
    const YamlValue arm_entry = arms.Required(kinematics::Name(side));
    kinematics::ArmSpec& arm = robot.arms[kinematics::Index(side)];
    const YamlValue joints = arm_entry.Required("joints");
    const std::vector<std::string> names = joints.AsStrings();
    if (names.size() != kinematics::kArmDof) joints.Fail("an arm needs exactly 7 joints");
    for (int i = 0; i < kinematics::kArmDof; ++i) arm.joints[i] = LookUp(joint_index, names[i], joints, "joint");
    arm.ik_link = LookUp(link_index, arm_entry.String("ik_link"), arm_entry, "link");
    arm_entry.ExpectNoOtherKeys();

    const YamlValue rest_entry = rest.Required(kinematics::Name(side));
    arm.rest_pose_canonical = MakeTransform(rest_entry.Vector3("position"),
                                            ReadQuatWxyz(rest_entry.Required("quat_wxyz")).toRotationMatrix());
    rest_entry.ExpectNoOtherKeys();
  }
  arms.ExpectNoOtherKeys();
  rest.ExpectNoOtherKeys();

  const YamlValue neck = root.Required("neck");
  const YamlValue neck_joints = neck.Required("joints");
  const std::vector<std::string> neck_names = neck_joints.AsStrings();
  if (neck_names.size() != kinematics::kNeckDof) neck_joints.Fail("the neck needs roll, pitch, yaw joints");
  for (int i = 0; i < kinematics::kNeckDof; ++i) robot.neck_joints[i] = LookUp(joint_index, neck_names[i], neck_joints, "joint");
  neck.ExpectNoOtherKeys();

  const YamlValue ik = root.Required("ik");
  robot.ik_damping = ik.Double("damping");
  robot.nullspace_gain = ik.Double("nullspace_gain");
  ik.ExpectNoOtherKeys();

  robot.gripper = ReadGripper(root.Required("gripper"));
  robot.observation_state = ReadObservationState(root.Required("observation_state"), joint_index);

  for (const YamlValue& entry : root.Required("cameras").Elements()) {
    kinematics::CameraMount camera;
    camera.name = entry.String("name");
    camera.link = LookUp(link_index, entry.String("parent"), entry, "link");
    camera.X_LC = MakeTransform(entry.Vector3("xyz"), ReadQuatWxyz(entry.Required("quat_wxyz")).toRotationMatrix());
    camera.focal_length_mm = entry.Double("focal_length_mm");
    camera.near_m = entry.Double("near");
    camera.far_m = entry.Double("far");
    entry.ExpectNoOtherKeys();
    robot.cameras.push_back(camera);
  }
  for (const YamlValue& entry : root.Required("shapes").Elements()) robot.shapes.push_back(ReadShape(entry, link_index));
  root.ExpectNoOtherKeys();
  return robot;
}

std::vector<std::string> KnownRobots(const std::string& config_dir) {
  std::vector<std::string> robots;
  const std::filesystem::path dir = std::filesystem::path(config_dir) / "robots";
  if (!std::filesystem::is_directory(dir)) return robots;
  for (const auto& file : std::filesystem::directory_iterator(dir)) {
    if (file.path().extension() == ".yaml") robots.push_back(file.path().stem().string());
  }
  std::sort(robots.begin(), robots.end());
  return robots;
}

std::string RobotConfigPath(const std::string& config_dir, const std::string& robot_name) {
  const std::filesystem::path path = std::filesystem::path(config_dir) / "robots" / (robot_name + ".yaml");
  if (std::filesystem::exists(path)) return path.string();
  std::string known;
  for (const std::string& name : KnownRobots(config_dir)) known += (known.empty() ? "" : ", ") + name;
  throw ConfigError("unknown robot '" + robot_name + "' (known: " + known + ") in " + config_dir + "/robots");
}

}  // namespace tavis::configs
