// One scene, as every front end names it: the task, the robot, the split, the seed, the
// perturbation levels, how the scripted expert's head leads and where the config files are.
// `tavis eval`, `tavis demos`, `tavis render`, `tavis audit`, the Python env and the benches
// each fill one in and plan it with PlanScene (scene_plan.h), so the world is built in one place.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scenarios/expert/expert_mode.h"
#include "scenarios/split.h"

namespace tavis::batch::scene {

struct SceneSpec {
  std::string task = "clutter-pick-cube";
  std::string robot = "gr1t2";  // configs/robots/<robot>.yaml under config_dir
  scenarios::Split split = scenarios::Split::kId;
  uint64_t seed = 0;  // episode i draws its randomness from (seed, i)
  // Perturbation levels, "AXIS:LEVEL" each, at most one per axis (batch/perturb/perturbation_catalog.h,
  // docs/perturbations.md); empty: the base scene. Episode i keeps its base scene under every one.
  std::vector<std::string> perturbations;
  // How the scripted expert's head leads (gaze-first, or head-still for the fixed-camera bias
  // ablation); the scene is the same under both.
  scenarios::expert::ExpertMode expert_mode = scenarios::expert::ExpertMode::kGazeFirst;
  std::string config_dir;  // holds robots/*.yaml and perturbations/*.yaml
};

// The scene of a config that declares the scene's settings as members of the spec's names and
// types (EvaluationCellConfig, DemoConfig: their settings tables need members of their own), with
// `task` its task (a recording names several).
template <typename Config>
SceneSpec SceneOf(const Config& config, const std::string& task) {
  SceneSpec spec;
  spec.task = task;
  spec.robot = config.robot;
  spec.split = config.split;
  spec.seed = config.seed;
  spec.perturbations = config.perturbations;
  spec.expert_mode = config.expert_mode;
  spec.config_dir = config.config_dir;
  return spec;
}

}  // namespace tavis::batch::scene
