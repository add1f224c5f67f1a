#include "configs/robot_config.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "configs/yaml_reader.h"

namespace tavis::configs {
namespace {

using kinematics::RobotModel;

// The bounds of robot_config.h. Zero or negative sizes and masses abort ODE; the upper bounds
// catch unit slips (mm for m) and values like 1e308 that overflow the solver.
constexpr double kTwoPi = 6.283185307179586;
constexpr Range kMass{kinematics::kMinBodyMass, 1000.0, false, "kg", "below 0.05 kg the physics solver stalls"};
constexpr Range kSize{0.0, 10.0, true, "m"};
constexpr Range kPosition{-10.0, 10.0, false, "m"};
constexpr Range kAngle{-kTwoPi, kTwoPi, false, "rad"};
constexpr Range kJointVelocity{0.0, 100.0, true, "rad/s"};
constexpr Range kJointEffort{0.0, 10000.0, true, "N m"};
constexpr Range kServoGain{0.0, 10000.0, true, "1/s"};
constexpr Range kIkDamping{0.0, 10.0, true, "", "without damping the IK is singular at full stretch"};
constexpr Range kNullspaceGain{0.0, 100.0, false, ""};
constexpr Range kClosedGap{0.0, 10.0, false, "m"};
constexpr Range kFingerForce{0.0, 10000.0, true, "N"};
constexpr Range kFingerSpeed{0.0, 10.0, true, "m/s"};
constexpr Range kFocalLength{0.0, 1000.0, true, "mm"};
constexpr Range kClipDistance{0.0, 1000.0, true, "m"};
constexpr double kUnitTolerance = 1e-3;  // |norm - 1| accepted for axes and quaternions

std::string Number(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

Quat ReadQuatWxyz(const YamlValue& value) {
  const std::vector<double> c = value.AsDoubles();
  if (c.size() != 4) value.Fail("expected a quaternion w, x, y, z");
  const Quat q(c[0], c[1], c[2], c[3]);
  if (std::abs(q.norm() - 1.0) > kUnitTolerance) {
    value.Fail("quaternion " + value.Text() + " is not normalised (norm " + Number(q.norm()) + ")");
  }
  return q.normalized();
}

// A non-unit axis is rejected rather than normalised: a zero axis aborts ODE, and [0, 1, 1] is
// more likely a typo than a meant diagonal. Rounded unit vectors pass and are made exact.
Vec3 ReadUnitAxis(const YamlValue& value) {
  const Vec3 axis = value.AsVec3();
  if (std::abs(axis.norm() - 1.0) > kUnitTolerance) {
    value.Fail("axis " + value.Text() + " is not a unit vector (norm " + Number(axis.norm()) + ")");
  }
  return axis.normalized();
}

RigidTransform ReadXyzRpy(const YamlValue& entry) {
  return TransformFromXyzRpy(entry.Vector3("xyz", kPosition), entry.Vector3("rpy", kAngle));
}

// Adds a link and returns its index; the parent must already be known (parents-first order).
int AddLink(RobotModel& robot, std::map<std::string, int>& link_index, const YamlValue& entry, const std::string& name,
            const std::string& parent) {
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

int LookUp(const std::map<std::string, int>& index, const std::string& name, const YamlValue& where, const char* what) {
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
  std::set<std::string> joint_names;
  for (const YamlValue& entry : root.Required("joints").Elements()) {
    kinematics::Joint joint;
    joint.name = entry.String("name");
    if (!joint_names.insert(joint.name).second)
      entry.Required("name").Fail("joint '" + joint.name + "' is defined twice");
    const int link = AddLink(robot, link_index, entry, entry.String("child"), entry.String("parent"));
    robot.links[link].origin = ReadXyzRpy(entry);
    robot.links[link].mass = entry.Double("mass", kMass);
    robot.links[link].joint = robot.num_joints();
    joint.link = link;
    joint.axis = ReadUnitAxis(entry.Required("axis"));
    joint.lower = entry.Double("lower", kAngle);
    joint.upper = entry.Double("upper", kAngle);
    joint.default_position = entry.Double("default", kAngle);
    if (!(joint.lower < joint.upper)) {
      entry.Required("lower").Fail("lower limit " + Number(joint.lower) + " is not below upper limit " +
                                   Number(joint.upper));
    }
    if (joint.default_position < joint.lower || joint.default_position > joint.upper) {
      entry.Required("default").Fail("default position " + Number(joint.default_position) +
                                     " outside the joint limits [" + Number(joint.lower) + ", " + Number(joint.upper) +
                                     "]");
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
  limits.velocity_limit = entry.Double("velocity_limit", kJointVelocity);
  limits.effort_limit = entry.Double("effort_limit", kJointEffort);
  limits.position_gain = entry.Double("position_gain", kServoGain);
  entry.ExpectNoOtherKeys();
  return limits;
}

kinematics::LinkShape ReadShape(const YamlValue& entry, const std::map<std::string, int>& link_index) {
  kinematics::LinkShape shape;
  shape.link = LookUp(link_index, entry.String("link"), entry, "link");
  const std::string kind = entry.String("kind");
  if (kind == "box") {
    shape.shape = {ShapeKind::kBox, entry.Vector3("size", kSize)};
    shape.X_LS.translation() = entry.Vector3("center", kPosition);
  } else if (kind == "cylinder") {
    const double radius = entry.Double("radius", kSize);
    shape.shape = {ShapeKind::kCylinder, Vec3(radius, radius, entry.Double("height", kSize))};
    shape.X_LS.translation() = entry.Vector3("center", kPosition);
  } else if (kind == "capsule") {
    const Vec3 a = entry.Vector3("a", kPosition);
    const Vec3 b = entry.Vector3("b", kPosition);
    const double radius = entry.Double("radius", kSize);
    const double length = (b - a).norm();
    // Its axis is b - a, undefined when the ends meet.
    if (!(length > 1e-6)) entry.Required("b").Fail("capsule end " + entry.Required("b").Text() + " equals end a");
    shape.shape = {ShapeKind::kCapsule, Vec3(radius, radius, length)};
    shape.X_LS.translation() = 0.5 * (a + b);
    shape.X_LS.linear() = Quat::FromTwoVectors(Vec3::UnitZ(), (b - a) / length).toRotationMatrix();
  } else {
    entry.Required("kind").Fail("unknown shape kind '" + kind + "' (box, cylinder, capsule)");
  }
  entry.ExpectNoOtherKeys();
  return shape;
}

kinematics::GripperSpec ReadGripper(const YamlValue& entry) {
  kinematics::GripperSpec g;
  g.tcp = entry.Vector3("tcp_xyz", kPosition);
  const YamlValue closing_axis = entry.Required("closing_axis");
  g.closing_axis = ReadUnitAxis(closing_axis);
  // Pads are boxes aligned with the IK link frame (GripperGeometry), so they can only slide
  // along one of its axes.
  if (g.closing_axis.cwiseAbs().maxCoeff() < 1.0 - kUnitTolerance) {
    closing_axis.Fail("axis " + closing_axis.Text() + " is not along x, y or z, as the box-shaped pads need");
  }
  g.pad_size = entry.Vector3("pad_size", kSize);
  g.pad_center = entry.Vector3("pad_center_xyz", kPosition);
  g.open_gap = entry.Double("open_gap", kSize);
  g.closed_gap = entry.Double("closed_gap", kClosedGap);
  g.max_force = entry.Double("max_force", kFingerForce);
  g.max_speed = entry.Double("max_speed", kFingerSpeed);
  g.finger_mass = entry.Double("finger_mass", kMass);
  const YamlValue housing = entry.Required("housing");
  g.housing_center = housing.Vector3("center", kPosition);
  g.housing_size = housing.Vector3("size", kSize);
  housing.ExpectNoOtherKeys();
  // The fingers travel (open - closed) / 2 each: zero travel is a slider with no range.
  if (!(g.closed_gap < g.open_gap)) {
    entry.Required("closed_gap")
        .Fail("closed_gap " + Number(g.closed_gap) + " is not below open_gap " + Number(g.open_gap));
  }
  // The visual fingers run from the housing's bottom face (the grippers approach along -z) down
  // to the pads; pads reaching into the housing leave them no length.
  const double pad_top = g.pad_center.z() + 0.5 * g.pad_size.z();
  const double housing_bottom = g.housing_center.z() - 0.5 * g.housing_size.z();
  if (pad_top > housing_bottom) {
    const YamlValue pad_center = entry.Required("pad_center_xyz");
    pad_center.Fail(pad_center.Text() + " puts the pads' top face at z = " + Number(pad_top) +
                    " m, above the housing's bottom face at z = " + Number(housing_bottom) +
                    " m: the pads must hang below the housing");
  }
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
      entry.value = item.Double("value", kAngle);
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

// The arms and the neck drive disjoint joints, and every joint is driven by one of them: the
// physics treats any joint outside the arms as a neck joint, servoed outside the simulation.
class JointOwners {
 public:
  explicit JointOwners(const std::map<std::string, int>& joint_index) : joint_index_(joint_index) {}

  // Reads a list of `count` joint names and records `list` as their owner.
  std::vector<int> Claim(const YamlValue& list, int count, const char* wrong_count) {
    const std::vector<std::string> names = list.AsStrings();
    if (static_cast<int>(names.size()) != count) list.Fail(std::string(wrong_count) + ", got " + list.Text());
    std::vector<int> joints;
    for (const std::string& name : names) {
      const int joint = LookUp(joint_index_, name, list, "joint");
      const auto [owner, inserted] = owner_.emplace(joint, list.key_path());
      if (!inserted) {
        list.Fail("joint '" + name + "' " +
                  (owner->second == list.key_path() ? "appears twice" : "is already in " + owner->second));
      }
      joints.push_back(joint);
    }
    return joints;
  }

  // `joints` is the file's joint list, in joint index order.
  void ExpectAllClaimed(const YamlValue& joints) const {
    const std::vector<YamlValue> entries = joints.Elements();
    for (size_t j = 0; j < entries.size(); ++j) {
      if (owner_.count(static_cast<int>(j)) == 0) {
        const YamlValue name = entries[j].Required("name");
        name.Fail("joint '" + name.AsString() + "' is in neither arm nor the neck, so nothing would drive it");
      }
    }
  }

 private:
  const std::map<std::string, int>& joint_index_;
  std::map<int, std::string> owner_;  // joint -> key path of the list that claimed it
};

// The IK moves the ik_link with the arm's joints, and the physics hangs the gripper on the body
// of the link's nearest arm joint: the link's chain to the base must hold exactly this arm's
// joints. A neck or other-arm joint above it, or base_link itself, leaves the gripper no body.
void CheckIkLink(const RobotModel& robot, const kinematics::ArmSpec& arm, const YamlValue& ik_link) {
  const std::string name = ik_link.AsString();
  if (arm.ik_link == kinematics::kBaseLink) ik_link.Fail("ik_link '" + name + "' is not moved by the arm's joints");
  std::set<int> chain;
  for (int link = arm.ik_link; link != kinematics::kBaseLink; link = robot.links[link].parent) {
    const int joint = robot.links[link].joint;
    if (joint < 0) continue;
    if (std::find(arm.joints.begin(), arm.joints.end(), joint) == arm.joints.end()) {
      ik_link.Fail("ik_link '" + name + "' is moved by joint '" + robot.joints[joint].name +
                   "', which is not one of this arm's joints");
    }
    chain.insert(joint);
  }
  for (int joint : arm.joints) {
    if (chain.count(joint) == 0) {
      ik_link.Fail("ik_link '" + name + "' is not moved by the arm's joint '" + robot.joints[joint].name + "'");
    }
  }
}

// The arms' joints, IK links and rest poses (`arms:` and `rest_pose:`), each joint claimed once.
void ReadArms(const YamlValue& root, const std::map<std::string, int>& link_index, JointOwners& owners,
              RobotModel& robot) {
  const YamlValue arms = root.Required("arms");
  const YamlValue rest = root.Required("rest_pose");
  for (kinematics::Side side : kinematics::kSides) {
    const YamlValue arm_entry = arms.Required(kinematics::Name(side));
    kinematics::ArmSpec& arm = robot.arms[kinematics::Index(side)];
    const YamlValue joints = arm_entry.Required("joints");
    const std::vector<int> arm_joints = owners.Claim(joints, kinematics::kArmDof, "an arm needs exactly 7 joints");
    std::copy(arm_joints.begin(), arm_joints.end(), arm.joints.begin());
    const YamlValue ik_link = arm_entry.Required("ik_link");
    arm.ik_link = LookUp(link_index, ik_link.AsString(), ik_link, "link");
    CheckIkLink(robot, arm, ik_link);
    arm_entry.ExpectNoOtherKeys();

    const YamlValue rest_entry = rest.Required(kinematics::Name(side));
    arm.rest_pose_canonical = MakeTransform(rest_entry.Vector3("position", kPosition),
                                            ReadQuatWxyz(rest_entry.Required("quat_wxyz")).toRotationMatrix());
    rest_entry.ExpectNoOtherKeys();
  }
  arms.ExpectNoOtherKeys();
  rest.ExpectNoOtherKeys();
}

// The camera mounts (`cameras:`), each name once, each on a known link.
std::vector<kinematics::CameraMount> ReadCameras(const YamlValue& root, const std::map<std::string, int>& link_index) {
  std::vector<kinematics::CameraMount> cameras;
  std::set<std::string> camera_names;
  for (const YamlValue& entry : root.Required("cameras").Elements()) {
    kinematics::CameraMount camera;
    camera.name = entry.String("name");
    if (!camera_names.insert(camera.name).second) {
      entry.Required("name").Fail("camera '" + camera.name + "' is defined twice");
    }
    camera.link = LookUp(link_index, entry.String("parent"), entry, "link");
    camera.X_LC =
        MakeTransform(entry.Vector3("xyz", kPosition), ReadQuatWxyz(entry.Required("quat_wxyz")).toRotationMatrix());
    camera.focal_length_mm = entry.Double("focal_length_mm", kFocalLength);
    camera.near_m = entry.Double("near", kClipDistance);
    camera.far_m = entry.Double("far", kClipDistance);
    if (!(camera.far_m > camera.near_m)) {
      entry.Required("far").Fail("far " + Number(camera.far_m) + " is not beyond near " + Number(camera.near_m));
    }
    entry.ExpectNoOtherKeys();
    cameras.push_back(camera);
  }
  return cameras;
}

}  // namespace

RobotModel LoadRobotModel(const std::string& path) { return ParseRobotModel(YamlValue::ReadFileText(path), path); }

RobotModel ParseRobotModel(const std::string& text, const std::string& path) {
  const YamlValue root = YamlValue::LoadString(text, path);
  RobotModel robot;
  robot.name = root.String("name");
  // Commands find a robot by its file's name (robots/NAME.yaml) and record that name in their
  // results, so a `name:` that says otherwise would label one robot's results with another's name.
  const std::string file_name = std::filesystem::path(path).stem().string();
  if (robot.name != file_name) {
    root.Required("name").Fail("'" + robot.name + "' differs from the file's name '" + file_name +
                               "' (robots/NAME.yaml must say name: NAME)");
  }
  robot.root_world = root.Vector3("root_world_xyz", kPosition);
  robot.canonical_offset = root.Vector3("canonical_offset", kPosition);

  std::map<std::string, int> link_index;
  ReadFramesAndJoints(root, robot, link_index);
  std::map<std::string, int> joint_index;
  for (int i = 0; i < robot.num_joints(); ++i) joint_index[robot.joints[i].name] = i;

  const YamlValue actuators = root.Required("actuators");
  robot.arm_actuator = ReadActuator(actuators.Required("arm"));
  robot.neck_actuator = ReadActuator(actuators.Required("neck"));
  actuators.ExpectNoOtherKeys();

  JointOwners owners(joint_index);
  ReadArms(root, link_index, owners, robot);

  const YamlValue neck = root.Required("neck");
  const std::vector<int> neck_joints =
      owners.Claim(neck.Required("joints"), kinematics::kNeckDof, "the neck needs roll, pitch, yaw joints");
  std::copy(neck_joints.begin(), neck_joints.end(), robot.neck_joints.begin());
  neck.ExpectNoOtherKeys();
  owners.ExpectAllClaimed(root.Required("joints"));

  const YamlValue ik = root.Required("ik");
  robot.ik_damping = ik.Double("damping", kIkDamping);
  robot.nullspace_gain = ik.Double("nullspace_gain", kNullspaceGain);
  ik.ExpectNoOtherKeys();

  robot.gripper = ReadGripper(root.Required("gripper"));
  robot.observation_state = ReadObservationState(root.Required("observation_state"), joint_index);

  robot.cameras = ReadCameras(root, link_index);
  for (const YamlValue& entry : root.Required("shapes").Elements())
    robot.shapes.push_back(ReadShape(entry, link_index));
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
