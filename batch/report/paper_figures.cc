#include "batch/report/paper_figures.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "batch/cell/statistics.h"
#include "batch/report/seed_groups.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

const char* const kSplits[] = {"id", "ood-spatial", "ood-init-pose"};

// The value of one rate for a label, or for a seed group the mean and spread across its
// checkpoints.
struct Value {
  double mean = 0.0;
  double std = 0.0;
  int checkpoints = 1;
};

Json ValueJson(const std::optional<Value>& value) {
  if (!value) return nullptr;
  return {{"mean", value->mean}, {"std", value->std}, {"checkpoints", value->checkpoints}};
}

class Lookup {
 public:
  explicit Lookup(const Json& summary) : summary_(summary) {}

  bool IsGroup(const std::string& name) const { return Group(name) != nullptr; }

  // The labels a name stands for: itself, or a seed group's checkpoints.
  std::vector<std::string> Labels(const std::string& name) const {
    if (const Json* group = Group(name)) return (*group)["labels"].get<std::vector<std::string>>();
    return {name};
  }

  // A suite's task average (task empty) or one task's rate.
  std::optional<Value> Rate(const std::string& name, const std::string& suite, const std::string& task,
                            const std::string& robot, const std::string& split, const std::string& camera) const {
    if (const Json* group = Group(name)) {
      for (const Json& row : (*group)[task.empty() ? "suite_means" : "rows"]) {
        if (row["suite"] == suite && row["robot"] == robot && row["split"] == split && row["camera"] == camera &&
            (task.empty() || row["task"] == task)) {
          return Value{row["mean"], row["std"], row["n"]};
        }
      }
      return std::nullopt;
    }
    for (const Json& entry : summary_["success"]) {
      if (entry["label"] != name || entry["suite"] != suite) continue;
      for (const Json& column : entry["columns"]) {
        if (column["robot"] != robot || column["split"] != split || column["camera"] != camera) continue;
        if (task.empty()) return Value{column["task_average"].get<double>(), 0.0, 1};
        for (const Json& row : column["tasks"]) {
          if (row["task"] == task && row.contains("success_rate"))
            return Value{row["success_rate"].get<double>(), 0.0, 1};
        }
      }
    }
    return std::nullopt;
  }

  std::vector<std::string> Robots() const { return Distinct("robot"); }
  std::vector<std::string> Suites() const { return Distinct("suite"); }
  std::vector<std::string> Tasks(const std::string& suite) const {
    std::vector<std::string> tasks;
    for (const Json& cell : summary_["cells"]) {
      if (cell["suite"] == suite && std::find(tasks.begin(), tasks.end(), cell["task"]) == tasks.end())
        tasks.push_back(cell["task"]);
    }
    return tasks;
  }

  // GALT values (s) of a name's successful head episodes of one task and split, all robots.
  std::vector<double> Galt(const std::string& name, const std::string& task, const std::string& split) const {
    const std::vector<std::string> labels = Labels(name);
    std::vector<double> values;
    for (const Json& cell : summary_["cells"]) {
      if (std::find(labels.begin(), labels.end(), cell["label"]) == labels.end() || cell["task"] != task ||
          cell["split"] != split || cell["galt"].is_null()) {
        continue;
      }
      for (const Json& value : cell["galt"]["values_s"]) values.push_back(value);
    }
    return values;
  }

 private:
  const Json* Group(const std::string& name) const {
    for (const Json& group : summary_["seed_groups"]) {
      if (group["seed_group"] == name) return &group;
    }
    return nullptr;
  }
  std::vector<std::string> Distinct(const char* key) const {
    std::vector<std::string> names;
    for (const Json& cell : summary_["cells"]) {
      if (std::find(names.begin(), names.end(), cell[key]) == names.end()) names.push_back(cell[key]);
    }
    return names;
  }

  const Json& summary_;
};

std::string Choice(const Json& choices, const char* key, const std::string& fallback) {
  return choices.contains(key) ? choices[key].get<std::string>() : fallback;
}

Json HeadVsFixed(const Lookup& lookup, const std::string& name) {
  Json points = Json::array();
  for (const std::string& suite : lookup.Suites()) {
    for (const std::string& task : lookup.Tasks(suite)) {
      for (const std::string& robot : lookup.Robots()) {
        const auto head = lookup.Rate(name, suite, task, robot, "id", "head");
        const auto fixed = lookup.Rate(name, suite, task, robot, "id", "fixed");
        if (head && fixed) {
          points.push_back({{"suite", suite},
                            {"task", task},
                            {"robot", robot},
                            {"head", ValueJson(head)},
                            {"fixed", ValueJson(fixed)}});
        }
      }
    }
  }
  if (points.empty()) return nullptr;
  return {{"policy", name}, {"split", "id"}, {"points", points}};
}

Json SingleVsMulti(const Lookup& lookup, const Json& pair) {
  if (pair.is_null()) return nullptr;
  const std::string single = pair[0], multi = pair[1];
  Json bars = Json::array();
  for (const std::string& suite : lookup.Suites()) {
    for (const std::string& robot : lookup.Robots()) {
      const auto a = lookup.Rate(single, suite, "", robot, "id", "head");
      const auto b = lookup.Rate(multi, suite, "", robot, "id", "head");
      if (a && b)
        bars.push_back({{"suite", suite}, {"robot", robot}, {"single", ValueJson(a)}, {"multi", ValueJson(b)}});
    }
  }
  if (bars.empty()) return nullptr;
  return {{"single", single}, {"multi", multi}, {"split", "id"}, {"camera", "head"}, {"bars", bars}};
}

Json Splits(const Lookup& lookup, const std::string& name) {
  Json bars = Json::array();
  for (const std::string& suite : lookup.Suites()) {
    for (const std::string& robot : lookup.Robots()) {
      Json bar = {{"suite", suite}, {"robot", robot}};
      bool any = false;
      for (const char* split : kSplits) {
        const auto value = lookup.Rate(name, suite, "", robot, split, "head");
        bar[split] = ValueJson(value);
        any = any || value.has_value();
      }
      if (any) bars.push_back(bar);
    }
  }
  if (bars.empty()) return nullptr;
  return {{"policy", name}, {"camera", "head"}, {"bars", bars}};
}

Json Ablation(const Lookup& lookup, const Json& choices, const std::string& name) {
  const Json defaults = {{"no_av", {{"label", name}, {"task", "clutter-pick-cube"}, {"camera", "fixed"}}},
                         {"full_av", {{"label", name}, {"task", "clutter-pick-cube"}, {"camera", "head"}}},
                         {"wrist_only", {{"label", name}, {"task", "blocked-clutter-pick-cube"}, {"camera", "head"}}}};
  const Json& arms_choice = choices.contains("ablation") ? choices["ablation"] : defaults;
  Json arms = Json::array();
  bool any = false;
  for (const char* arm : {"no_av", "full_av", "wrist_only"}) {
    const Json& what = arms_choice[arm];
    const std::string task = what["task"];
    Json per_robot = Json::array();
    double sum = 0.0;
    for (const std::string& robot : lookup.Robots()) {
      for (const std::string& suite : lookup.Suites()) {
        const auto value = lookup.Rate(what["label"], suite, task, robot, "id", what["camera"]);
        if (!value) continue;
        per_robot.push_back({{"robot", robot}, {"rate", ValueJson(value)}});
        sum += value->mean;
      }
    }
    Json entry = what;
    entry["arm"] = arm;
    entry["split"] = "id";
    entry["per_robot"] = per_robot;
    entry["mean_over_robots"] = per_robot.empty() ? Json() : Json(sum / static_cast<double>(per_robot.size()));
    any = any || !per_robot.empty();
    arms.push_back(entry);
  }
  if (!any) return nullptr;
  return {{"arms", arms}};
}

Json HistogramJson(const std::vector<double>& all, double window, double high) {
  std::vector<double> kept;
  for (const double value : all) {
    if (value >= kGaltFigureLow && value <= window) kept.push_back(value);
  }
  Json json = {{"n", kept.size()},
               {"n_outside_window", all.size() - kept.size()},
               {"median", nullptr},
               {"counts", HistogramCounts(kept, kGaltFigureLow, high, kGaltFigureBins)}};
  if (!kept.empty()) json["median"] = cell::Median(kept);
  return json;
}

// What a task's reference values come from: the label, the task's dataset folder, or null.
Json ReferenceSource(const Json& choices, const Json& reference, const std::string& task) {
  if (choices.contains("galt_reference")) return choices["galt_reference"];
  if (reference.is_null() || !reference["tasks"].contains(task)) return nullptr;
  if (reference.contains("datasets") && reference["datasets"].contains(task)) return reference["datasets"][task];
  return reference["source"];
}

Json GaltFigure(const Lookup& lookup, const Json& choices, const std::string& name, const Json& reference) {
  const double window = choices.contains("galt_window_s") ? choices["galt_window_s"].get<double>() : kGaltFigureWindow;
  const double high = std::max(kGaltFigureHigh, window);
  const bool reference_label = choices.contains("galt_reference");
  Json tasks = Json::array();
  for (const std::string& task : lookup.Tasks("tavis-head")) {
    const std::vector<double> values = lookup.Galt(name, task, "id");
    if (values.empty()) continue;
    std::vector<double> reference_values;
    if (reference_label) {
      reference_values = lookup.Galt(choices["galt_reference"], task, "id");
    } else if (!reference.is_null() && reference["tasks"].contains(task)) {
      reference_values = reference["tasks"][task].get<std::vector<double>>();
    }
    Json row = {{"task", task},
                {"policy", HistogramJson(values, window, high)},
                {"reference", nullptr},
                {"reference_source", ReferenceSource(choices, reference, task)},
                {"relative_median_difference", nullptr}};
    if (!reference_values.empty()) {
      row["reference"] = HistogramJson(reference_values, window, high);
      const Json& m_policy = row["policy"]["median"];
      const Json& m_reference = row["reference"]["median"];
      if (!m_policy.is_null() && !m_reference.is_null() && m_reference.get<double>() != 0.0) {
        row["relative_median_difference"] =
            std::abs(m_policy.get<double>() - m_reference.get<double>()) / std::abs(m_reference.get<double>());
      }
    }
    tasks.push_back(row);
  }
  if (tasks.empty()) return nullptr;
  const Json reference_name = reference_label       ? Json(choices["galt_reference"])
                              : reference.is_null() ? Json()
                                                    : reference["source"];
  return {{"policy", name},     {"reference", reference_name},
          {"split", "id"},      {"camera", "head"},
          {"window_s", window}, {"bins", {{"low", kGaltFigureLow}, {"high", high}, {"count", kGaltFigureBins}}},
          {"tasks", tasks}};
}

// The mean over bars of one field's mean (null when none has it).
Json MeanOver(const Json& bars, const char* field) {
  double sum = 0.0;
  int n = 0;
  for (const Json& bar : bars) {
    if (!bar[field].is_null()) {
      sum += bar[field]["mean"].get<double>();
      ++n;
    }
  }
  return n > 0 ? Json(sum / n) : Json();
}

}  // namespace

std::vector<int> HistogramCounts(const std::vector<double>& values, double low, double high, int bins) {
  std::vector<int> counts(static_cast<std::size_t>(bins), 0);
  for (const double value : values) {
    if (!(value >= low && value <= high)) continue;  // also NaN
    const int bin = std::min(bins - 1, static_cast<int>((value - low) / (high - low) * bins));
    ++counts[static_cast<std::size_t>(std::max(0, bin))];
  }
  return counts;
}

Json PaperFiguresJson(const Json& summary, const Json& choices, const Json& galt_reference) {
  const Lookup lookup(summary);
  if (summary["labels"].empty()) return nullptr;
  const std::string main = Choice(choices, "policy", summary["labels"][0]["label"]);
  return {{"fig3a", HeadVsFixed(lookup, Choice(choices, "head_vs_fixed", main))},
          {"fig3b", SingleVsMulti(lookup, choices.contains("single_vs_multi") ? choices["single_vs_multi"] : Json())},
          {"fig3c", Splits(lookup, Choice(choices, "splits", main))},
          {"fig3d", Ablation(lookup, choices, main)},
          {"fig4", GaltFigure(lookup, choices, Choice(choices, "galt", main), galt_reference)}};
}

Json HeadlineJson(const Json& figures) {
  Json headline = {{"q1_ablation", nullptr}, {"q2_single_vs_multi", nullptr}, {"q3_splits", nullptr}};
  if (figures.is_null()) return headline;
  if (!figures["fig3d"].is_null()) {
    headline["q1_ablation"] = Json::object();
    for (const Json& arm : figures["fig3d"]["arms"])
      headline["q1_ablation"][arm["arm"].get<std::string>()] = arm["mean_over_robots"];
  }
  const auto per_suite = [](const Json& bars, const std::vector<const char*>& fields) {
    Json result = Json::array();
    std::vector<std::string> suites;
    for (const Json& bar : bars) {
      if (std::find(suites.begin(), suites.end(), bar["suite"]) == suites.end()) suites.push_back(bar["suite"]);
    }
    for (const std::string& suite : suites) {
      Json mine = Json::array();
      for (const Json& bar : bars) {
        if (bar["suite"] == suite) mine.push_back(bar);
      }
      Json row = {{"suite", suite}, {"robots", mine.size()}};
      for (const char* field : fields) row[field] = MeanOver(mine, field);
      result.push_back(row);
    }
    return result;
  };
  if (!figures["fig3b"].is_null())
    headline["q2_single_vs_multi"] = per_suite(figures["fig3b"]["bars"], {"single", "multi"});
  if (!figures["fig3c"].is_null())
    headline["q3_splits"] = per_suite(figures["fig3c"]["bars"], {"id", "ood-spatial", "ood-init-pose"});
  return headline;
}

}  // namespace tavis::batch::report
