#include "batch/report/seed_groups.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

// Key -> one value per label, in first-appearance order of the keys.
struct ValuesByKey {
  std::vector<Json> order;
  std::map<std::string, std::map<std::string, double>> values;  // key dump -> label -> value

  void Add(const Json& key, const std::string& label, double value) {
    const std::string text = key.dump();
    if (!values.count(text)) order.push_back(key);
    values[text][label] = value;
  }

  // Per key the checkpoints that evaluated it (e.g. a group of per-robot checkpoints: each
  // robot's), named in "labels".
  Json Rows(const std::vector<std::string>& labels) const {
    Json rows = Json::array();
    for (const Json& key : order) {
      const auto& by_label = values.at(key.dump());
      std::vector<double> across;
      std::vector<std::string> which;
      for (const std::string& label : labels) {
        const auto it = by_label.find(label);
        if (it == by_label.end()) continue;
        across.push_back(it->second);
        which.push_back(label);
      }
      Json row = key;
      row["labels"] = which;
      row.update(AcrossCheckpoints(across));
      rows.push_back(row);
    }
    return rows;
  }
};

}  // namespace

Json AcrossCheckpoints(const std::vector<double>& values) {
  const double n = static_cast<double>(values.size());
  const double mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
  double squared = 0.0;
  for (const double value : values) squared += (value - mean) * (value - mean);
  return {{"values", values},
          {"n", values.size()},
          {"mean", mean},
          {"std", values.size() > 1 ? std::sqrt(squared / (n - 1.0)) : 0.0},
          {"min", *std::min_element(values.begin(), values.end())},
          {"max", *std::max_element(values.begin(), values.end())}};
}

Json SeedGroupsJson(const Json& summary) {
  std::vector<std::string> groups;
  std::map<std::string, std::vector<std::string>> members;
  for (const Json& label : summary["labels"]) {
    const std::string group = label["seed_group"];
    if (group.empty()) continue;
    if (!members.count(group)) groups.push_back(group);
    members[group].push_back(label["label"]);
  }
  Json result = Json::array();
  for (const std::string& group : groups) {
    const std::vector<std::string>& labels = members[group];
    ValuesByKey rates, means;
    for (const Json& suite : summary["success"]) {
      const std::string label = suite["label"];
      if (std::find(labels.begin(), labels.end(), label) == labels.end()) continue;
      for (const Json& column : suite["columns"]) {
        const Json where = {{"suite", suite["suite"]},
                            {"robot", column["robot"]},
                            {"split", column["split"]},
                            {"camera", column["camera"]}};
        means.Add(where, label, column["task_average"]);
        for (const Json& task : column["tasks"]) {
          if (!task.contains("success_rate")) continue;
          Json key = {{"suite", suite["suite"]}, {"task", task["task"]}};
          for (const auto& [name, value] : where.items()) {
            if (name != "suite") key[name] = value;
          }
          rates.Add(key, label, task["success_rate"]);
        }
      }
    }
    result.push_back(
        {{"seed_group", group}, {"labels", labels}, {"rows", rates.Rows(labels)}, {"suite_means", means.Rows(labels)}});
  }
  return result;
}

}  // namespace tavis::batch::report
