#include "batch/sweep/galt_reference.h"

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "batch/dataset/reader/dataset_galt.h"

namespace tavis::batch::sweep {

nlohmann::ordered_json DatasetGaltReference(const nlohmann::ordered_json& figures) {
  if (!figures.contains("galt_reference_datasets")) return nullptr;
  const nlohmann::ordered_json& datasets = figures["galt_reference_datasets"];
  nlohmann::ordered_json reference = {
      {"source", nullptr}, {"datasets", datasets}, {"tasks", nlohmann::ordered_json::object()}};
  std::map<std::string, std::vector<double>> read;  // a folder named for several tasks is read once
  for (const auto& [task, dir_json] : datasets.items()) {
    const std::string dir = dir_json.get<std::string>();
    if (read.count(dir) == 0) {
      try {
        read[dir] = dataset::reader::DatasetGaltSeconds(dir);
      } catch (const std::exception& error) {
        throw std::runtime_error("figures.galt_reference_datasets." + task + ": " + error.what());
      }
    }
    reference["tasks"][task] = read[dir];
  }
  reference["source"] = read.size() == 1 ? read.begin()->first : std::string("datasets");
  return reference;
}

}  // namespace tavis::batch::sweep
