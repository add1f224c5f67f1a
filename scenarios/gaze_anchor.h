// A task's gaze anchors: the lead times its records measure from the head's arrival on a thing
// (the task's cue, or its target) to an action event (the reach onset, the grasp, a stage such as
// the lift), beside GALT's one anchor (docs/gaze.md, "Anchors"). Each task declares its own in its
// ScenarioDef; the recorder measures them on the fixations it traced (batch/cell/gaze_anchors.h).
#pragma once

#include <string>
#include <vector>

#include "scenarios/stage.h"

namespace tavis::scenarios {

struct GazeAnchor {
  // What the head arrives on: one of the task's cue objects, or the episode's target.
  enum class Fixation { kCue, kTarget };
  // The action event it leads: the reach onset and the gripper event GALT finds on the commanded
  // actions, or the first tick of one of the task's stages.
  enum class Event { kReachOnset, kGrasp, kStage };
  std::string name;  // the record's key, e.g. "card_to_reach"
  Fixation fixation = Fixation::kTarget;
  Event event = Event::kGrasp;
  std::string stage;  // kStage: the stage's key (stage.h), e.g. "target_lifted"
};

// The anchors of a pick with the task's `stages` (PickStages): the target's fixation before the
// grasp ("target_to_grasp") and before the raise stage ("target_to_lift" for target_lifted,
// "target_to_pull" for target_pulled); a task with a cue first has "<cue_name>_to_reach"
// ("card_to_reach", "light_to_reach"): its cue's fixation before the reach onset.
std::vector<GazeAnchor> PickGazeAnchors(const std::vector<StageDef>& stages, const std::string& cue_name = "");

// The names the summaries write: "cue", "target"; "reach_onset", "grasp", "stage".
const char* ToString(GazeAnchor::Fixation fixation);
const char* ToString(GazeAnchor::Event event);

}  // namespace tavis::scenarios
