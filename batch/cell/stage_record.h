// The JSON of an episode's stages and targets (episodes.jsonl) and of a cell's stage funnel
// (summary.json), and reading them back. Line keys (docs: README, "Episode records"):
//   "prompt": the instruction;  "target": {"object": model name, "side" / "shelf" / "open_side"
//   where the task has them, and under a runtime perturbation level "moved_tick": the control tick
//   it was moved, null if never};  "stages": {stage: reached?};  "stage_ticks": {stage: first
//   control tick, null if never}.
// Summary key "stages": [{"stage": name, "reached": episodes that reached it and every stage
// before it}, ...] in the task's order: the funnel.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/episode_recorder.h"

namespace tavis::batch::cell {

// Adds the record's prompt, target, stages and stage_ticks to its line.
void AddStagesJson(const EpisodeRecord& record, nlohmann::json& line);

// Reads them back into the record; a line without them (written before stages existed) leaves
// them empty. Throws std::invalid_argument naming a malformed key.
void ParseStagesJson(const nlohmann::json& line, EpisodeRecord& record);

// The names of the task's stages (its ScenarioDef), in order; throws std::invalid_argument for
// an unknown task.
std::vector<std::string> StageNames(const std::string& task);

// Per stage of `stages` (the task's order): the episodes that reached it and every earlier one.
// A record lacking a stage has not reached it.
struct FunnelStep {
  std::string stage;
  int64_t reached = 0;
};
std::vector<FunnelStep> StageFunnel(const std::vector<std::string>& stages, const std::vector<EpisodeRecord>& episodes);
nlohmann::json StageFunnelJson(const std::vector<std::string>& stages, const std::vector<EpisodeRecord>& episodes);

}  // namespace tavis::batch::cell
