// A scene's settings as the commands take them, each declared once: its key (as the records and
// the Python env's keyword arguments name it), its flag and its help text. Every subcommand that
// runs a scene (eval, demos, render, audit) registers its flags from this table
// (tools/scene_options.h), and `tavis eval`'s settings table (batch/cell/cell_settings.cc) takes
// their flags and texts from here.
#pragma once

#include <string>
#include <vector>

namespace tavis::batch::scene {

struct SceneSetting {
  const char* key;   // SceneSpec's member, the records' key and the Python keyword
  const char* flag;  // the commands' flag
  std::string help;
};

// task, robot, split, seed, perturbations, expert_mode (the config dir is every command's
// --config-dir, registered with the robot files' check).
const std::vector<SceneSetting>& SceneSettings();
// The setting with that key; a key no setting has is a bug (an invariant aborts).
const SceneSetting& SceneSettingNamed(const std::string& key);

}  // namespace tavis::batch::scene
