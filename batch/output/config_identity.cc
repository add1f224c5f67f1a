#include "batch/output/config_identity.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "batch/output/program_version.h"
#include "configs/robot_config.h"
#include "configs/yaml_reader.h"

namespace tavis::batch::output {
namespace {

// Scalars keep their text ("5.0"): the identity is what the file says, not how it is parsed.
nlohmann::json YamlAsJson(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Map: {
      nlohmann::json object = nlohmann::json::object();
      for (const auto& entry : node) object[entry.first.as<std::string>()] = YamlAsJson(entry.second);
      return object;
    }
    case YAML::NodeType::Sequence: {
      nlohmann::json array = nlohmann::json::array();
      for (const auto& item : node) array.push_back(YamlAsJson(item));
      return array;
    }
    case YAML::NodeType::Scalar: return node.Scalar();
    default: return nullptr;
  }
}

nlohmann::json YamlTextAsJson(const std::string& text, const std::string& path) {
  try {
    return YamlAsJson(YAML::Load(text));
  } catch (const YAML::Exception& error) {
    throw std::invalid_argument(path + ": " + error.what());
  }
}

// FNV-1a over the file's bytes, as 16 hex digits: enough to tell an edited file from the one a
// cell started with, whatever its encoding.
std::string BytesHash(const std::string& bytes) {
  std::uint64_t hash = 14695981039346656037ull;
  for (const char byte : bytes) hash = (hash ^ static_cast<unsigned char>(byte)) * 1099511628211ull;
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace

nlohmann::json ConfigIdentityFromTexts(const std::string& robot_path, const std::string& robot_yaml,
                                       const std::string& keys_identity) {
  nlohmann::json identity = {{"program_version", ProgramVersion()},
                             {"robot_config", YamlTextAsJson(robot_yaml, robot_path)}};
  if (!keys_identity.empty()) identity["observation_keys_config"] = keys_identity;
  return identity;
}

std::string ObservationKeysIdentityFile(const std::string& config_dir, const std::string& observation_keys) {
  // A key file or a shipped preset's file by the hash of its bytes; the built-in contract preset
  // (observation_contract.h) is part of the program, whose version is recorded beside it.
  const bool is_file = std::filesystem::is_regular_file(observation_keys);
  const std::string path = is_file ? observation_keys : config_dir + "/policy_keys/" + observation_keys + ".yaml";
  return std::filesystem::is_regular_file(path) ? path : "";
}

std::string ObservationKeysIdentity(const std::string& file, const std::string& bytes) {
  return file.empty() ? "built-in" : "fnv1a:" + BytesHash(bytes);
}

nlohmann::json ConfigIdentityJson(const std::string& config_dir, const std::string& robot,
                                  const std::string& observation_keys) {
  const std::string robot_path = configs::RobotConfigPath(config_dir, robot);
  std::string keys_identity;
  if (!observation_keys.empty()) {
    const std::string file = ObservationKeysIdentityFile(config_dir, observation_keys);
    keys_identity = ObservationKeysIdentity(file, file.empty() ? "" : configs::YamlValue::ReadFileText(file));
  }
  return ConfigIdentityFromTexts(robot_path, configs::YamlValue::ReadFileText(robot_path), keys_identity);
}

}  // namespace tavis::batch::output
