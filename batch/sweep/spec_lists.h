// The lists a sweep spec names cells by (tasks by suite or name, robots, splits, cameras), read
// strictly: both the spec's top level and each labelled policy's `cells:` filter read them here.
#pragma once

#include <string>
#include <vector>

#include "batch/camera_protocol.h"
#include "configs/yaml_reader.h"
#include "scenarios/registry.h"

namespace tavis::batch::sweep {

// Refuses any key of `mapping` not in `known`, before a key is read: a typo ("robot:") is named
// as an unknown key with the nearest known one and the list (configs::YamlValue), not reported
// as the key it meant being missing.
void RejectUnknownKeys(const configs::YamlValue& mapping, const std::vector<std::string>& known);

// An integer in [low, high]; the error names the range and the value.
int ReadCount(const configs::YamlValue& value, int low, int high);
// An integer in the range the cell setting `key` allows (cell::CellSettings(): episodes, envs).
int ReadSettingCount(const configs::YamlValue& value, const std::string& key);

// `suites` (all their tasks, suite order) then `tasks`, no repeats; either may be absent.
// Writes the suites as given to *suite_names when it is not null.
std::vector<std::string> ReadTasks(const std::optional<configs::YamlValue>& suites,
                                   const std::optional<configs::YamlValue>& tasks,
                                   std::vector<std::string>* suite_names = nullptr);
std::vector<std::string> ReadRobots(const configs::YamlValue& list, const std::vector<std::string>& known_robots);
std::vector<scenarios::Split> ReadSplits(const configs::YamlValue& list);
std::vector<CameraProtocol> ReadCameras(const configs::YamlValue& list);

}  // namespace tavis::batch::sweep
