// The lead times of a task's gaze anchors (scenarios/gaze_anchor.h) in an episode, measured on
// its traced fixations (gaze_fixation.h): from the head's arrival on the anchor's thing (a cue, the
// target) to its action event (the reach onset or gripper event of the episode's GALT, or a
// stage's first tick); and their distributions over a cell's successful episodes (docs/gaze.md,
// "Anchors").
#pragma once

#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/gaze_fixation.h"
#include "kinematics/galt.h"
#include "scenarios/gaze_anchor.h"
#include "scenarios/stage.h"

namespace tavis::batch::cell {

// Where the episode's action events happen: its GALT (reach onset and gripper event, seconds) and
// the first control tick of each of the task's stages (-1: never), at control_hz.
struct AnchorEvents {
  const kinematics::GaltResult* galt = nullptr;  // null: no GALT (a failed episode, a fixed view)
  const std::vector<scenarios::StageDef>* stages = nullptr;
  const std::vector<int>* stage_first_ticks = nullptr;  // [stage]
  double control_hz = 60.0;
};

// The policy step the head arrived on `on` for an event at policy step `event_step`: the first
// step of the last fixation of `on` that began before the event, earlier fixations of it counted
// in when the gaze left it for less than GALT's fixation persistence (k_fix_s, 0.08 s: a single
// 20 Hz step); unset when none began before the event.
std::optional<int> ArrivalStep(const std::vector<FixationSegment>& fixations, GazeTarget on, int event_step,
                               double policy_hz);

// Each anchor's lead time (event time - arrival time, s) from the record's fixations, in declared
// order; unset where the event or the fixation is missing.
std::vector<AnchorLead> MeasureGazeAnchors(const std::vector<scenarios::GazeAnchor>& anchors,
                                           const std::vector<FixationSegment>& fixations, const AnchorEvents& events,
                                           double policy_hz);

// summary.json's gaze "anchors": per declared anchor, in order, {anchor, fixation, event (the
// stage's key for a stage event), n (episodes with a value), n_missing (traced successful episodes
// without one), median_s, q1_s, q3_s, iqr_s (nulls when n is 0)}, over the traced records given.
nlohmann::json GazeAnchorSummaryJson(const std::vector<scenarios::GazeAnchor>& anchors,
                                     const std::vector<const GazeRecord*>& successful_episodes);

// The whole "gaze" block of a cell (or of cells pooled): GazeSummaryJson with the anchors'
// distributions as "anchors"; null when no episode was traced.
nlohmann::json GazeBlockJson(const std::vector<scenarios::GazeAnchor>& anchors,
                             const std::vector<const GazeRecord*>& successful_episodes);

}  // namespace tavis::batch::cell
