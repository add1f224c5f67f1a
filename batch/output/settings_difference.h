// What changed between the settings a run was started with and the ones it is resumed with, so
// a resume that would mix two different runs is refused naming what differs.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tavis::batch::output {

// One key whose value differs: its path ("robot_config.arm.velocity_limit") and the value on each
// side, absent where that side does not have the key.
struct SettingChange {
  std::string path;
  std::optional<nlohmann::json> was;
  std::optional<nlohmann::json> now;
};

// Every key whose value differs between `was` and `now`, in key order; a key only one side has
// differs as much as one whose value changed. Objects on both sides are compared key by key and
// named by their path, so a change inside a robot file names the key, not the whole file.
std::vector<SettingChange> SettingChanges(const nlohmann::json& was, const nlohmann::json& now);

// "seed 0 -> 9, fps 60 -> 20" for every key whose value differs between `was` and `now`, in key
// order; a key only one side has is "unset" on the other ("perturbations [...] -> unset": a resume
// that leaves a setting out differs as much as one that changes it); empty when they agree.
// Objects on both sides are compared key by key and named by their path
// ("robot_config.arm.velocity_limit \"5.0\" -> \"4.0\""). A setting recorded only when it is not
// at its default must be written the same way by both runs, so that absent means default on both.
std::string SettingsDifference(const nlohmann::json& was, const nlohmann::json& now);

}  // namespace tavis::batch::output
