#include "batch/report/stage_funnel_table.h"

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "batch/report/stage_funnel_section.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

std::optional<int64_t> Count(const nlohmann::json& step, const char* key) {
  if (!step.contains(key) || step.at(key).is_null()) return std::nullopt;
  return step.at(key).get<int64_t>();
}

// Cells of one column and task pooled: counts add up; a count one of them lacks is unknown; a
// stage applies unless a cell says it does not.
std::vector<FunnelCount> PoolFunnels(const std::vector<CellFunnel>& funnels) {
  // Cells of one task share its stages; one written before stages existed has none (and counts as
  // reaching none).
  std::vector<FunnelCount> pooled;
  for (const CellFunnel& funnel : funnels) {
    if (pooled.empty()) pooled = funnel.stages;
  }
  for (FunnelCount& step : pooled) {
    step.reached = step.reached_alone = 0;
    for (const CellFunnel& funnel : funnels) {
      const auto other = std::find_if(funnel.stages.begin(), funnel.stages.end(),
                                      [&](const FunnelCount& count) { return count.stage == step.stage; });
      if (other == funnel.stages.end()) continue;
      step.applies = step.applies && other->applies;
      for (auto [mine, theirs] :
           {std::pair{&step.reached, &other->reached}, std::pair{&step.reached_alone, &other->reached_alone}}) {
        *mine = *mine && *theirs ? std::optional<int64_t>(**mine + **theirs) : std::nullopt;
      }
    }
  }
  return pooled;
}

std::string Labels(const std::vector<CellCounts>& cells) {
  std::vector<std::string> labels;
  for (const CellCounts& cell : cells) {
    if (std::find(labels.begin(), labels.end(), cell.label) == labels.end()) labels.push_back(cell.label);
  }
  std::string joined;
  for (const std::string& label : labels) joined += (joined.empty() ? "" : "+") + label;
  return joined;
}

}  // namespace

CellFunnel ReadCellFunnel(const std::string& summary_path) {
  std::ifstream in(summary_path);
  const nlohmann::json summary = nlohmann::json::parse(in, nullptr, false);
  if (summary.is_discarded() || !summary.is_object()) throw std::runtime_error(summary_path + ": not a JSON object");
  CellFunnel funnel;
  try {
    if (summary.contains("stages")) {
      for (const nlohmann::json& step : summary.at("stages")) {
        FunnelCount count{step.at("stage").get<std::string>(), step.value("applies", true), Count(step, "reached"),
                          Count(step, "reached_alone")};
        if (count.applies && !count.reached) throw std::runtime_error(step.dump() + " has no reached count");
        funnel.stages.push_back(count);
      }
    }
    if (summary.contains("simulator_faults")) {
      funnel.simulator_faults = summary.at("simulator_faults").get<int64_t>();
    } else if (summary.contains("ends") && summary.at("ends").contains("physics_blow_up")) {
      funnel.simulator_faults = summary.at("ends").at("physics_blow_up").get<int64_t>();
    }
  } catch (const std::exception& error) {
    throw std::runtime_error(summary_path + ": stages or simulator_faults: " + error.what());
  }
  return funnel;
}

std::string FormatFunnelMarkdown(const ResultsTable& table, const std::vector<CellCounts>& cells) {
  // The rows the sweep's summary.json would hold for these cells, pooled per task and column.
  Json rows = Json::array();
  const std::string label = Labels(cells);
  for (const std::string& task : table.tasks) {
    for (const TableColumn& column : table.columns) {
      int64_t episodes = 0, successes = 0, faults = 0;
      std::vector<CellFunnel> funnels;
      for (const CellCounts& cell : cells) {
        if (cell.task != task || cell.robot != column.robot || cell.split != column.split ||
            cell.camera != column.camera)
          continue;
        funnels.push_back(ReadCellFunnel(cell.source));
        episodes += cell.n_episodes;
        successes += cell.n_successful;
        faults += funnels.back().simulator_faults;
      }
      if (episodes == 0) continue;
      Json stages = Json::array();
      for (const FunnelCount& step : PoolFunnels(funnels)) {
        const auto json = [](const std::optional<int64_t>& count) { return count ? Json(*count) : Json(); };
        stages.push_back({{"stage", step.stage},
                          {"applies", step.applies},
                          {"reached", json(step.reached)},
                          {"reached_alone", json(step.reached_alone)}});
      }
      rows.push_back({{"label", label},
                      {"task", task},
                      {"robot", column.robot},
                      {"split", column.split},
                      {"camera", column.camera},
                      {"episodes", episodes},
                      {"successes", successes},
                      {"simulator_faults", faults},
                      {"stages", stages}});
    }
  }
  std::string text = "\n## Stage funnel\n";
  for (const TextTable& funnel : StageFunnelTables(rows)) text += "\n" + ToMarkdown(funnel);
  return text;
}

}  // namespace tavis::batch::report
