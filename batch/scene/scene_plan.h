// A scene spec resolved once: the task, the robot model parsed from the bytes of its file (kept,
// so that what a record says of the robot file is what the model was built from), the chosen
// perturbation levels as their files say, and the world model (the robot in the task's scene, the
// levels applied). Every front end builds its VecEnv from a plan's model; none builds a world by
// hand.
#pragma once

#include <string>
#include <vector>

#include "batch/perturb/perturbation_catalog.h"
#include "batch/scene/scene_spec.h"
#include "engine/world_model.h"
#include "scenarios/scenario.h"

namespace tavis::batch::scene {

struct ScenePlan {
  SceneSpec spec;  // as given
  const scenarios::ScenarioDef* scenario = nullptr;
  // The robot file and its text, read once: the model is parsed from these bytes, and a record's
  // identity (output::ConfigIdentityFromTexts) is taken from the same.
  std::string robot_path;
  std::string robot_yaml;
  std::vector<perturb::PerturbationLevel> perturbations;  // the levels chosen, in the spec's order
  engine::WorldModel model;                               // the robot in the task's scene, the levels applied
};

// Finds the task, reads and parses the robot file, resolves the perturbation levels and builds
// the world model. Throws std::invalid_argument naming an unknown task or a bad perturbation
// choice, configs::ConfigError naming an unknown robot or a bad robot or level file.
ScenePlan PlanScene(const SceneSpec& spec);

}  // namespace tavis::batch::scene
