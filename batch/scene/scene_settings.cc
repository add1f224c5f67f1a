#include "batch/scene/scene_settings.h"

#include "kinematics/invariant.h"
#include "scenarios/registry.h"

namespace tavis::batch::scene {

const std::vector<SceneSetting>& SceneSettings() {
  static const std::vector<SceneSetting> settings = {
      {"task", "--task", "Task (" + scenarios::KnownTasks() + ")"},
      {"robot", "--robot", "Robot: gr1t2 or reachy2 (configs/robots/<name>.yaml)"},
      {"split", "--split", "Split: id, ood-spatial or ood-init-pose"},
      {"seed", "--seed", "Seed: episode i draws its randomness from (seed, i)"},
      {"perturbations", "--perturb",
       "AXIS:LEVEL: run every episode under a perturbation level (configs/perturbations/AXIS.yaml:\n"
       "camera, sensor, lighting, appearance, distractors, language, runtime; docs/perturbations.md);\n"
       "repeat it for several axes, one level each. Episode i keeps its base scene, so its results pair\n"
       "with the unperturbed ones (a distractors level adds its objects, a runtime level moves the target\n"
       "under the hand); the levels are recorded with the results"},
      {"expert_mode", "--expert-mode",
       "How the scripted expert's head leads: gaze-first (looks at the cue and the target, then acts)\n"
       "or head-still (neck still at its reset pose, hands act as soon as the task allows)"},
  };
  return settings;
}

const SceneSetting& SceneSettingNamed(const std::string& key) {
  for (const SceneSetting& setting : SceneSettings()) {
    if (key == setting.key) return setting;
  }
  TAVIS_INVARIANT(false, ("no scene setting is named '" + key + "'").c_str());
  return SceneSettings().front();
}

}  // namespace tavis::batch::scene
