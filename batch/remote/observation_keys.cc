#include "batch/remote/observation_keys.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "batch/observation_contract.h"
#include "batch/scene_render.h"
#include "configs/yaml_reader.h"

namespace tavis::batch::remote {
namespace {

constexpr const char* kContractPreset = "tavis";
const char* const kPresets[] = {kContractPreset, "libero", "aloha"};  // the contract's first: it is built in

std::string JoinPath(const KeyPath& path) {
  std::string text;
  for (const std::string& part : path) text += (text.empty() ? "" : "/") + part;
  return text;
}

KeyPath ReadKeyPath(const configs::YamlValue& value) {
  KeyPath path = value.IsSequence() ? value.AsStrings() : KeyPath{value.AsString()};
  if (path.empty()) value.Fail("a key path needs at least one key");
  for (const std::string& part : path) {
    if (part.empty()) value.Fail("empty key");
  }
  return path;
}

// True when one path is a prefix of the other: their values would overwrite each other.
bool Collide(const KeyPath& a, const KeyPath& b) {
  const std::size_t n = std::min(a.size(), b.size());
  return std::equal(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(n), b.begin());
}

ObservationKeys ReadKeys(const configs::YamlValue& root, std::string source) {
  ObservationKeys keys;
  keys.source = std::move(source);
  const configs::YamlValue cameras = root.Required("cameras");
  for (const std::string& camera : batch::SceneCameraNames()) {
    if (const auto key = cameras.Optional(camera)) keys.cameras.emplace_back(camera, ReadKeyPath(*key));
  }
  cameras.ExpectNoOtherKeys();
  const auto listed = [&keys](const char* name) {
    return std::any_of(keys.cameras.begin(), keys.cameras.end(),
                       [name](const auto& entry) { return entry.first == name; });
  };
  if (listed("fixed") && !listed("head"))
    cameras.Fail("fixed replaces head under the fixed protocol: give head a key too");
  if (keys.PolicyCameras().empty())
    cameras.Fail("no camera for the policy (give at least one of head, left_wrist, right_wrist)");
  keys.state = ReadKeyPath(root.Required("state"));
  keys.prompt = ReadKeyPath(root.Required("prompt"));
  if (const auto task = root.Optional("task")) keys.task = ReadKeyPath(*task);
  const std::string layout = root.String("image_layout");
  if (layout != "hwc" && layout != "chw")
    root.Required("image_layout").Fail("expected hwc or chw, got '" + layout + "'");
  keys.image_layout = layout == "hwc" ? ImageLayout::kHwc : ImageLayout::kChw;
  keys.image_width = root.Int("image_width");
  keys.image_height = root.Int("image_height");
  if (keys.image_width < 8 || keys.image_height < 8) {
    root.Fail("image_width and image_height must be at least 8, got " + std::to_string(keys.image_width) + "x" +
              std::to_string(keys.image_height));
  }
  keys.letterbox = root.Required("letterbox").AsBool();
  root.ExpectNoOtherKeys();

  // The fixed camera may share head's key (it replaces head); any other overlap loses a value.
  std::vector<std::pair<std::string, KeyPath>> sent = keys.cameras;
  sent.erase(std::remove_if(sent.begin(), sent.end(), [](const auto& entry) { return entry.first == "fixed"; }),
             sent.end());
  sent.emplace_back("state", keys.state);
  sent.emplace_back("prompt", keys.prompt);
  if (!keys.task.empty()) sent.emplace_back("task", keys.task);
  for (const auto& [name, path] : sent) {
    for (const char* field : batch::contract::kRequestFields) {
      if (path.front() == field)
        root.Fail(name + " uses the key '" + field + "', which every request carries as a request field");
    }
  }
  for (std::size_t i = 0; i < sent.size(); ++i) {
    for (std::size_t j = i + 1; j < sent.size(); ++j) {
      if (Collide(sent[i].second, sent[j].second)) {
        root.Fail(sent[i].first + " and " + sent[j].first + " overlap at key '" + JoinPath(sent[i].second) + "' / '" +
                  JoinPath(sent[j].second) + "'");
      }
    }
  }
  return keys;
}

// The entries whose paths start with the same first key become one nested map, in first-seen order.
Value Nest(std::vector<std::pair<KeyPath, Value>> entries, std::size_t depth) {
  Value::Map map;
  std::vector<bool> used(entries.size(), false);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (used[i]) continue;
    const std::string& key = entries[i].first[depth];
    if (entries[i].first.size() == depth + 1) {
      map.push_back({key, std::move(entries[i].second)});
      continue;
    }
    std::vector<std::pair<KeyPath, Value>> group;
    for (std::size_t j = i; j < entries.size(); ++j) {
      if (!used[j] && entries[j].first.size() > depth + 1 && entries[j].first[depth] == key) {
        used[j] = true;
        group.push_back(std::move(entries[j]));
      }
    }
    map.push_back({key, Nest(std::move(group), depth + 1)});
  }
  return map;
}

// The shape of one env's image of `camera` as sent: H x W x 3 or 3 x H x W, padded to the keys'
// size when letterboxed.
std::vector<std::int64_t> ImageShape(const render::ImageBatch& images, int camera, const ObservationKeys& keys) {
  const std::int64_t width = keys.letterbox ? keys.image_width : images.width(camera);
  const std::int64_t height = keys.letterbox ? keys.image_height : images.height(camera);
  return keys.image_layout == ImageLayout::kHwc ? std::vector<std::int64_t>{height, width, 3}
                                                : std::vector<std::int64_t>{3, height, width};
}

// The rendered image of `camera` padded to the sent size (centred black bands) and laid out, written to
// `pixels` (zeroed, of ImageShape's size).
void WritePolicyImage(const render::ImageBatch& images, int env, int camera, const ObservationKeys& keys,
                      std::uint8_t* pixels) {
  const int rendered_width = images.width(camera);
  const int rendered_height = images.height(camera);
  const int width = keys.letterbox ? keys.image_width : rendered_width;
  const int height = keys.letterbox ? keys.image_height : rendered_height;
  const int left = (width - rendered_width) / 2;
  const int top = (height - rendered_height) / 2;
  const uint8_t* rgb = images.rgb(env, camera);
  const std::size_t plane = static_cast<std::size_t>(width) * height;
  for (int y = 0; y < rendered_height; ++y) {
    for (int x = 0; x < rendered_width; ++x) {
      const uint8_t* source = rgb + (static_cast<std::size_t>(y) * rendered_width + x) * 3;
      const std::size_t pixel = static_cast<std::size_t>(y + top) * width + (x + left);
      for (int c = 0; c < 3; ++c) {
        pixels[keys.image_layout == ImageLayout::kHwc ? pixel * 3 + c : c * plane + pixel] = source[c];
      }
    }
  }
}

// The images of `camera` for `envs`, stacked on a leading axis when `stacked`.
NdArray PolicyImages(const render::ImageBatch& images, const std::vector<int>& envs, int camera,
                     const ObservationKeys& keys, bool stacked) {
  std::vector<std::int64_t> shape = ImageShape(images, camera, keys);
  const std::size_t size = ElementCount(shape);
  std::vector<std::uint8_t> pixels(size * envs.size(), 0);
  for (std::size_t i = 0; i < envs.size(); ++i)
    WritePolicyImage(images, envs[i], camera, keys, pixels.data() + i * size);
  if (stacked) shape.insert(shape.begin(), static_cast<std::int64_t>(envs.size()));
  return MakeUint8Array(std::move(shape), std::move(pixels));
}

template <typename T>
NdArray VectorArray(const char* dtype, const std::vector<T>& values) {
  NdArray array{
      dtype, {static_cast<std::int64_t>(values.size())}, std::vector<std::uint8_t>(values.size() * sizeof(T))};
  if (!values.empty()) std::memcpy(array.data.data(), values.data(), array.data.size());
  return array;
}

const char* PromptOf(const batch::Observation& observation, int env) {
  const char* prompt = observation.prompts[static_cast<std::size_t>(env)];
  return prompt != nullptr ? prompt : "";
}

// The entries of a request for `envs`: one env's values, or with `stacked` every value on a
// leading env axis.
std::vector<std::pair<KeyPath, Value>> RequestEntries(const batch::Observation& observation,
                                                      const ObservationKeys& keys,
                                                      const std::vector<std::string>& cameras,
                                                      const std::vector<int>& envs, bool stacked) {
  if (observation.images == nullptr || observation.proprioception == nullptr) {
    throw std::logic_error("a served policy needs the images and proprioception of the episode driver");
  }
  std::vector<std::pair<KeyPath, Value>> entries;
  for (int camera = 0; camera < static_cast<int>(cameras.size()); ++camera) {
    entries.emplace_back(keys.KeyOf(cameras[static_cast<std::size_t>(camera)]),
                         PolicyImages(*observation.images, envs, camera, keys, stacked));
  }
  const batch::ProprioceptionBatch& proprioception = *observation.proprioception;
  const int state_size = proprioception.state_size();
  std::vector<float> state;
  for (int env : envs) state.insert(state.end(), proprioception.state(env), proprioception.state(env) + state_size);
  std::vector<std::int64_t> state_shape = {state_size};
  if (stacked) state_shape.insert(state_shape.begin(), static_cast<std::int64_t>(envs.size()));
  entries.emplace_back(keys.state, MakeFloat32Array(state_shape, state));

  const int ticks_per_step = observation.model.physics.controls_per_policy();
  std::vector<std::int64_t> env_index, episode_index, step;
  std::vector<std::uint8_t> is_first;
  Value::Array prompts;
  for (int env : envs) {
    env_index.push_back(env);
    episode_index.push_back(observation.state.episode[env]);
    // Counted from the policy's first observation: under ood-init-pose the reset's warm-up
    // steps come before step 0, so a stateful server sees every episode start at step 0.
    step.push_back((observation.state.control_step[env] - observation.state.policy_start_tick[env]) / ticks_per_step);
    is_first.push_back(step.back() == 0 ? 1 : 0);
    prompts.emplace_back(PromptOf(observation, env));
  }
  const auto prompt_value = [&] { return stacked ? Value(prompts) : Value(PromptOf(observation, envs.front())); };
  entries.emplace_back(keys.prompt, prompt_value());
  if (!keys.task.empty()) entries.emplace_back(keys.task, prompt_value());
  namespace contract = batch::contract;
  if (stacked) {
    entries.emplace_back(KeyPath{contract::kEnvIndexField}, VectorArray("<i8", env_index));
    entries.emplace_back(KeyPath{contract::kEpisodeIndexField}, VectorArray("<i8", episode_index));
    entries.emplace_back(KeyPath{contract::kStepField}, VectorArray("<i8", step));
    entries.emplace_back(KeyPath{contract::kIsFirstField}, VectorArray("|b1", is_first));
    entries.emplace_back(KeyPath{contract::kBatchSizeField}, Value(static_cast<std::int64_t>(envs.size())));
  } else {
    entries.emplace_back(KeyPath{contract::kEnvIndexField}, Value(env_index.front()));
    entries.emplace_back(KeyPath{contract::kEpisodeIndexField}, Value(episode_index.front()));
    entries.emplace_back(KeyPath{contract::kStepField}, Value(step.front()));
    entries.emplace_back(KeyPath{contract::kIsFirstField}, Value(is_first.front() != 0));
  }
  return entries;
}

int IntAt(const nlohmann::json& value, const std::string& where) {
  if (!value.is_number_integer()) throw std::invalid_argument(where + " must be an integer, got " + value.dump());
  return value.get<int>();
}

}  // namespace

std::vector<std::string> ObservationKeys::PolicyCameras() const {
  std::vector<std::string> names;
  for (const auto& [camera, key] : cameras) {
    if (camera != "fixed") names.push_back(camera);
  }
  return names;
}

const KeyPath& ObservationKeys::KeyOf(const std::string& camera) const {
  for (const auto& [name, key] : cameras) {
    if (name == camera) return key;
  }
  if (camera == "fixed") return KeyOf("head");
  throw std::logic_error("the observation keys " + source + " have no key for camera '" + camera + "'");
}

std::string KeyPresetNames() {
  std::string names;
  for (const char* preset : kPresets) names += (names.empty() ? "" : ", ") + std::string(preset);
  return names;
}

ObservationKeys ContractKeys() {
  namespace contract = batch::contract;
  ObservationKeys keys;
  keys.source = kContractPreset;
  for (const std::string& camera : batch::SceneCameraNames()) {
    keys.cameras.emplace_back(camera, KeyPath{contract::CameraImageKey(camera)});
  }
  keys.state = {contract::kStateKey};
  keys.prompt = {contract::kPromptKey};
  keys.task = {contract::kTaskKey};
  keys.image_layout = ImageLayout::kHwc;
  keys.image_width = contract::kServedImageWidth;
  keys.image_height = contract::kServedImageHeight;
  keys.letterbox = false;
  return keys;
}

ObservationKeys LoadObservationKeys(const std::string& preset_or_path, const std::string& config_dir) {
  return LoadObservationKeysWithFile(preset_or_path, config_dir).keys;
}

LoadedObservationKeys LoadObservationKeysWithFile(const std::string& preset_or_path, const std::string& config_dir) {
  if (preset_or_path == kContractPreset) return {ContractKeys(), "", ""};
  std::string file = preset_or_path;
  if (std::find(std::begin(kPresets), std::end(kPresets), preset_or_path) != std::end(kPresets)) {
    file = config_dir + "/policy_keys/" + preset_or_path + ".yaml";
  } else if (!std::filesystem::is_regular_file(preset_or_path)) {
    throw std::invalid_argument("observation keys '" + preset_or_path + "' are neither a preset (" + KeyPresetNames() +
                                ") nor a YAML file");
  }
  std::string text = configs::YamlValue::ReadFileText(file);
  ObservationKeys keys = ReadKeys(configs::YamlValue::LoadString(text, file), preset_or_path);
  return {std::move(keys), std::move(file), std::move(text)};
}

std::pair<int, int> RenderSize(const ObservationKeys& keys) {
  if (!keys.letterbox) return {keys.image_width, keys.image_height};
  // The cameras' sensors are 4:3 (640 x 480 in the reference).
  const int width = std::min(keys.image_width, keys.image_height * 4 / 3) / 2 * 2;
  const int height = width * 3 / 4 / 2 * 2;
  return {width, height};
}

ObservationKeys LoadDatasetKeys(const std::string& dataset_dir, int state_size) {
  const std::string path = (std::filesystem::path(dataset_dir) / "meta" / "info.json").string();
  std::ifstream in(path);
  if (!in)
    throw std::invalid_argument("dataset '" + dataset_dir + "': cannot open " + path + " (not a LeRobot dataset?)");
  nlohmann::json info;
  try {
    info = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    throw std::invalid_argument(path + ": not valid JSON: " + error.what());
  }
  if (!info.is_object() || !info.contains("features") || !info["features"].is_object()) {
    throw std::invalid_argument(path + ": no \"features\" object");
  }
  const nlohmann::json& features = info["features"];
  ObservationKeys keys = ContractKeys();
  keys.source = "dataset " + dataset_dir;
  keys.cameras.clear();
  int width = 0, height = 0;
  for (const std::string& camera : batch::SceneCameraNames()) {
    const std::string key = batch::contract::CameraImageKey(camera);
    if (!features.contains(key)) continue;
    const nlohmann::json& shape = features[key].value("shape", nlohmann::json());
    const std::string where = path + ": features." + key + ".shape";
    if (!shape.is_array() || shape.size() != 3 || IntAt(shape[2], where + "[2]") != 3) {
      throw std::invalid_argument(where + " must be [height, width, 3], got " + shape.dump());
    }
    const int feature_height = IntAt(shape[0], where + "[0]"), feature_width = IntAt(shape[1], where + "[1]");
    if (width != 0 && (feature_width != width || feature_height != height)) {
      throw std::invalid_argument(where + " is " + std::to_string(feature_width) + "x" +
                                  std::to_string(feature_height) + " but another camera of the dataset is " +
                                  std::to_string(width) + "x" + std::to_string(height) +
                                  ": one size is served to every camera");
    }
    width = feature_width;
    height = feature_height;
    keys.cameras.emplace_back(camera, KeyPath{key});
  }
  if (keys.PolicyCameras().empty()) {
    throw std::invalid_argument(path +
                                ": no image feature of a policy camera (observation.images.OBS_HEAD, OBS_WRIST_LEFT, "
                                "OBS_WRIST_RIGHT)");
  }
  const bool has_fixed =
      std::any_of(keys.cameras.begin(), keys.cameras.end(), [](const auto& e) { return e.first == "fixed"; });
  const bool has_head =
      std::any_of(keys.cameras.begin(), keys.cameras.end(), [](const auto& e) { return e.first == "head"; });
  if (has_fixed && !has_head) {
    // A fixed-camera-only dataset: the fixed camera is the scene camera the policy reads.
    throw std::invalid_argument(path +
                                ": has observation.images.OBS_FIXED but no OBS_HEAD; record the dataset with both");
  }
  keys.image_width = width;
  keys.image_height = height;
  const nlohmann::json& state = features.value(batch::contract::kStateKey, nlohmann::json());
  const nlohmann::json& state_shape = state.is_object() ? state.value("shape", nlohmann::json()) : nlohmann::json();
  if (!state_shape.is_array() || state_shape.size() != 1 || !state_shape[0].is_number_integer()) {
    throw std::invalid_argument(path + ": features.observation.state.shape must be [D], got " + state_shape.dump());
  }
  if (state_shape[0].get<int>() != state_size) {
    throw std::invalid_argument(path + ": observation.state has " + state_shape[0].dump() +
                                " entries, but this robot's has " + std::to_string(state_size) +
                                " (a dataset of another robot?)");
  }
  return keys;
}

std::vector<std::string> LayoutDifferences(const ObservationKeys& served, const ObservationKeys& expected) {
  std::vector<std::string> differences;
  const auto key_of = [](const ObservationKeys& keys, const std::string& camera) -> std::string {
    for (const auto& [name, key] : keys.cameras) {
      if (name == camera) return JoinPath(key);
    }
    return "";
  };
  for (const std::string& camera : batch::SceneCameraNames()) {
    const std::string a = key_of(served, camera), b = key_of(expected, camera);
    if (a != b) {
      differences.push_back("camera " + camera + ": served " + (a.empty() ? "not at all" : "as '" + a + "'") + ", " +
                            expected.source + " has " + (b.empty() ? "none" : "'" + b + "'"));
    }
  }
  const auto compare = [&](const char* what, const KeyPath& a, const KeyPath& b) {
    if (a != b) {
      differences.push_back(std::string(what) + ": served as '" + JoinPath(a) + "', " + expected.source + " reads '" +
                            JoinPath(b) + "'");
    }
  };
  compare("state", served.state, expected.state);
  compare("prompt", served.prompt, expected.prompt);
  compare("task", served.task, expected.task);
  if (served.image_width != expected.image_width || served.image_height != expected.image_height) {
    differences.push_back("image size: served " + std::to_string(served.image_width) + "x" +
                          std::to_string(served.image_height) + ", " + expected.source + " has " +
                          std::to_string(expected.image_width) + "x" + std::to_string(expected.image_height));
  }
  if (served.image_layout != expected.image_layout)
    differences.push_back("image layout: served and expected differ (hwc/chw)");
  if (served.letterbox != expected.letterbox) {
    differences.push_back(std::string("letterbox: served ") + (served.letterbox ? "letterboxed" : "full-frame") + ", " +
                          expected.source + (expected.letterbox ? " letterboxed" : " full-frame"));
  }
  return differences;
}

Value BuildRequest(const batch::Observation& observation, const ObservationKeys& keys,
                   const std::vector<std::string>& cameras, int env) {
  return Nest(RequestEntries(observation, keys, cameras, {env}, false), 0);
}

Value BuildBatchRequest(const batch::Observation& observation, const ObservationKeys& keys,
                        const std::vector<std::string>& cameras, const std::vector<int>& envs) {
  if (envs.empty()) throw std::logic_error("a batched request needs at least one env");
  return Nest(RequestEntries(observation, keys, cameras, envs, true), 0);
}

}  // namespace tavis::batch::remote
