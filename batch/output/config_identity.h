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
// Throws std::invalid_argument naming the file when it cannot be read.
nlohmann::json ConfigIdentityJson(const std::string& config_dir, const std::string& robot,
                                  const std::string& observation_keys = "");

}  // namespace tavis::batch::output
