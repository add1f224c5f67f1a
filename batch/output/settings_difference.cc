#include "batch/output/settings_difference.h"

namespace tavis::batch::output {
namespace {

void AddDifferences(const nlohmann::json& was, const nlohmann::json& now, const std::string& prefix,
                    std::string* differences) {
  for (const auto& [key, value] : now.items()) {
    if (was.contains(key) && was.at(key) == value) continue;
    // Nested settings (a robot file's content) name the key that changed, not the whole file.
    if (was.contains(key) && was.at(key).is_object() && value.is_object()) {
      AddDifferences(was.at(key), value, prefix + key + ".", differences);
      continue;
    }
    *differences += (differences->empty() ? "" : ", ") + prefix + key + " " +
                    (was.contains(key) ? was.at(key).dump() : "unset") + " -> " + value.dump();
  }
}

}  // namespace

std::string SettingsDifference(const nlohmann::json& was, const nlohmann::json& now) {
  std::string differences;
  AddDifferences(was, now, "", &differences);
  return differences;
}

}  // namespace tavis::batch::output
