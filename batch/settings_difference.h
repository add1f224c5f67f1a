// What changed between the settings a run was started with and the ones it is resumed with, so
// a resume that would mix two different runs is refused naming what differs.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace tavis::batch {

// "seed 0 -> 9, fps 60 -> 20" for every key of `now` whose value differs in `was` (or is missing
// there: "unset"); empty when they agree.
std::string SettingsDifference(const nlohmann::json& was, const nlohmann::json& now);

}  // namespace tavis::batch
