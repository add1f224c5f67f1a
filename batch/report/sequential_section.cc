#include "batch/report/sequential_section.h"

#include <algorithm>
#include <cstdio>
#include <set>

#include "batch/cell/cell_settings.h"
#include "scenarios/split.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

std::string LabelOf(const CellEpisodes& cell) { return cell.label.empty() ? cell.config.policy : cell.label; }

Outcomes OutcomesOf(const CellEpisodes& cell) {
  Outcomes outcomes;
  for (const cell::EpisodeRecord& record : cell.episodes) outcomes.push_back(record.success);
  return outcomes;
}

std::string Side(const Json& row, const char* which) {
  return row[std::string(which) + "_label"].get<std::string>() + " " +
         row[std::string(which) + "_camera"].get<std::string>();
}

std::string DecisionText(const Json& row) {
  const std::string outcome = row["outcome"];
  if (outcome == "first_better") return Side(row, "first") + " better";
  if (outcome == "second_better") return Side(row, "second") + " better";
  return "undecided";
}

std::string EValueText(double e_value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", e_value);
  return text;
}

}  // namespace

Json SequentialSection(const std::vector<CellEpisodes>& cells, const SequentialSettings& settings) {
  std::vector<PairingCell> pairing;
  for (const CellEpisodes& cell : cells) pairing.push_back({&cell.config, LabelOf(cell)});
  const std::vector<SequentialPair> pairs = SequentialPairs(pairing, settings);
  Json rows = Json::array();
  std::set<std::size_t> paired;
  for (const SequentialPair& pair : pairs) {
    const CellEpisodes& first = cells[pair.first];
    const CellEpisodes& second = cells[pair.second];
    paired.insert(pair.first);
    paired.insert(pair.second);
    const SequentialDecision decision = DecideSequentially(OutcomesOf(first), OutcomesOf(second), settings.test);
    const bool decided = decision.outcome != SequentialOutcome::kUndecided;
    const int64_t cap = first.config.episodes;
    const int64_t stopped_at = static_cast<int64_t>(std::min(first.episodes.size(), second.episodes.size()));
    rows.push_back({{"kind", pair.kind},
                    {"first", first.id},
                    {"second", second.id},
                    {"first_label", LabelOf(first)},
                    {"second_label", LabelOf(second)},
                    {"task", first.config.task},
                    {"robot", first.config.robot},
                    {"split", scenarios::ToString(first.config.split)},
                    {"first_camera", ToString(first.config.camera)},
                    {"second_camera", ToString(second.config.camera)},
                    {"seed", first.config.seed},
                    {"stopped_at", stopped_at},
                    {"cap", cap},
                    {"stopped_early", stopped_at < cap},
                    {"outcome", ToString(decision.outcome)},
                    {"decided_at", decided ? Json(decision.pairs) : Json()},
                    {"first_only", decision.first_only},
                    {"second_only", decision.second_only},
                    {"e_value", decision.e_value},
                    {"episodes_saved", 2 * (cap - stopped_at)}});
  }
  int64_t run = 0, capped = 0, stopped_early = 0;
  for (const std::size_t i : paired) {
    run += static_cast<int64_t>(cells[i].episodes.size());
    capped += cells[i].config.episodes;
    stopped_early += static_cast<int64_t>(cells[i].episodes.size()) < cells[i].config.episodes ? 1 : 0;
  }
  return {{"settings", SequentialSettingsJson(settings)},
          {"pairs", rows},
          {"cells_in_pairs", paired.size()},
          {"cells_stopped_early", stopped_early},
          {"episodes_run", run},
          {"episodes_cap", capped},
          {"episodes_saved", capped - run}};
}

TextTable SequentialTable(const Json& summary) {
  const Json& section = summary["sequential"];
  TextTable table{"sequential_pairs",
                  "Sequential paired test: where each pair stopped",
                  {"kind", "first", "second", "task", "robot", "split", "seed", "stopped at", "cap", "decision",
                   "decided at", "first only", "second only", "e-value", "episodes saved"},
                  {},
                  ""};
  for (const Json& row : section["pairs"]) {
    table.rows.push_back({row["kind"], Side(row, "first"), Side(row, "second"), row["task"], row["robot"], row["split"],
                          std::to_string(row["seed"].get<uint64_t>()), std::to_string(row["stopped_at"].get<int64_t>()),
                          std::to_string(row["cap"].get<int64_t>()), DecisionText(row),
                          row["decided_at"].is_null() ? "-" : std::to_string(row["decided_at"].get<int64_t>()),
                          std::to_string(row["first_only"].get<int64_t>()),
                          std::to_string(row["second_only"].get<int64_t>()), EValueText(row["e_value"]),
                          std::to_string(row["episodes_saved"].get<int64_t>())});
  }
  const Json& settings = section["settings"];
  char level[64];
  std::snprintf(level, sizeof(level), "alpha %g, a look every %d pairs", settings["alpha"].get<double>(),
                settings["block"].get<int>());
  table.note =
      std::string("Anytime-valid test on the discordant pairs (") + level +
      "): the e-value B(b + 1/2, c + 1/2) / B(1/2, 1/2) * 2^(b + c) of b first-only and c second-only pairs; a "
      "pair decides at the first look where it reaches 1/alpha, and a group of paired cells stops when every "
      "pair in it has decided, or at the cap. Under equal success rates a pair decides with probability at "
      "most alpha (Ville's inequality). " +
      std::to_string(section["cells_stopped_early"].get<int64_t>()) + " of " +
      std::to_string(section["cells_in_pairs"].get<int64_t>()) + " paired cells stopped early; " +
      std::to_string(section["episodes_saved"].get<int64_t>()) + " of " +
      std::to_string(section["episodes_cap"].get<int64_t>()) + " episodes saved.";
  return table;
}

std::string SequentialHtml(const Json& summary) {
  if (!summary.contains("sequential")) return "";
  const Json& section = summary["sequential"];
  int64_t early = 0;
  for (const Json& row : section["pairs"]) early += row["stopped_early"].get<bool>() ? 1 : 0;
  return "<h2>Sequential paired test</h2>\n<p id=\"sequential\">" + std::to_string(early) + " of " +
         std::to_string(section["pairs"].size()) + " pairs stopped before the cap of " +
         std::to_string(summary["spec"]["episodes"].get<int64_t>()) + " episodes; " +
         std::to_string(section["episodes_saved"].get<int64_t>()) + " of " +
         std::to_string(section["episodes_cap"].get<int64_t>()) +
         " episodes saved (table sequential_pairs below: each pair's decision and where it stopped).</p>\n";
}

}  // namespace tavis::batch::report
