#include "batch/report/stage_funnel_table.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace tavis::batch::report {
namespace {

std::string Percent(int64_t count, int64_t total) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f",
                total > 0 ? 100.0 * static_cast<double>(count) / static_cast<double>(total) : 0.0);
  return text;
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
        funnel.stages.push_back({step.at("stage").get<std::string>(), step.at("reached").get<int64_t>()});
      }
    }
    if (summary.contains("simulator_faults")) {
      funnel.simulator_faults = summary.at("simulator_faults").get<int64_t>();
    } else if (summary.contains("ends") && summary.at("ends").contains("physics_blow_up")) {
      funnel.simulator_faults = summary.at("ends").at("physics_blow_up").get<int64_t>();
    }
  } catch (const nlohmann::json::exception& error) {
    throw std::runtime_error(summary_path + ": stages or simulator_faults: " + error.what());
  }
  return funnel;
}

std::string FormatFunnelMarkdown(const ResultsTable& table, const std::vector<CellCounts>& cells) {
  std::string text =
      "\n## Stage funnel\n\n"
      "| task | column | episodes | stages reached (%, each with every stage before it) | success % | simulator faults "
      "|\n"
      "|---|---|---|---|---|---|\n";
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
      // Cells of one task share its stages; one written before stages existed has none (and
      // counts as reaching none).
      std::vector<FunnelCount> stages;
      for (const CellFunnel& funnel : funnels) {
        if (stages.empty()) stages = funnel.stages;
      }
      for (FunnelCount& step : stages) {
        step.reached = 0;
        for (const CellFunnel& funnel : funnels) {
          for (const FunnelCount& other : funnel.stages) {
            if (other.stage == step.stage) step.reached += other.reached;
          }
        }
      }
      if (episodes == 0) continue;
      std::string reached;
      for (const FunnelCount& step : stages) {
        reached += (reached.empty() ? "" : " → ") + step.stage + " " + Percent(step.reached, episodes);
      }
      text += "| " + task + " | " + column.label() + " | " + std::to_string(episodes) + " | " +
              (reached.empty() ? "-" : reached) + " | " + Percent(successes, episodes) + " | " +
              std::to_string(faults) + " |\n";
    }
  }
  text +=
      "\nSimulator faults are episodes whose physics blew up (end `physics_blow_up`): the success rates above count "
      "them as failures; they are the simulator's, not the policy's.\n";
  return text;
}

}  // namespace tavis::batch::report
