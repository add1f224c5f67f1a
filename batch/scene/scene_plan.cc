#include "batch/scene/scene_plan.h"

#include "batch/vec_env.h"
#include "configs/robot_config.h"
#include "configs/yaml_reader.h"
#include "scenarios/registry.h"

namespace tavis::batch::scene {

ScenePlan PlanScene(const SceneSpec& spec) {
  ScenePlan plan;
  plan.spec = spec;
  plan.scenario = &scenarios::FindScenario(spec.task);
  plan.robot_path = configs::RobotConfigPath(spec.config_dir, spec.robot);
  plan.robot_yaml = configs::YamlValue::ReadFileText(plan.robot_path);
  plan.model = BuildWorldModel(configs::ParseRobotModel(plan.robot_yaml, plan.robot_path), *plan.scenario);
  plan.perturbations = perturb::ResolvePerturbations(spec.config_dir, spec.perturbations);
  perturb::ApplyPerturbationLevels(plan.perturbations, spec.seed, &plan.model);
  return plan;
}

}  // namespace tavis::batch::scene
