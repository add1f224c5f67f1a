// What a refused resume names: each changed key, nested ones by their path.
#include "batch/output/settings_difference.h"

#include <gtest/gtest.h>

namespace tavis::batch::output {
namespace {

TEST(SettingsDifference, NamesChangedTopLevelKeys) {
  EXPECT_EQ(SettingsDifference({{"seed", 0}, {"fps", 60}}, {{"seed", 9}, {"fps", 60}}), "seed 0 -> 9");
  EXPECT_EQ(SettingsDifference({{"seed", 0}}, {{"seed", 0}, {"fps", 20}}), "fps unset -> 20");
  EXPECT_EQ(SettingsDifference({{"seed", 0}}, {{"seed", 0}}), "");
}

TEST(SettingsDifference, NamesTheNestedKeyThatChangedNotTheWholeObject) {
  const nlohmann::json was = {
      {"identity",
       {{"robot_config", {{"actuators", {{"arm", {{"velocity_limit", "5.0"}, {"effort_limit", "30.0"}}}}}}}}}};
  nlohmann::json now = was;
  now["identity"]["robot_config"]["actuators"]["arm"]["velocity_limit"] = "4.0";
  EXPECT_EQ(SettingsDifference(was, now), "identity.robot_config.actuators.arm.velocity_limit \"5.0\" -> \"4.0\"");
}

}  // namespace
}  // namespace tavis::batch::output
