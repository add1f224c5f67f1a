// A scene planned once: the robot parsed from the bytes of its file (kept for the records), the
// levels resolved and applied, and the world the hand-built one of every front end was.
#include "batch/scene/scene_plan.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "batch/scene/scene_settings.h"
#include "batch/vec_env.h"
#include "configs/robot_config.h"
#include "configs/yaml_reader.h"
#include "scenarios/registry.h"

namespace tavis::batch::scene {
namespace {

SceneSpec Spec(const std::string& task) {
  SceneSpec spec;
  spec.task = task;
  spec.robot = "reachy2";
  spec.seed = 5;
  spec.config_dir = TAVIS_CONFIG_DIR;
  return spec;
}

TEST(ScenePlan, ParsesTheRobotFromTheBytesItKeeps) {
  const ScenePlan plan = PlanScene(Spec("wait-then-act"));
  EXPECT_EQ(plan.scenario, &scenarios::FindScenario("wait-then-act"));
  EXPECT_EQ(plan.robot_path, configs::RobotConfigPath(TAVIS_CONFIG_DIR, "reachy2"));
  EXPECT_EQ(plan.robot_yaml, configs::YamlValue::ReadFileText(plan.robot_path));
  EXPECT_EQ(plan.model.robot.name, "reachy2");
  EXPECT_TRUE(plan.perturbations.empty());
  EXPECT_FALSE(plan.model.view_perturbation.moves_cameras());
}

// The world is the robot in the task's scene with the levels applied, as each front end built it
// by hand before: a distractors level's objects after the task's, a camera level's field of view.
TEST(ScenePlan, IsTheRobotInTheTasksSceneWithTheLevelsApplied) {
  SceneSpec spec = Spec("clutter-pick-cube");
  spec.perturbations = {"camera:fov-wide", "distractors:two"};
  const ScenePlan plan = PlanScene(spec);
  engine::WorldModel by_hand =
      BuildWorldModel(configs::LoadRobotModel(plan.robot_path), scenarios::FindScenario("clutter-pick-cube"));
  perturb::ApplyPerturbations(TAVIS_CONFIG_DIR, spec.perturbations, spec.seed, &by_hand);
  ASSERT_EQ(plan.perturbations.size(), 2u);
  EXPECT_EQ(plan.perturbations[0].name, "fov-wide");
  EXPECT_EQ(plan.perturbations[1].name, "two");
  EXPECT_EQ(plan.model.num_objects(), by_hand.num_objects());
  EXPECT_GT(plan.model.num_objects(), plan.model.num_task_objects());
  EXPECT_EQ(plan.model.view_perturbation.head_fov_scale, by_hand.view_perturbation.head_fov_scale);
  EXPECT_NE(plan.model.view_perturbation.head_fov_scale, 1.0);
  EXPECT_EQ(plan.model.view_perturbation.noise_seed, 5u);
}

TEST(ScenePlan, BadNamesAreRefusedNamingThem) {
  const auto error_of = [](const SceneSpec& spec) {
    try {
      PlanScene(spec);
    } catch (const std::exception& error) {
      return std::string(error.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_NE(error_of(Spec("fly-to-moon")).find("'fly-to-moon'"), std::string::npos);
  SceneSpec robot = Spec("wait-then-act");
  robot.robot = "r2d2";
  EXPECT_NE(error_of(robot).find("r2d2"), std::string::npos);
  SceneSpec level = Spec("wait-then-act");
  level.perturbations = {"lighting:pitch-black"};
  EXPECT_NE(error_of(level).find("no level 'pitch-black'"), std::string::npos);
}

// Every scene setting has a flag of its own, which every command registers from this table.
TEST(SceneSettings, EachSettingHasItsOwnFlagAndHelp) {
  for (const char* key : {"task", "robot", "split", "seed", "perturbations", "expert_mode"}) {
    const SceneSetting& setting = SceneSettingNamed(key);
    EXPECT_EQ(setting.flag[0], '-') << key;
    EXPECT_FALSE(setting.help.empty()) << key;
  }
  EXPECT_EQ(std::string(SceneSettingNamed("perturbations").flag), "--perturb");
}

}  // namespace
}  // namespace tavis::batch::scene
