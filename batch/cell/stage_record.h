// The JSON of an episode's stages and targets (episodes.jsonl) and of a cell's stage funnel
// (summary.json), and reading them back. Line keys (docs: README, "Episode records"):
//   "prompt": the instruction;  "target": {"object": model name, the task's facts as their keys
//   and values (scenarios::TargetFact: conditional-pick's "side", multi-shelf-scan's "shelf",
//   peeking-box's "open_side"), and under a runtime perturbation level "moved_tick": the control
//   tick it was moved, null if never};  "stages": {stage: reached?};  "stage_ticks": {stage: first
//   control tick, null if never}.
// Summary key "stages": the funnel, in the task's order: [{"stage": name, "applies": whether the
// stage can be reached under the cell's camera protocol, "reached": episodes that reached it and
// every earlier stage that applies, "reached_alone": episodes that reached it whatever came
// before}, ...]; the counts are null for a stage that does not apply.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/camera_protocol.h"
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

// A stage of the funnel of one camera protocol. A gaze stage (cue_fixated) needs a head that
// moves: under a fixed view (fixed, fixed-only) the neck is zeroed, so it does not apply. It is
// shown as not applicable and left out of the chain, so the later stages of a fixed cell count
// what its episodes did, not a gaze they could not make.
struct FunnelStage {
  std::string name;
  bool applies = true;
};
// The task's stages in order, each marked for the protocol; throws as StageNames.
std::vector<FunnelStage> FunnelStages(const std::string& task, CameraProtocol camera);

// Per stage of `stages`: the episodes that reached it and every earlier stage that applies
// (`reached`, the cumulative funnel), and those that reached it whatever came before
// (`reached_alone`, the same under every protocol: how head and fixed compare stage by stage).
// Both 0 for a stage that does not apply. A record lacking a stage has not reached it.
struct FunnelStep {
  std::string stage;
  bool applies = true;
  int64_t reached = 0;
  int64_t reached_alone = 0;
};
std::vector<FunnelStep> StageFunnel(const std::vector<FunnelStage>& stages, const std::vector<EpisodeRecord>& episodes);
// The summary's "stages" entries of a funnel.
nlohmann::json FunnelJson(const std::vector<FunnelStep>& funnel);

}  // namespace tavis::batch::cell
