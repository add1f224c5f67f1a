#include "batch/cell/cell_plan.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "batch/camera_protocol.h"
#include "batch/cell/declared_contract.h"
#include "batch/output/config_identity.h"
#include "batch/output/setting_error.h"
#include "batch/remote/websocket_url.h"
#include "batch/scene/scene_plan.h"
#include "batch/scene_render.h"
#include "configs/yaml_reader.h"

namespace tavis::batch::cell {
namespace {

PolicyKind KnownPolicy(const std::string& name) {
  const PolicyDecl* policy = FindPolicy(name);
  if (policy == nullptr) {
    throw std::invalid_argument("unknown policy '" + name + "' (known: " + PolicyNames(/*built_in_only=*/false) + ")");
  }
  return policy->kind;
}

// The settings that need no file: the table's ranges and scopes, what a policy needs, the
// episodes to run, the image size and the extra cameras.
void CheckSettings(const EvaluationCellConfig& config, PolicyKind policy) {
  CheckSettingValues(config);
  if (policy == PolicyKind::kOpenpi && config.servers.empty()) {
    throw output::SettingError("servers", "must name a policy server (ws://HOST:PORT) for policy 'openpi'");
  }
  CheckServerUrls(config);
  if (policy == PolicyKind::kReplay && config.actions_file.empty()) {
    throw output::SettingError("actions_file",
                               "must name a CSV of actions or a folder of episode_<i>.csv for policy 'replay'");
  }
  if ((config.image_width == 0) != (config.image_height == 0)) {
    throw output::SettingError("image_width",
                               "and image_height must be given together (0 x 0: the policy's own), got " +
                                   std::to_string(config.image_width) + "x" + std::to_string(config.image_height));
  }
  CameraSettings cameras;
  cameras.cameras = config.render_cameras;
  if (config.image_width != 0) {
    cameras.width = config.image_width;
    cameras.height = config.image_height;
  }
  ValidateCameraSettings(cameras);
}

// The files a plan reads, each once: what it builds from them and what cell.json records of them
// (the identity) come from the same bytes.
struct PlanFiles {
  std::string robot_path;
  std::string robot_yaml;
  std::string key_file;  // a served policy's key file, "" when none was read
  std::string key_text;
};

// The served policy's request layout: the one its server declares when it declares a contract
// (declared_contract.h), else the dataset's when one is named and no keys are, else the keys'
// (preset or file), with an explicit image size taking the place of its own; a layout that
// differs from a dataset named alongside is reported.
void PlanServedLayout(CellPlan& plan, PlanFiles& files) {
  const EvaluationCellConfig& config = plan.config;
  const int state_size = static_cast<int>(plan.model.robot.observation_state.size());
  std::optional<remote::ObservationKeys> dataset;
  if (!config.observation_dataset.empty()) dataset = remote::LoadDatasetKeys(config.observation_dataset, state_size);
  remote::ObservationKeys keys;
  if (config.declared_contract) {
    keys = AdoptDeclaredContract(plan.config, dataset, state_size);
  } else if (dataset && !config.observation_keys_given) {
    keys = *dataset;
  } else {
    remote::LoadedObservationKeys loaded =
        remote::LoadObservationKeysWithFile(config.observation_keys, config.config_dir);
    keys = std::move(loaded.keys);
    files.key_file = std::move(loaded.file);
    files.key_text = std::move(loaded.text);
  }
  if (config.image_width != 0) {
    keys.image_width = config.image_width;
    keys.image_height = config.image_height;
  }
  if (dataset) plan.layout_differences = remote::LayoutDifferences(keys, *dataset);
  plan.image_width = keys.image_width;
  plan.image_height = keys.image_height;
  std::tie(plan.render_width, plan.render_height) = remote::RenderSize(keys);
  plan.policy_cameras = ProtocolCameras(keys.PolicyCameras(), config.camera);
  plan.keys = std::move(keys);
}

// A built-in policy takes no images; the image size is the one given, or the reference's.
void PlanBuiltinImages(CellPlan& plan) {
  const CameraSettings reference;
  plan.image_width = plan.config.image_width != 0 ? plan.config.image_width : reference.width;
  plan.image_height = plan.config.image_height != 0 ? plan.config.image_height : reference.height;
  plan.render_width = plan.image_width;
  plan.render_height = plan.image_height;
}

// The policy's cameras first, then the extra ones; how long the policy holds an action (the
// expert decides at every control tick, holding its action itself at 20 Hz; the others act at
// the policy rate), and so what the recorder keeps.
void PlanCamerasAndRecords(CellPlan& plan) {
  plan.cameras = plan.policy_cameras;
  for (const std::string& name : plan.config.render_cameras) {
    if (std::find(plan.cameras.begin(), plan.cameras.end(), name) == plan.cameras.end()) plan.cameras.push_back(name);
  }
  const engine::PhysicsSettings& physics = plan.model.physics;
  plan.control_ticks_per_action = plan.policy == PolicyKind::kExpert ? 1 : physics.controls_per_policy();
  plan.record =
      RecordSettingsFor(plan.config, plan.control_ticks_per_action, physics, plan.policy == PolicyKind::kOpenpi);
}

// What cell.json records of the files (CellIdentityJson), from the bytes the plan read; a key
// file the identity names but the layout did not come from (a dataset's) is read here.
nlohmann::json PlanIdentity(const CellPlan& plan, const PlanFiles& files) {
  std::string keys_identity;
  if (plan.policy == PolicyKind::kOpenpi) {
    const std::string file = output::ObservationKeysIdentityFile(plan.config.config_dir, plan.config.observation_keys);
    const std::string bytes = file.empty()             ? ""
                              : file == files.key_file ? files.key_text
                                                       : configs::YamlValue::ReadFileText(file);
    keys_identity = output::ObservationKeysIdentity(file, bytes);
  }
  return output::ConfigIdentityFromTexts(files.robot_path, files.robot_yaml, keys_identity);
}

}  // namespace

void CheckServerUrls(const EvaluationCellConfig& config) {
  for (const std::string& server : config.servers) {
    try {
      remote::ParseWebSocketUrl(server);
    } catch (const std::invalid_argument& error) {
      throw output::SettingsAdvice<std::invalid_argument>(output::SettingKey("servers") + ": " + error.what());
    }
  }
}

void CellPlan::ContinueFrom(int64_t first) {
  if (first < config.episode_start || first > end_episode()) {
    throw std::invalid_argument("the first episode to run must be in [" + std::to_string(config.episode_start) + ", " +
                                std::to_string(end_episode()) + "], got " + std::to_string(first));
  }
  config.first_episode = first;
}

nlohmann::json CellIdentityJson(const EvaluationCellConfig& config) {
  const bool served = IsPolicy(config.policy, PolicyKind::kOpenpi);
  return output::ConfigIdentityJson(config.config_dir, config.robot, served ? config.observation_keys : "");
}

// What the recorder keeps: GALT sampled when the policy acted (every `hold_ticks` control ticks),
// as the reference records actions at its policy rate, and for a policy acting faster also at the
// 20 Hz policy rate; none under the fixed protocol, where there is no head to lead.
RecordSettings RecordSettingsFor(const EvaluationCellConfig& config, int hold_ticks,
                                 const engine::PhysicsSettings& physics, bool served) {
  RecordSettings settings;
  settings.head_moves = !UsesFixedView(config.camera);
  if (!UsesFixedView(config.camera)) {
    settings.galt_stride = hold_ticks;
    settings.galt_fps = physics.control_hz / hold_ticks;
    const int policy_stride = physics.controls_per_policy();
    if (hold_ticks < policy_stride) {
      settings.policy_rate_stride = policy_stride;
      settings.policy_rate_fps = physics.control_hz / policy_stride;
    }
  }
  // A served policy's chunks, and a 20 Hz expert's held actions, are kept at the policy rate for
  // --policy replay, which plays them back exactly.
  const bool expert_at_policy_rate = IsPolicy(config.policy, PolicyKind::kExpert) && config.expert_hz != 60;
  settings.replay_stride = served ? hold_ticks : expert_at_policy_rate ? physics.controls_per_policy() : 0;
  settings.keep_actions = config.keep_actions;
  return settings;
}

CellPlan PlanCell(const EvaluationCellConfig& config) {
  CellPlan plan;
  plan.config = config;
  plan.policy = KnownPolicy(config.policy);
  CheckSettings(config, plan.policy);
  plan.ContinueFrom(config.first_episode);
  scene::ScenePlan scene = scene::PlanScene(scene::SceneOf(config, config.task));
  plan.scenario = scene.scenario;
  PlanFiles files;
  files.robot_path = std::move(scene.robot_path);
  files.robot_yaml = std::move(scene.robot_yaml);
  plan.model = std::move(scene.model);
  plan.perturbations = std::move(scene.perturbations);
  const bool served = plan.policy == PolicyKind::kOpenpi;
  if (served) {
    PlanServedLayout(plan, files);
  } else {
    PlanBuiltinImages(plan);
  }
  PlanCamerasAndRecords(plan);
  plan.identity = PlanIdentity(plan, files);
  return plan;
}

}  // namespace tavis::batch::cell
