#include "batch/config_identity.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "batch/program_version.h"
#include "configs/robot_config.h"

namespace tavis::batch {
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

nlohmann::json YamlFileAsJson(const std::string& path) {
  try {
    return YamlAsJson(YAML::LoadFile(path));
  } catch (const YAML::Exception& error) {
    throw std::invalid_argument(path + ": " + error.what());
  }
}

}  // namespace

nlohmann::json ConfigIdentityJson(const std::string& config_dir, const std::string& robot, const std::string& observation_keys) {
  nlohmann::json identity = {{"program_version", ProgramVersion()},
                             {"robot_config", YamlFileAsJson(configs::RobotConfigPath(config_dir, robot))}};
  if (!observation_keys.empty()) {
    const bool is_file = std::filesystem::is_regular_file(observation_keys);
    // The key file's text: its escapes are read by the strict reader (observation_keys.cc), not here.
    std::ifstream in(is_file ? observation_keys : config_dir + "/policy_keys/" + observation_keys + ".yaml", std::ios::binary);
    identity["observation_keys_config"] = std::string(std::istreambuf_iterator<char>(in), {});
  }
  return identity;
}

}  // namespace tavis::batch
