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

void AddChanges(const nlohmann::json& was, const nlohmann::json& now, const std::string& prefix,
                std::vector<SettingChange>* changes) {
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
      AddChanges(was.at(key), now.at(key), prefix + key + ".", changes);
      continue;
    }
    SettingChange change{prefix + key, std::nullopt, std::nullopt};
    if (in_was) change.was = was.at(key);
    if (in_now) change.now = now.at(key);
    changes->push_back(std::move(change));
  }
}

}  // namespace

std::vector<SettingChange> SettingChanges(const nlohmann::json& was, const nlohmann::json& now) {
  std::vector<SettingChange> changes;
  AddChanges(was, now, "", &changes);
  return changes;
}

std::string SettingsDifference(const nlohmann::json& was, const nlohmann::json& now) {
  std::string differences;
  for (const SettingChange& change : SettingChanges(was, now)) {
    differences += (differences.empty() ? "" : ", ") + change.path + " " + (change.was ? change.was->dump() : "unset") +
                   " -> " + (change.now ? change.now->dump() : "unset");
  }
  return differences;
}

}  // namespace tavis::batch::output
