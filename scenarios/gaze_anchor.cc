#include "scenarios/gaze_anchor.h"

#include <stdexcept>

namespace tavis::scenarios {

std::vector<GazeAnchor> PickGazeAnchors(const std::vector<StageDef>& stages, const std::string& cue_name) {
  std::vector<GazeAnchor> anchors;
  if (!cue_name.empty()) {
    anchors.push_back({cue_name + "_to_reach", GazeAnchor::Fixation::kCue, GazeAnchor::Event::kReachOnset, ""});
  }
  anchors.push_back({"target_to_grasp", GazeAnchor::Fixation::kTarget, GazeAnchor::Event::kGrasp, ""});
  for (const StageDef& stage : stages) {
    if (stage.kind != StageDef::Kind::kTargetRaised) continue;
    // "target_lifted" -> "target_to_lift", "target_pulled" -> "target_to_pull".
    const std::string verb = stage.name.substr(stage.name.find('_') + 1);
    anchors.push_back({"target_to_" + verb.substr(0, verb.size() - 2), GazeAnchor::Fixation::kTarget,
                       GazeAnchor::Event::kStage, stage.name});
    return anchors;
  }
  throw std::invalid_argument("PickGazeAnchors: the stages have no raise stage (PickStages makes one)");
}

const char* ToString(GazeAnchor::Fixation fixation) {
  return fixation == GazeAnchor::Fixation::kCue ? "cue" : "target";
}

const char* ToString(GazeAnchor::Event event) {
  switch (event) {
    case GazeAnchor::Event::kReachOnset: return "reach_onset";
    case GazeAnchor::Event::kGrasp: return "grasp";
    case GazeAnchor::Event::kStage: return "stage";
  }
  return "stage";
}

}  // namespace tavis::scenarios
