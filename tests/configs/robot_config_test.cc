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

// Writes `text` to a temporary robot file and returns the loader's error message. ctest runs
// each case as its own process in parallel, so the file is named after the running test.
std::string LoadError(const std::string& text) {
  const std::string test_name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  const std::string path =
      (std::filesystem::temp_directory_path() / ("tavis_robot_config_" + test_name + ".yaml")).string();
  std::ofstream(path) << text;
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

TEST(RobotConfig, UnknownKeyIsNamedWithItsPath) {
  const std::string text = std::regex_replace(kGr1t2, std::regex("  damping: 0.01"), "  damping: 0.01\n  dampnig: 0.02");
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
  const std::string text = std::regex_replace(kGr1t2, std::regex("left_wrist_pitch_joint\\]"), "left_wrist_pich_joint]");
  EXPECT_NE(LoadError(text).find("unknown joint 'left_wrist_pich_joint'"), std::string::npos) << LoadError(text);
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
