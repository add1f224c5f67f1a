#include "batch/sweep/spec_lists.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "batch/cell/cell_settings.h"

namespace tavis::batch::sweep {
namespace {

using configs::YamlValue;

std::string Join(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

// A non-empty list of strings without repeats; each passed to `check`, which throws
// std::invalid_argument for a bad one (its message becomes the error's).
template <typename Check>
std::vector<std::string> ReadNames(const YamlValue& list, Check check) {
  const std::vector<YamlValue> elements = list.Elements();
  if (elements.empty()) list.Fail("must name at least one, got []");
  std::vector<std::string> names;
  for (const YamlValue& element : elements) {
    const std::string name = element.AsString();
    try {
      check(name);
    } catch (const std::invalid_argument& error) {
      element.Fail(error.what());
    }
    if (std::find(names.begin(), names.end(), name) != names.end()) element.Fail("'" + name + "' is listed twice");
    names.push_back(name);
  }
  return names;
}

}  // namespace

void RejectUnknownKeys(const YamlValue& mapping, const std::vector<std::string>& known) {
  for (const std::string& key : known) mapping.Optional(key);  // each known key asked for (given or not),
  mapping.ExpectNoOtherKeys();                                 // so any other is named, with its nearest
}

int ReadCount(const YamlValue& value, int low, int high) {
  int count = 0;
  const std::string expected =
      "must be an integer from " + std::to_string(low) + " to " + std::to_string(high) + ", got ";
  try {
    count = value.AsInt();
  } catch (const configs::ConfigError&) {
    value.Fail(expected + value.Text());
  }
  if (count < low || count > high) value.Fail(expected + value.Text());
  return count;
}

int ReadSettingCount(const YamlValue& value, const std::string& key) {
  const output::SettingRange& range = *cell::CellSettingNamed(key).range;
  return ReadCount(value, static_cast<int>(range.low), static_cast<int>(range.high));
}

std::vector<std::string> ReadTasks(const std::optional<YamlValue>& suites, const std::optional<YamlValue>& tasks,
                                   std::vector<std::string>* suite_names) {
  std::vector<std::string> result;
  if (suites) {
    const std::vector<std::string> names =
        ReadNames(*suites, [](const std::string& name) { scenarios::ParseSuite(name); });
    if (suite_names) *suite_names = names;
    for (const std::string& suite : names) {
      for (const scenarios::ScenarioDef* scenario : scenarios::SuiteScenarios(scenarios::ParseSuite(suite))) {
        result.push_back(scenario->name);
      }
    }
  }
  if (tasks) {
    for (const std::string& task : ReadNames(*tasks, [](const std::string& name) { scenarios::FindScenario(name); })) {
      if (std::find(result.begin(), result.end(), task) == result.end()) result.push_back(task);
    }
  }
  return result;
}

std::vector<std::string> ReadRobots(const YamlValue& list, const std::vector<std::string>& known_robots) {
  return ReadNames(list, [&known_robots](const std::string& name) {
    if (std::find(known_robots.begin(), known_robots.end(), name) == known_robots.end()) {
      throw std::invalid_argument("unknown robot '" + name + "' (known: " + Join(known_robots) + ")");
    }
  });
}

std::vector<scenarios::Split> ReadSplits(const YamlValue& list) {
  std::vector<scenarios::Split> splits;
  for (const std::string& split : ReadNames(list, [](const std::string& name) { scenarios::ParseSplit(name); })) {
    splits.push_back(scenarios::ParseSplit(split));
  }
  return splits;
}

std::vector<CameraProtocol> ReadCameras(const YamlValue& list) {
  std::vector<CameraProtocol> cameras;
  for (const std::string& camera : ReadNames(list, [](const std::string& name) { ParseCameraProtocol(name); })) {
    cameras.push_back(ParseCameraProtocol(camera));
  }
  return cameras;
}

}  // namespace tavis::batch::sweep
