// The identity of what shapes a run's episodes beyond its command-line settings: the robot
// file's content, a served policy's observation-key file, and the program version. Recorded in a
// cell's cell.json and a dataset's spool, so that a resume or a merge that would mix episodes of
// two robots (a velocity limit changed between runs) is refused naming the key that changed.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace tavis::batch::output {

// {"program_version": ..., "robot_config": <the robot YAML as JSON, scalars as their text>, and
// with `observation_keys` (a preset name or a YAML file; empty: none) "observation_keys_config"}.
// Throws std::invalid_argument or configs::ConfigError naming the file when it cannot be read.
nlohmann::json ConfigIdentityJson(const std::string& config_dir, const std::string& robot,
                                  const std::string& observation_keys = "");

// The same from files a caller has read already (a cell's plan reads each once): the robot file's
// text (`robot_path` names it in errors) and what the identity says of the key file
// (ObservationKeysIdentity; empty: no served policy, no entry).
nlohmann::json ConfigIdentityFromTexts(const std::string& robot_path, const std::string& robot_yaml,
                                       const std::string& keys_identity);

// The file a served policy's `observation_keys` are recorded by: the file it names, or a shipped
// preset's config_dir/policy_keys/NAME.yaml; "" when there is none (the built-in preset).
std::string ObservationKeysIdentityFile(const std::string& config_dir, const std::string& observation_keys);
// What the identity says of that file: "fnv1a:" and the hash of its bytes, or "built-in" for none.
std::string ObservationKeysIdentity(const std::string& file, const std::string& bytes);

}  // namespace tavis::batch::output
