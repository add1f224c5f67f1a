#include "batch/settings_difference.h"

namespace tavis::batch {

std::string SettingsDifference(const nlohmann::json& was, const nlohmann::json& now) {
  std::string differences;
  for (const auto& [key, value] : now.items()) {
    if (was.contains(key) && was.at(key) == value) continue;
    differences += (differences.empty() ? "" : ", ") + key + " " + (was.contains(key) ? was.at(key).dump() : "unset") +
                   " -> " + value.dump();
  }
  return differences;
}

}  // namespace tavis::batch
