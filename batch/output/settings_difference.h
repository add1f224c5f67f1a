// What changed between the settings a run was started with and the ones it is resumed with, so
// a resume that would mix two different runs is refused naming what differs.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace tavis::batch::output {

// "seed 0 -> 9, fps 60 -> 20" for every key of `now` whose value differs in `was` (or is missing
// there: "unset"); empty when they agree. Objects on both sides are compared key by key and named
// by their path ("robot_config.arm.velocity_limit \"5.0\" -> \"4.0\"").
std::string SettingsDifference(const nlohmann::json& was, const nlohmann::json& now);

}  // namespace tavis::batch::output
