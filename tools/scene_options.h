// The flags of a scene's settings (batch/scene/scene_settings.h: task, robot, split, seed,
// perturbations, expert mode, and the config dir), registered by one function for every
// subcommand that runs a scene: eval, demos, render and audit each say where they keep each
// setting, and take the flag, its help text and its parsing from here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "batch/scene/scene_spec.h"

namespace tavis::tools {

// Where a command keeps each scene setting; null: the command has no such flag.
struct SceneFlags {
  std::string* task = nullptr;
  std::string* robot = nullptr;
  scenarios::Split* split = nullptr;
  uint64_t* seed = nullptr;
  std::vector<std::string>* perturbations = nullptr;
  scenarios::expert::ExpertMode* expert_mode = nullptr;
  std::string* config_dir = nullptr;
};

// Every setting of `spec` (which must outlive the parse); a command drops those it has no flag for.
SceneFlags FlagsOf(batch::scene::SceneSpec& spec);

// Adds the flag of every setting `flags` points to, in the table's order, showing its default
// (--config-dir: AddConfigDirOption). A split or expert mode that is none of its values throws
// std::invalid_argument naming the text; a perturbation is checked when the scene is planned.
void AddSceneOptions(CLI::App& command, const SceneFlags& flags);

}  // namespace tavis::tools
