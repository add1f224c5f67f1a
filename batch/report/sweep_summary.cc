#include "batch/report/sweep_summary.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>
#include <utility>

#include "batch/cell/galt_summary.h"
#include "batch/cell/statistics.h"
#include "batch/report/camera_set_pairs.h"
#include "batch/report/failure_event_section.h"
#include "batch/report/galt_validation.h"
#include "batch/report/gaze_figures.h"
#include "batch/report/gaze_section.h"
#include "batch/report/paired_statistics.h"
#include "batch/report/paper_figures.h"
#include "batch/report/perturbation_pairs.h"
#include "batch/report/results_table.h"
#include "batch/report/seed_groups.h"
#include "batch/report/sequential_section.h"
#include "batch/report/stage_funnel_section.h"
#include "scenarios/registry.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

// count, mean, median and population standard deviation of `values` (nulls when empty).
Json SpreadJson(std::vector<double> values) {
  Json spread = {{"n", values.size()}, {"mean", nullptr}, {"median", nullptr}, {"std", nullptr}};
  if (values.empty()) return spread;
  const cell::Spread of = cell::SpreadOf(std::move(values));
  spread["mean"] = of.mean;
  spread["median"] = of.median;
  spread["std"] = of.std;
  return spread;
}

Json RateJson(int64_t successes, int64_t episodes) {
  const cell::ProportionInterval ci = cell::WilsonInterval(successes, episodes);
  return {{"n_episodes", episodes},
          {"n_successful", successes},
          {"success_rate", episodes > 0 ? static_cast<double>(successes) / static_cast<double>(episodes) : 0.0},
          {"ci_low", ci.low},
          {"ci_high", ci.high}};
}

std::string SuiteOf(const std::string& task) { return scenarios::ToString(scenarios::FindScenario(task).suite); }

// Cells pooled over seeds: (task, robot, split, camera) in first-appearance order.
using GroupKey = std::tuple<std::string, std::string, std::string, std::string>;

GroupKey KeyOf(const CellEpisodes& cell) {
  return {cell.config.task, cell.config.robot, scenarios::ToString(cell.config.split), ToString(cell.config.camera)};
}

struct Group {
  int64_t successes = 0;
  int64_t episodes = 0;
  std::vector<double> success_lengths_s;
  std::vector<kinematics::GaltResult> galt;  // successful episodes' (head cells)
};

double LengthSeconds(const cell::EpisodeRecord& record) {
  return static_cast<double>(record.length_steps) / kPolicyRateHz;
}

Json CellJson(const CellEpisodes& cell) {
  int64_t successes = 0;
  std::vector<double> lengths;
  std::vector<kinematics::GaltResult> galt;
  Json galt_values = Json::array();
  for (const cell::EpisodeRecord& record : cell.episodes) {
    if (!record.success) continue;
    ++successes;
    lengths.push_back(LengthSeconds(record));
    if (record.galt) {
      galt.push_back(*record.galt);
      if (record.galt->galt_s) galt_values.push_back(*record.galt->galt_s);
    }
  }
  Json json = {{"id", cell.id},
               {"suite", SuiteOf(cell.config.task)},
               {"task", cell.config.task},
               {"robot", cell.config.robot},
               {"split", scenarios::ToString(cell.config.split)},
               {"camera", ToString(cell.config.camera)},
               {"label", cell.label.empty() ? cell.config.policy : cell.label},
               {"seed_group", cell.seed_group},
               {"policy", cell.config.policy},
               {"seed", cell.config.seed}};
  json["server_metadata"] = cell.server_metadata;
  json.update(RateJson(successes, static_cast<int64_t>(cell.episodes.size())));
  Json length_values = Json::array();
  for (const double length : lengths) length_values.push_back(length);
  json["successful_length_s"] = SpreadJson(lengths);
  json["successful_length_s"]["values"] = length_values;
  if (!UsesFixedView(cell.config.camera)) {
    json["galt"] = cell::GaltSummaryJson(cell::SummarizeGalt(galt));
    json["galt"]["values_s"] = galt_values;
  } else {
    json["galt"] = nullptr;
  }
  return json;
}

// The paper-layout success table of one suite, from results_table's pooling.
Json SuccessJson(const std::string& suite, const std::vector<CellEpisodes>& cells) {
  std::vector<CellCounts> counts;
  for (const CellEpisodes& cell : cells) {
    if (SuiteOf(cell.config.task) != suite) continue;
    CellCounts entry;
    std::tie(entry.task, entry.robot, entry.split, entry.camera) = KeyOf(cell);
    entry.policy = cell.config.policy;
    entry.n_episodes = static_cast<int64_t>(cell.episodes.size());
    entry.n_successful = std::count_if(cell.episodes.begin(), cell.episodes.end(),
                                       [](const cell::EpisodeRecord& r) { return r.success; });
    counts.push_back(entry);
  }
  const ResultsTable table = BuildResultsTable(counts, suite);
  Json columns = Json::array();
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    const TableColumn& column = table.columns[c];
    Json rows = Json::array();
    for (std::size_t t = 0; t < table.tasks.size(); ++t) {
      const std::optional<RateCell>& cell = table.cells[t][c];
      Json row = {{"task", table.tasks[t]}};
      if (cell) row.update(RateJson(cell->n_successful, cell->n_episodes));
      rows.push_back(row);
    }
    columns.push_back({{"robot", column.robot},
                       {"split", column.split},
                       {"camera", column.camera},
                       {"tasks", rows},
                       {"task_average", *table.task_average[c]},
                       {"pooled", RateJson(table.pooled[c]->n_successful, table.pooled[c]->n_episodes)}});
  }
  // id - ood per robot and camera: per task, then for the task average and the pooled rate.
  Json differences = Json::array();
  for (const Json& id : columns) {
    if (id["split"] != "id") continue;
    for (const Json& ood : columns) {
      if (ood["split"] == "id" || ood["robot"] != id["robot"] || ood["camera"] != id["camera"]) continue;
      Json tasks = Json::array();
      for (std::size_t t = 0; t < id["tasks"].size(); ++t) {
        const Json& a = id["tasks"][t];
        const Json& b = ood["tasks"][t];
        tasks.push_back(a.contains("success_rate") && b.contains("success_rate")
                            ? Json(a["success_rate"].get<double>() - b["success_rate"].get<double>())
                            : Json());
      }
      differences.push_back(
          {{"robot", id["robot"]},
           {"camera", id["camera"]},
           {"ood_split", ood["split"]},
           {"tasks", tasks},
           {"task_average", id["task_average"].get<double>() - ood["task_average"].get<double>()},
           {"pooled", id["pooled"]["success_rate"].get<double>() - ood["pooled"]["success_rate"].get<double>()}});
    }
  }
  return {{"suite", suite},
          {"title", scenarios::Title(scenarios::ParseSuite(suite))},
          {"columns", columns},
          {"id_minus_ood", differences}};
}

// One label's cells grouped by (task, robot, split, camera), in the order they first appear, and
// their matched episodes for the head vs fixed pairing.
struct LabelGroups {
  std::vector<GroupKey> order;
  std::map<GroupKey, Group> groups;
  // (task, robot, split, seed) -> camera -> each episode's success.
  std::map<std::tuple<std::string, std::string, std::string, uint64_t>, std::map<std::string, std::vector<bool>>> pairs;
  std::vector<std::string> suites;
};

LabelGroups GroupCells(const std::vector<CellEpisodes>& cells) {
  LabelGroups grouped;
  std::vector<GroupKey>& order = grouped.order;
  std::map<GroupKey, Group>& groups = grouped.groups;
  auto& pairs = grouped.pairs;
  std::vector<std::string>& suites = grouped.suites;
  for (const CellEpisodes& cell : cells) {
    const GroupKey key = KeyOf(cell);
    if (!groups.count(key)) order.push_back(key);
    Group& group = groups[key];
    std::vector<bool>& outcomes =
        pairs[{cell.config.task, cell.config.robot, std::get<2>(key), cell.config.seed}][ToString(cell.config.camera)];
    for (const cell::EpisodeRecord& record : cell.episodes) {
      ++group.episodes;
      outcomes.push_back(record.success);
      if (!record.success) continue;
      ++group.successes;
      group.success_lengths_s.push_back(LengthSeconds(record));
      if (record.galt) group.galt.push_back(*record.galt);
    }
    const std::string suite = SuiteOf(cell.config.task);
    if (std::find(suites.begin(), suites.end(), suite) == suites.end()) suites.push_back(suite);
  }
  return grouped;
}

Json SuccessSection(const std::vector<CellEpisodes>& cells, const std::vector<std::string>& suites) {
  Json success = Json::array();
  for (const scenarios::Suite suite : scenarios::kAllSuites) {
    if (std::find(suites.begin(), suites.end(), scenarios::ToString(suite)) != suites.end()) {
      success.push_back(SuccessJson(scenarios::ToString(suite), cells));
    }
  }
  return success;
}

Json SuccessfulLengthSection(const LabelGroups& grouped) {
  Json lengths = Json::array();
  for (const GroupKey& key : grouped.order) {
    const auto& [task, robot, split, camera] = key;
    lengths.push_back({{"task", task},
                       {"robot", robot},
                       {"split", split},
                       {"camera", camera},
                       {"successful_length_s", SpreadJson(grouped.groups.at(key).success_lengths_s)}});
  }
  return lengths;
}

Json IdMinusOodSection(const LabelGroups& grouped) {
  const std::vector<GroupKey>& order = grouped.order;
  const std::map<GroupKey, Group>& groups = grouped.groups;
  Json id_minus_ood = Json::array();
  for (const GroupKey& key : order) {
    const auto& [task, robot, split, camera] = key;
    if (split != "id") continue;
    const Group& id = groups.at(key);
    for (const scenarios::Split ood : {scenarios::Split::kOodSpatial, scenarios::Split::kOodInitPose}) {
      const auto other = groups.find({task, robot, scenarios::ToString(ood), camera});
      if (other == groups.end() || id.episodes == 0 || other->second.episodes == 0) continue;
      const double id_rate = static_cast<double>(id.successes) / static_cast<double>(id.episodes);
      const double ood_rate =
          static_cast<double>(other->second.successes) / static_cast<double>(other->second.episodes);
      id_minus_ood.push_back({{"task", task},
                              {"robot", robot},
                              {"camera", camera},
                              {"ood_split", scenarios::ToString(ood)},
                              {"id_rate", id_rate},
                              {"ood_rate", ood_rate},
                              {"difference", id_rate - ood_rate}});
    }
  }
  return id_minus_ood;
}

Json PairedSection(const LabelGroups& grouped) {
  const std::vector<GroupKey>& order = grouped.order;
  const auto& pairs = grouped.pairs;
  // Head vs fixed over the pairs of every seed; a pair needs both cells with the same episodes.
  std::map<std::tuple<std::string, std::string, std::string>, PairedCounts> paired_counts;
  std::vector<std::tuple<std::string, std::string, std::string>> paired_order;
  for (const GroupKey& key : order) {
    const auto& [task, robot, split, camera] = key;
    if (camera != "head") continue;
    for (const auto& [pair_key, protocols] : pairs) {
      if (std::get<0>(pair_key) != task || std::get<1>(pair_key) != robot || std::get<2>(pair_key) != split) continue;
      const auto head = protocols.find("head");
      const auto fixed = protocols.find("fixed");
      if (head == protocols.end() || fixed == protocols.end() || head->second.size() != fixed->second.size()) continue;
      const auto paired_key = std::make_tuple(task, robot, split);
      if (!paired_counts.count(paired_key)) paired_order.push_back(paired_key);
      PairedCounts& counts = paired_counts[paired_key];
      for (std::size_t i = 0; i < head->second.size(); ++i) {
        const bool h = head->second[i], f = fixed->second[i];
        ++(h && f ? counts.both : h ? counts.first_only : f ? counts.second_only : counts.neither);
      }
    }
  }
  Json paired = Json::array();
  for (const auto& paired_key : paired_order) {
    const PairedCounts& counts = paired_counts[paired_key];
    const double n = static_cast<double>(counts.pairs());
    const double head_rate = static_cast<double>(counts.both + counts.first_only) / n;
    const double fixed_rate = static_cast<double>(counts.both + counts.second_only) / n;
    paired.push_back({{"task", std::get<0>(paired_key)},
                      {"robot", std::get<1>(paired_key)},
                      {"split", std::get<2>(paired_key)},
                      {"pairs", counts.pairs()},
                      {"both", counts.both},
                      {"head_only", counts.first_only},
                      {"fixed_only", counts.second_only},
                      {"neither", counts.neither},
                      {"head_rate", head_rate},
                      {"fixed_rate", fixed_rate},
                      {"difference", head_rate - fixed_rate},
                      {"mcnemar_p", McNemarExactP(counts.first_only, counts.second_only)}});
  }
  return paired;
}

Json GaltSection(const LabelGroups& grouped) {
  Json galt = Json::array();
  for (const GroupKey& key : grouped.order) {
    const auto& [task, robot, split, camera] = key;
    if (camera != "head") continue;
    const cell::GaltSummary galt_summary = cell::SummarizeGalt(grouped.groups.at(key).galt);
    Json row = {
        {"robot", robot},
        {"task", task},
        {"split", split},
        {"detection_rate",
         galt_summary.n_episodes > 0 ? static_cast<double>(galt_summary.n_valid) / galt_summary.n_episodes : 0.0}};
    row.update(Json(cell::GaltSummaryJson(galt_summary)));
    galt.push_back(row);
  }
  std::stable_sort(galt.begin(), galt.end(), [](const Json& a, const Json& b) { return a["robot"] < b["robot"]; });
  return galt;
}

// The sections of one label's cells: success, successful_length, id_minus_ood, paired, galt, stages,
// paired_camera_sets, failure_events, gaze.
Json LabelSections(const std::vector<CellEpisodes>& cells) {
  const LabelGroups grouped = GroupCells(cells);
  Json summary = Json::object();
  summary["success"] = SuccessSection(cells, grouped.suites);
  summary["successful_length"] = SuccessfulLengthSection(grouped);
  summary["id_minus_ood"] = IdMinusOodSection(grouped);
  summary["paired"] = PairedSection(grouped);
  summary["galt"] = GaltSection(grouped);
  summary["stages"] = StageFunnelRows(cells);
  summary["paired_camera_sets"] = CameraSetPairRows(cells);
  summary["failure_events"] = FailureEventRows(cells);
  summary["gaze"] = GazeRows(cells);
  return summary;
}

std::string LabelOf(const CellEpisodes& cell) { return cell.label.empty() ? cell.config.policy : cell.label; }

// `row` with "label" first.
Json Labelled(const std::string& label, const Json& row) {
  Json labelled = {{"label", label}};
  labelled.update(row);
  return labelled;
}

}  // namespace

Json SweepSummaryJson(const Json& spec, const std::vector<CellEpisodes>& cells, const Json& galt_reference) {
  Json summary = {{"spec", spec}};
  std::vector<std::string> labels;
  Json label_list = Json::array();
  Json cell_list = Json::array();
  for (const CellEpisodes& cell : cells) {
    cell_list.push_back(CellJson(cell));
    const std::string label = LabelOf(cell);
    if (std::find(labels.begin(), labels.end(), label) != labels.end()) continue;
    labels.push_back(label);
    label_list.push_back({{"label", label}, {"policy", cell.config.policy}, {"seed_group", cell.seed_group}});
  }
  summary["labels"] = label_list;
  summary["cells"] = cell_list;
  const char* sections[] = {"success", "successful_length",  "id_minus_ood",   "paired", "galt",
                            "stages",  "paired_camera_sets", "failure_events", "gaze"};
  for (const char* section : sections) summary[section] = Json::array();
  for (const std::string& label : labels) {
    std::vector<CellEpisodes> mine;
    for (const CellEpisodes& cell : cells) {
      if (LabelOf(cell) == label) mine.push_back(cell);
    }
    const Json label_sections = LabelSections(mine);
    for (const char* section : sections) {
      for (const Json& row : label_sections[section]) summary[section].push_back(Labelled(label, row));
    }
  }
  // Across labels (a perturbed cell's label is its base label and its levels); only a sweep with
  // perturbed cells has the section, so other summaries are as before.
  const Json perturbation_pairs = PerturbationPairRows(cells);
  if (!perturbation_pairs.empty()) summary["paired_perturbations"] = perturbation_pairs;
  // Only a sweep that runs the sequential test has its section.
  const SequentialSettings sequential = SequentialSettingsFromJson(spec.value("sequential", Json()));
  if (sequential.enabled) summary["sequential"] = SequentialSection(cells, sequential);
  summary["seed_groups"] = SeedGroupsJson(summary);
  const Json choices = spec.contains("figures") ? spec["figures"] : Json::object();
  summary["figures"] = PaperFiguresJson(summary, choices, galt_reference);
  summary["headline"] = HeadlineJson(summary["figures"]);
  summary["gaze_figures"] = GazeFiguresJson(summary, choices);
  return summary;
}

}  // namespace tavis::batch::report
