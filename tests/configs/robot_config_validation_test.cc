// Every value a robot file can hold is validated at load: each case mutates one value of a
// shipped robot and expects a ConfigError naming the file, the key path and the bad value.
// The first cases are the reported crashes: ODE aborted or the gripper build read out of
// bounds on them before the loader checked.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>
#include <vector>

#include "configs/robot_config.h"
#include "configs/yaml_reader.h"

namespace tavis::configs {
namespace {

struct Mutation {
  const char* name;
  const char* robot;
  const char* from;  // replaced at its first occurrence
  const char* to;
  const char* key_path;
  const char* fragment;  // the bad value (and, where useful, the rule) as the message shows it
};

// Names the case in test listings (ctest shows the parameter).
void PrintTo(const Mutation& m, std::ostream* out) { *out << m.name; }

const Mutation kMutations[] = {
    // Reported crashes: ODE aborts and the ik_link out-of-bounds read.
    {"ZeroFingerMass", "gr1t2", "finger_mass: 0.1", "finger_mass: 0.0", "gripper.finger_mass", "got 0.0"},
    {"NegativeFingerMass", "reachy2", "finger_mass: 0.1", "finger_mass: -0.1", "gripper.finger_mass", "got -0.1"},
    {"HugeLinkMass", "gr1t2", "default: -0.335, mass: 1.0}", "default: -0.335, mass: 1e308}", "joints[0].mass",
     "got 1e308"},
    {"ZeroJointAxis", "gr1t2", "axis: [0, 1, 0]", "axis: [0, 0, 0]", "joints[0].axis",
     "[0, 0, 0] is not a unit vector"},
    {"ZeroBoxSize", "gr1t2", "size: [0.224, 0.345, 0.174]", "size: [0.224, 0, 0.174]", "shapes[0].size[1]", "got 0"},
    {"NegativeBoxSize", "gr1t2", "size: [0.056, 0.046, 0.036]", "size: [-0.056, 0.046, 0.036]", "shapes[13].size[0]",
     "got -0.056"},
    {"ZeroCapsuleRadius", "gr1t2", "radius: 0.08}", "radius: 0}", "shapes[1].radius", "got 0"},
    {"NegativeCylinderRadius", "reachy2", "radius: 0.245", "radius: -0.245", "shapes[0].radius", "got -0.245"},
    {"IkLinkIsBaseLink", "gr1t2", "ik_link: left_hand_pitch_link", "ik_link: base_link", "arms.left.ik_link",
     "'base_link' is not moved by the arm's joints"},
    {"IkLinkMovedByTheNeck", "gr1t2", "ik_link: left_hand_pitch_link", "ik_link: head_yaw_link", "arms.left.ik_link",
     "'head_yaw_link' is moved by joint 'head_yaw_joint'"},
    {"IkLinkMovedByTheNeckReachy", "reachy2", "ik_link: r_wrist_link", "ik_link: head", "arms.right.ik_link",
     "'head' is moved by joint 'neck_yaw'"},
    {"IkLinkAboveTheWrist", "gr1t2", "ik_link: left_hand_pitch_link", "ik_link: left_lower_arm_pitch_link",
     "arms.left.ik_link", "not moved by the arm's joint 'left_wrist_yaw_joint'"},
    // Silently accepted before: masses raised, duplicate keys, meaningless limits.
    {"LinkMassBelowEngineMinimum", "gr1t2", "upper: 0.96, default: 0.0, mass: 0.2}",
     "upper: 0.96, default: 0.0, mass: 0.01}", "joints[5].mass", "got 0.01, expected a value in [0.05, 1000] kg"},
    {"NanLinkMass", "gr1t2", "default: -0.335, mass: 1.0}", "default: -0.335, mass: .nan}", "joints[0].mass", "'.nan'"},
    {"NonUnitJointAxis", "reachy2", "axis: [0, 1, 0]", "axis: [0, 1, 1]", "joints[0].axis",
     "[0, 1, 1] is not a unit vector"},
    {"HugeBoxSize", "gr1t2", "size: [0.283, 0.288, 0.388]", "size: [283, 0.288, 0.388]", "shapes[5].size[0]",
     "got 283"},
    {"ZeroCylinderHeight", "reachy2", "height: 0.19", "height: 0", "shapes[0].height", "got 0"},
    {"CapsuleWithoutLength", "gr1t2", "a: [0, 0, 0], b: [0, 0.095, 0]", "a: [0, 0, 0], b: [0, 0, 0]", "shapes[8].b",
     "[0, 0, 0] equals end a"},
    {"JointLimitsReversed", "gr1t2", "lower: -2.79, upper: 1.92", "lower: 1.92, upper: -2.79", "joints[0].lower",
     "lower limit 1.92 is not below upper limit -2.79"},
    {"JointLimitsEqual", "reachy2", "lower: -0.35, upper: 0.35", "lower: 0.0, upper: 0.0", "joints[14].lower",
     "lower limit 0 is not below upper limit 0"},
    {"JointLimitOutOfRange", "gr1t2", "lower: -2.97, upper: 2.97", "lower: -297, upper: 2.97", "joints[2].lower",
     "got -297"},
    {"DefaultOutsideLimits", "gr1t2", "default: -0.335", "default: 2.5", "joints[0].default", "position 2.5 outside"},
    {"NegativeVelocityLimit", "gr1t2", "arm: {velocity_limit: 5.0", "arm: {velocity_limit: -5.0",
     "actuators.arm.velocity_limit", "got -5.0"},
    {"ZeroEffortLimit", "reachy2", "effort_limit: 10.0", "effort_limit: 0", "actuators.neck.effort_limit", "got 0"},
    {"NegativePositionGain", "gr1t2", "position_gain: 60.0", "position_gain: -60.0", "actuators.arm.position_gain",
     "got -60.0"},
    {"NegativeIkDamping", "gr1t2", "damping: 0.01", "damping: -0.01", "ik.damping", "got -0.01"},
    {"NegativeNullspaceGain", "reachy2", "nullspace_gain: 0.1", "nullspace_gain: -0.1", "ik.nullspace_gain",
     "got -0.1"},
    {"NegativeClosedGap", "reachy2", "closed_gap: 0.003", "closed_gap: -0.003", "gripper.closed_gap", "got -0.003"},
    {"ClosedGapNotBelowOpenGap", "gr1t2", "closed_gap: 0.0", "closed_gap: 0.1", "gripper.closed_gap",
     "closed_gap 0.1 is not below open_gap 0.085"},
    {"NegativeGripperForce", "gr1t2", "max_force: 20.0", "max_force: -20.0", "gripper.max_force", "got -20.0"},
    {"ZeroGripperSpeed", "reachy2", "max_speed: 0.15", "max_speed: 0", "gripper.max_speed", "got 0"},
    {"ZeroPadSize", "gr1t2", "pad_size: [0.022, 0.008, 0.0375]", "pad_size: [0.022, 0.0, 0.0375]",
     "gripper.pad_size[1]", "got 0.0"},
    {"NegativeHousingSize", "gr1t2", "size: [0.075, 0.085, 0.093]", "size: [-0.075, 0.085, 0.093]",
     "gripper.housing.size[0]", "got -0.075"},
    {"PadsInsideTheHousing", "gr1t2", "pad_center_xyz: [0.0, 0.0, -0.160]", "pad_center_xyz: [0.0, 0.0, -0.05]",
     "gripper.pad_center_xyz", "[0.0, 0.0, -0.05] puts the pads' top face"},
    {"ZeroClosingAxis", "gr1t2", "closing_axis: [0.0, 1.0, 0.0]", "closing_axis: [0.0, 0.0, 0.0]",
     "gripper.closing_axis", "[0.0, 0.0, 0.0] is not a unit vector"},
    {"DiagonalClosingAxis", "reachy2", "closing_axis: [0.0, 1.0, 0.0]", "closing_axis: [0.0, 0.7071068, 0.7071068]",
     "gripper.closing_axis", "[0.0, 0.7071068, 0.7071068] is not along x, y or z"},
    {"ZeroFocalLength", "gr1t2", "focal_length_mm: 15.0", "focal_length_mm: 0", "cameras[0].focal_length_mm", "got 0"},
    {"NearBeyondFar", "gr1t2", "near: 0.15, far: 10.0", "near: 0.15, far: 0.1", "cameras[0].far",
     "far 0.1 is not beyond near 0.15"},
    {"ZeroNear", "reachy2", "near: 0.10, far: 1.0", "near: 0, far: 1.0", "cameras[1].near", "got 0"},
    {"HugeFar", "gr1t2", "far: 10.0", "far: 1e9", "cameras[0].far", "got 1e9"},
    {"CameraQuaternionNotNormalised", "gr1t2", "quat_wxyz: [1, 0, 0, 0]", "quat_wxyz: [2, 0, 0, 0]",
     "cameras[0].quat_wxyz", "[2, 0, 0, 0] is not normalised"},
    {"CameraNameTwice", "gr1t2", "name: left_wrist, parent", "name: head, parent", "cameras[1].name",
     "camera 'head' is defined twice"},
    {"JointNameTwice", "gr1t2", "name: left_shoulder_roll_joint,", "name: left_shoulder_pitch_joint,", "joints[1].name",
     "joint 'left_shoulder_pitch_joint' is defined twice"},
    {"NeckSharesAnArmJoint", "gr1t2", "joints: [head_roll_joint, head_pitch_joint, head_yaw_joint]",
     "joints: [head_roll_joint, head_pitch_joint, left_wrist_pitch_joint]", "neck.joints",
     "joint 'left_wrist_pitch_joint' is already in arms.left.joints"},
    {"ArmsShareAJoint", "reachy2", "[r_shoulder_pitch, r_shoulder_roll", "[l_shoulder_pitch, r_shoulder_roll",
     "arms.right.joints", "joint 'l_shoulder_pitch' is already in arms.left.joints"},
    {"ArmJointTwice", "gr1t2", "left_wrist_roll_joint, left_wrist_pitch_joint]",
     "left_wrist_roll_joint, left_wrist_roll_joint]", "arms.left.joints",
     "joint 'left_wrist_roll_joint' appears twice"},
    {"JointDrivenByNothing", "gr1t2", "\n\n# TAVIS actuators",
     "\n  - {name: extra_joint, parent: head_yaw_link, child: extra_link, xyz: [0, 0, 0], rpy: [0, 0, 0], axis: [0, 0, "
     "1], "
     "lower: -1, upper: 1, default: 0, mass: 0.1}\n\n# TAVIS actuators",
     "joints[17].name", "joint 'extra_joint' is in neither arm nor the neck"},
    {"FrameAngleOutOfRange", "gr1t2", "rpy: [0, 0, 0]}", "rpy: [0, 0, 90]}", "frames[0].rpy[2]", "got 90"},
    {"RootPositionOutOfRange", "gr1t2", "root_world_xyz: [0.0, 0.0, 0.93]", "root_world_xyz: [0.0, 0.0, 930]",
     "root_world_xyz[2]", "got 930"},
    {"UnsimulatedStateOutOfRange", "gr1t2", "{unsimulated: left_hip_roll_joint, value: 0.0}",
     "{unsimulated: left_hip_roll_joint, value: 1e6}", "observation_state[0].value", "got 1e6"},
    {"DuplicateKeyInFlowMapping", "gr1t2", "default: -0.335, mass: 1.0}", "default: -0.335, mass: 1.0, mass: 0.01}",
     "joints[0].mass", "duplicate key 'mass' (lines 14 and 14)"},
    {"DuplicateTopLevelKey", "reachy2", "canonical_offset: [-0.01, 0.0, 0.93]\n",
     "canonical_offset: [-0.01, 0.0, 0.93]\nname: reachy3\n", "name", "duplicate key 'name' (lines 9 and 12)"},
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string ShippedRobot(const std::string& robot) { return ReadFile(RobotConfigPath(TAVIS_CONFIG_DIR, robot)); }

// ROBOT.yaml (a robot file's name must match its name: key) in a per-test folder: ctest runs
// each case as its own process, in parallel.
std::string TempRobotFile(const std::string& text, const std::string& robot) {
  std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  for (char& c : name) c = c == '/' ? '_' : c;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("tavis_robot_validation_" + name);
  std::filesystem::create_directories(dir);
  const std::string path = (dir / (robot + ".yaml")).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

class RobotConfigValidation : public ::testing::TestWithParam<Mutation> {};

TEST_P(RobotConfigValidation, NamesFileKeyAndValue) {
  const Mutation& m = GetParam();
  std::string text = ShippedRobot(m.robot);
  const size_t at = text.find(m.from);
  ASSERT_NE(at, std::string::npos) << "the shipped " << m.robot << ".yaml no longer holds '" << m.from << "'";
  text.replace(at, std::string(m.from).size(), m.to);
  const std::string path = TempRobotFile(text, m.robot);
  try {
    LoadRobotModel(path);
    FAIL() << "accepted: " << m.to;
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ": " + m.key_path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(m.fragment), std::string::npos) << message;
  }
  std::filesystem::remove(path);
}

INSTANTIATE_TEST_SUITE_P(Mutations, RobotConfigValidation, ::testing::ValuesIn(kMutations),
                         [](const ::testing::TestParamInfo<Mutation>& mutation) {
                           return std::string(mutation.param.name);
                         });

TEST(RobotConfigValidationExtra, ShippedRobotsPassUnchanged) {
  for (const char* robot : {"gr1t2", "reachy2"}) {
    const kinematics::RobotModel model = LoadRobotModel(RobotConfigPath(TAVIS_CONFIG_DIR, robot));
    for (const kinematics::Link& link : model.links) {
      if (link.joint >= 0) {
        EXPECT_GE(link.mass, kinematics::kMinBodyMass) << robot << " " << link.name;
      }
    }
  }
}

// yaml-cpp skips a UTF-8 byte order mark: such a file loads as the same robot.
TEST(RobotConfigValidationExtra, ByteOrderMarkIsAccepted) {
  const std::string path = TempRobotFile("\xEF\xBB\xBF" + ShippedRobot("gr1t2"), "gr1t2");
  const kinematics::RobotModel with_bom = LoadRobotModel(path);
  std::filesystem::remove(path);
  const kinematics::RobotModel plain = LoadRobotModel(RobotConfigPath(TAVIS_CONFIG_DIR, "gr1t2"));
  EXPECT_EQ(with_bom.name, "gr1t2");
  EXPECT_EQ(with_bom.num_joints(), plain.num_joints());
}

TEST(RobotConfigValidationExtra, DuplicateKeysAreFoundAtAnyDepth) {
  try {
    YamlValue::LoadString("a:\n  - {b: 1}\n  - {c: {d: 1, e: 2, d: 3}}\n", "inline.yaml");
    FAIL() << "accepted a duplicate key";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "inline.yaml: a[1].c.d: duplicate key 'd' (lines 3 and 3)");
  }
}

}  // namespace
}  // namespace tavis::configs
