#include "batch/output/config_identity.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "batch/output/program_version.h"
#include "configs/robot_config.h"

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

nlohmann::json YamlFileAsJson(const std::string& path) {
  try {
    return YamlAsJson(YAML::LoadFile(path));
  } catch (const YAML::Exception& error) {
    throw std::invalid_argument(path + ": " + error.what());
  }
}

// FNV-1a over the file's bytes, as 16 hex digits: enough to tell an edited file from the one a
// cell started with, whatever its encoding ("" for a file that cannot be read).
std::string FileHash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::uint64_t hash = 14695981039346656037ull;
  for (std::istreambuf_iterator<char> it(in), end; it != end; ++it) {
    hash = (hash ^ static_cast<unsigned char>(*it)) * 1099511628211ull;
  }
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace

nlohmann::json ConfigIdentityJson(const std::string& config_dir, const std::string& robot,
                                  const std::string& observation_keys) {
  nlohmann::json identity = {{"program_version", ProgramVersion()},
                             {"robot_config", YamlFileAsJson(configs::RobotConfigPath(config_dir, robot))}};
  if (!observation_keys.empty()) {
    // A key file or a shipped preset's file by the hash of its bytes; the built-in contract
    // preset (observation_contract.h) is part of the program, whose version is recorded above.
    const bool is_file = std::filesystem::is_regular_file(observation_keys);
    const std::string path = is_file ? observation_keys : config_dir + "/policy_keys/" + observation_keys + ".yaml";
    identity["observation_keys_config"] =
        std::filesystem::is_regular_file(path) ? "fnv1a:" + FileHash(path) : "built-in";
  }
  return identity;
}

}  // namespace tavis::batch::output
