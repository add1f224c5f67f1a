#include "tools/scene_options.h"

#include "batch/scene/scene_settings.h"
#include "tools/option_parsing.h"

namespace tavis::tools {
namespace {

using batch::scene::SceneSettingNamed;

// An option whose text is read into an enum by `read` (which names text that is none of its
// values), showing the current value written by `write` as its default.
template <typename T, typename Read, typename Write>
void AddEnumOption(CLI::App& command, const char* key, T& value, Read read, Write write) {
  const batch::scene::SceneSetting& setting = SceneSettingNamed(key);
  command
      .add_option_function<std::string>(
          setting.flag, [&value, read](const std::string& text) { value = read(text); }, setting.help)
      ->default_str(write(value));
}

void AddTextOption(CLI::App& command, const char* key, std::string& value) {
  const batch::scene::SceneSetting& setting = SceneSettingNamed(key);
  command.add_option(setting.flag, value, setting.help)->capture_default_str();
}

}  // namespace

SceneFlags FlagsOf(batch::scene::SceneSpec& spec) {
  return {&spec.task, &spec.robot, &spec.split, &spec.seed, &spec.perturbations, &spec.expert_mode, &spec.config_dir};
}

void AddSceneOptions(CLI::App& command, const SceneFlags& flags) {
  if (flags.task != nullptr) AddTextOption(command, "task", *flags.task);
  if (flags.robot != nullptr) AddTextOption(command, "robot", *flags.robot);
  if (flags.split != nullptr) {
    AddEnumOption(command, "split", *flags.split, scenarios::ParseSplit,
                  [](scenarios::Split split) { return scenarios::ToString(split); });
  }
  if (flags.seed != nullptr) AddSeedOption(command, *flags.seed, SceneSettingNamed("seed").help);
  if (flags.perturbations != nullptr) {
    const batch::scene::SceneSetting& setting = SceneSettingNamed("perturbations");
    command.add_option(setting.flag, *flags.perturbations, setting.help);
  }
  if (flags.expert_mode != nullptr) {
    AddEnumOption(command, "expert_mode", *flags.expert_mode, scenarios::expert::ParseExpertMode,
                  [](scenarios::expert::ExpertMode mode) { return scenarios::expert::ToString(mode); });
  }
  if (flags.config_dir != nullptr) AddConfigDirOption(command, *flags.config_dir);
}

}  // namespace tavis::tools
