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

// A resume that leaves a setting out (no --perturb, no --episode) differs from the run it resumes
// as much as one that changes it: the keys only the old run has are named too.
TEST(SettingsDifference, NamesKeysOnlyTheOldRunHas) {
  EXPECT_EQ(SettingsDifference({{"seed", 0}, {"perturbations", {"runtime:move"}}}, {{"seed", 0}}),
            "perturbations [\"runtime:move\"] -> unset");
  EXPECT_EQ(SettingsDifference({{"episode_start", 7}, {"episodes", 1}}, {{"episodes", 1}}), "episode_start 7 -> unset");
  EXPECT_EQ(SettingsDifference({{"identity", {{"a", 1}, {"b", 2}}}}, {{"identity", {{"a", 1}}}}),
            "identity.b 2 -> unset");
  // Both directions at once, in key order.
  EXPECT_EQ(SettingsDifference({{"a", 1}, {"c", 3}}, {{"b", 2}, {"c", 3}}), "a 1 -> unset, b unset -> 2");
}

// A damaged record that is not an object has none of the settings.
TEST(SettingsDifference, ARecordThatIsNotAnObjectHasNoneOfTheSettings) {
  EXPECT_EQ(SettingsDifference(nlohmann::json::array(), {{"seed", 0}}), "seed unset -> 0");
  EXPECT_EQ(SettingsDifference({{"seed", 0}}, nlohmann::json()), "seed 0 -> unset");
}

// The changes themselves, for a caller that words them its own way (tavis verify): each key's
// path and both values, absent where a side has none.
TEST(SettingChanges, GiveEachChangedKeysPathAndBothValues) {
  const std::vector<SettingChange> changes = SettingChanges({{"identity", {{"arm", {{"gain", "60.0"}}}}}, {"seed", 0}},
                                                            {{"identity", {{"arm", {{"gain", "61.0"}}}}}});
  ASSERT_EQ(changes.size(), 2u);
  EXPECT_EQ(changes[0].path, "identity.arm.gain");
  EXPECT_EQ(*changes[0].was, "60.0");
  EXPECT_EQ(*changes[0].now, "61.0");
  EXPECT_EQ(changes[1].path, "seed");
  EXPECT_EQ(*changes[1].was, 0);
  EXPECT_FALSE(changes[1].now.has_value());
  EXPECT_TRUE(SettingChanges({{"a", 1}}, {{"a", 1}}).empty());
}

}  // namespace
}  // namespace tavis::batch::output
