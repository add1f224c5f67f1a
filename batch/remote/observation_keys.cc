#include "batch/remote/observation_keys.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "batch/scene_render.h"
#include "configs/yaml_reader.h"

namespace tavis::remote {
namespace {

const char* const kPresets[] = {"tavis", "libero", "aloha"};

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
    return std::any_of(keys.cameras.begin(), keys.cameras.end(), [name](const auto& entry) { return entry.first == name; });
  };
  if (listed("fixed") && !listed("head")) cameras.Fail("fixed replaces head under the fixed protocol: give head a key too");
  if (keys.PolicyCameras().empty()) cameras.Fail("no camera for the policy (give at least one of head, left_wrist, right_wrist)");
  keys.state = ReadKeyPath(root.Required("state"));
  keys.prompt = ReadKeyPath(root.Required("prompt"));
  const std::string layout = root.String("image_layout");
  if (layout != "hwc" && layout != "chw") root.Required("image_layout").Fail("expected hwc or chw, got '" + layout + "'");
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
  sent.erase(std::remove_if(sent.begin(), sent.end(), [](const auto& entry) { return entry.first == "fixed"; }), sent.end());
  sent.emplace_back("state", keys.state);
  sent.emplace_back("prompt", keys.prompt);
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

// The rendered image of `camera` padded to width x height (centred black bands) and laid out.
NdArray PolicyImage(const render::ImageBatch& images, int env, int camera, const ObservationKeys& keys) {
  const int rendered_width = images.width(camera);
  const int rendered_height = images.height(camera);
  const int width = keys.letterbox ? keys.image_width : rendered_width;
  const int height = keys.letterbox ? keys.image_height : rendered_height;
  const int left = (width - rendered_width) / 2;
  const int top = (height - rendered_height) / 2;
  const uint8_t* rgb = images.rgb(env, camera);
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * height * 3, 0);
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
  const std::vector<std::int64_t> shape = keys.image_layout == ImageLayout::kHwc
                                              ? std::vector<std::int64_t>{height, width, 3}
                                              : std::vector<std::int64_t>{3, height, width};
  return MakeUint8Array(shape, std::move(pixels));
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

ObservationKeys LoadObservationKeys(const std::string& preset_or_path, const std::string& config_dir) {
  if (std::find(std::begin(kPresets), std::end(kPresets), preset_or_path) != std::end(kPresets)) {
    const std::string path = config_dir + "/policy_keys/" + preset_or_path + ".yaml";
    return ReadKeys(configs::YamlValue::LoadFile(path), preset_or_path);
  }
  if (!std::filesystem::is_regular_file(preset_or_path)) {
    throw std::invalid_argument("observation keys '" + preset_or_path + "' are neither a preset (" + KeyPresetNames() +
                                ") nor a YAML file");
  }
  return ReadKeys(configs::YamlValue::LoadFile(preset_or_path), preset_or_path);
}

std::pair<int, int> RenderSize(const ObservationKeys& keys) {
  if (!keys.letterbox) return {keys.image_width, keys.image_height};
  // The cameras' sensors are 4:3 (640 x 480 in the reference).
  const int width = std::min(keys.image_width, keys.image_height * 4 / 3) / 2 * 2;
  const int height = width * 3 / 4 / 2 * 2;
  return {width, height};
}

Value BuildRequest(const batch::Observation& observation, const ObservationKeys& keys,
                   const std::vector<std::string>& cameras, int env) {
  if (observation.images == nullptr || observation.proprioception == nullptr) {
    throw std::logic_error("a served policy needs the images and proprioception of the episode driver");
  }
  std::vector<std::pair<KeyPath, Value>> entries;
  for (int camera = 0; camera < static_cast<int>(cameras.size()); ++camera) {
    entries.emplace_back(keys.KeyOf(cameras[static_cast<std::size_t>(camera)]),
                         PolicyImage(*observation.images, env, camera, keys));
  }
  const batch::ProprioceptionBatch& proprioception = *observation.proprioception;
  const float* state = proprioception.state(env);
  entries.emplace_back(keys.state, MakeFloat32Array({proprioception.state_size()},
                                                    std::vector<float>(state, state + proprioception.state_size())));
  const char* prompt = observation.prompts[static_cast<std::size_t>(env)];
  entries.emplace_back(keys.prompt, Value(prompt != nullptr ? prompt : ""));
  return Nest(std::move(entries), 0);
}

}  // namespace tavis::remote
