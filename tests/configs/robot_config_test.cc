#include "configs/robot_config.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "configs/yaml_reader.h"

namespace tavis::configs {
namespace {

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Writes `text` as the robot file ROBOT.yaml in a temporary folder and returns its path. ctest
// runs each case as its own process in parallel, so the folder is named after the running test.
std::string TempRobotFile(const std::string& text, const std::string& robot = "gr1t2") {
  const std::string test_name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("tavis_robot_config_" + test_name);
  std::filesystem::create_directories(dir);
  const std::string path = (dir / (robot + ".yaml")).string();
  std::ofstream(path) << text;
  return path;
}

// The loader's error message for `text` as gr1t2.yaml ("" when it loads).
std::string LoadError(const std::string& text) {
  const std::string path = TempRobotFile(text);
  try {
    LoadRobotModel(path);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

const std::string kGr1t2 = ReadFile(std::string(TAVIS_CONFIG_DIR) + "/robots/gr1t2.yaml");

TEST(RobotConfig, BothRobotsLoad) {
  for (const char* name : {"gr1t2", "reachy2"}) {
    const kinematics::RobotModel robot = LoadRobotModel(RobotConfigPath(TAVIS_CONFIG_DIR, name));
    EXPECT_EQ(robot.name, name);
    EXPECT_EQ(robot.num_joints(), 17);
    EXPECT_EQ(robot.cameras.size(), 3u);
  }
}

// Commands find a robot by its file's name and label results with it: a file whose name: says
// another robot is refused, naming the file, the key and both names.
TEST(RobotConfig, NameThatDiffersFromTheFileNameIsRefused) {
  const std::string path = TempRobotFile(kGr1t2, "myrobot");
  try {
    LoadRobotModel(path);
    FAIL() << "a file myrobot.yaml saying name: gr1t2 was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              path + ": name: 'gr1t2' differs from the file's name 'myrobot' (robots/NAME.yaml must say name: NAME)");
  }
  std::string renamed = kGr1t2;
  renamed.replace(renamed.find("name: gr1t2"), std::string("name: gr1t2").size(), "name: myrobot");
  std::ofstream(path) << renamed;
  EXPECT_EQ(LoadRobotModel(path).name, "myrobot");
}

// A device named as a YAML file is named as such, not read without end.
TEST(RobotConfig, DeviceGivenAsAYamlFileIsNamed) {
  try {
    YamlValue::LoadFile("/dev/zero");
    FAIL() << "/dev/zero was read";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "/dev/zero: is a character device, not a regular file");
  }
}

TEST(RobotConfig, UnknownKeyIsNamedWithItsPath) {
  const std::string text =
      std::regex_replace(kGr1t2, std::regex("  damping: 0.01"), "  damping: 0.01\n  dampnig: 0.02");
  EXPECT_NE(LoadError(text).find("ik.dampnig: unknown key 'dampnig'"), std::string::npos) << LoadError(text);
}

TEST(RobotConfig, MissingKeyIsNamed) {
  const std::string text = std::regex_replace(kGr1t2, std::regex("  nullspace_gain: 1.0\n"), "");
  EXPECT_NE(LoadError(text).find("ik: missing key 'nullspace_gain'"), std::string::npos) << LoadError(text);
}

TEST(RobotConfig, BadValueIsNamed) {
  const std::string text = std::regex_replace(kGr1t2, std::regex("damping: 0.01"), "damping: fast");
  EXPECT_NE(LoadError(text).find("ik.damping: expected a number"), std::string::npos) << LoadError(text);
}

TEST(RobotConfig, MalformedYamlIsReported) {
  EXPECT_NE(LoadError("name: [gr1t2\n").find("malformed YAML"), std::string::npos);
}

TEST(RobotConfig, UnknownJointInArmIsNamed) {
  const std::string text =
      std::regex_replace(kGr1t2, std::regex("left_wrist_pitch_joint\\]"), "left_wrist_pich_joint]");
  EXPECT_NE(LoadError(text).find("unknown joint 'left_wrist_pich_joint'"), std::string::npos) << LoadError(text);
}

TEST(RobotConfig, ObservationStateFollowsTheReferenceLayout) {
  const kinematics::RobotModel gr1t2 = LoadRobotModel(RobotConfigPath(TAVIS_CONFIG_DIR, "gr1t2"));
  ASSERT_EQ(gr1t2.observation_state.size(), 34u) << "32 reference joints and one entry per gripper";
  // The reference's neck_state_indices for GR1T2 are 11, 16, 21.
  for (int k = 0; k < kinematics::kNeckDof; ++k) {
    const kinematics::StateEntry& entry = gr1t2.observation_state[static_cast<std::size_t>(11 + 5 * k)];
    EXPECT_EQ(entry.kind, kinematics::StateEntry::Kind::kJoint);
    EXPECT_EQ(entry.joint, gr1t2.neck_joints[k]) << "neck entry " << k;
  }
  EXPECT_EQ(gr1t2.observation_state[0].kind, kinematics::StateEntry::Kind::kUnsimulated);
  EXPECT_EQ(gr1t2.observation_state[0].name, "left_hip_roll_joint");
  EXPECT_EQ(gr1t2.observation_state[33].kind, kinematics::StateEntry::Kind::kGripperGap);
  EXPECT_EQ(gr1t2.observation_state[33].side, kinematics::Side::kRight);
}

TEST(RobotConfig, ObservationStateErrorsAreNamed) {
  const std::string twice =
      std::regex_replace(kGr1t2, std::regex("\\{joint: head_yaw_joint\\}"), "{joint: head_pitch_joint}");
  EXPECT_NE(LoadError(twice).find("joint 'head_pitch_joint' appears twice"), std::string::npos) << LoadError(twice);
  const std::string missing = std::regex_replace(kGr1t2, std::regex("  - \\{joint: head_yaw_joint\\}  # 21\n"), "");
  EXPECT_NE(LoadError(missing).find("1 are missing"), std::string::npos) << LoadError(missing);
  const std::string side = std::regex_replace(kGr1t2, std::regex("gripper_gap: left"), "gripper_gap: middle");
  EXPECT_NE(LoadError(side).find("gripper_gap is left or right, got 'middle'"), std::string::npos) << LoadError(side);
  const std::string both =
      std::regex_replace(kGr1t2, std::regex("\\{gripper_gap: left\\}"), "{gripper_gap: left, joint: head_roll_joint}");
  EXPECT_NE(LoadError(both).find("an entry is one of"), std::string::npos) << LoadError(both);
}

TEST(RobotConfig, UnknownRobotListsTheKnownOnes) {
  try {
    RobotConfigPath(TAVIS_CONFIG_DIR, "atlas");
    FAIL() << "expected an error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown robot 'atlas'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("gr1t2"), std::string::npos);
  }
}

}  // namespace
}  // namespace tavis::configs
