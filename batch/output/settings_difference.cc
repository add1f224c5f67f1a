#include "batch/output/settings_difference.h"

#include <set>

namespace tavis::batch::output {
namespace {

// An object's keys; none for anything else (a damaged record), so its keys all read as unset.
std::set<std::string> Keys(const nlohmann::json& settings) {
  std::set<std::string> keys;
  if (settings.is_object()) {
    for (const auto& [key, value] : settings.items()) keys.insert(key);
  }
  return keys;
}

void AddDifferences(const nlohmann::json& was, const nlohmann::json& now, const std::string& prefix,
                    std::string* differences) {
  // Both sides' keys: a setting the new run leaves out (a resume without --perturb) differs as
  // much as one it changes, or its records would mix two runs.
  std::set<std::string> keys = Keys(was);
  keys.merge(Keys(now));
  for (const std::string& key : keys) {
    const bool in_was = was.is_object() && was.contains(key);
    const bool in_now = now.is_object() && now.contains(key);
    if (in_was && in_now && was.at(key) == now.at(key)) continue;
    // Nested settings (a robot file's content) name the key that changed, not the whole file.
    if (in_was && in_now && was.at(key).is_object() && now.at(key).is_object()) {
      AddDifferences(was.at(key), now.at(key), prefix + key + ".", differences);
      continue;
    }
    *differences += (differences->empty() ? "" : ", ") + prefix + key + " " + (in_was ? was.at(key).dump() : "unset") +
                    " -> " + (in_now ? now.at(key).dump() : "unset");
  }
}

}  // namespace

std::string SettingsDifference(const nlohmann::json& was, const nlohmann::json& now) {
  std::string differences;
  AddDifferences(was, now, "", &differences);
  return differences;
}

}  // namespace tavis::batch::output
