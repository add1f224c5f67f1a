#include "batch/cell/gaze_anchors.h"

#include <cmath>

#include "batch/cell/statistics.h"

namespace tavis::batch::cell {
namespace {

GazeTarget TargetOf(scenarios::GazeAnchor::Fixation fixation) {
  return fixation == scenarios::GazeAnchor::Fixation::kCue ? GazeTarget::kCue : GazeTarget::kTarget;
}

// The anchor's event time (s from the episode's first tick), unset when the episode has none.
std::optional<double> EventTime(const scenarios::GazeAnchor& anchor, const AnchorEvents& events) {
  switch (anchor.event) {
    case scenarios::GazeAnchor::Event::kReachOnset: return events.galt ? events.galt->t_hand_onset_s : std::nullopt;
    case scenarios::GazeAnchor::Event::kGrasp: return events.galt ? events.galt->t_hand_arrival_s : std::nullopt;
    case scenarios::GazeAnchor::Event::kStage:
      if (events.stages == nullptr || events.stage_first_ticks == nullptr) return std::nullopt;
      for (std::size_t s = 0; s < events.stages->size(); ++s) {
        const int tick = (*events.stage_first_ticks)[s];
        if ((*events.stages)[s].name == anchor.stage && tick >= 0) return tick / events.control_hz;
      }
      return std::nullopt;
  }
  return std::nullopt;
}

std::string EventName(const scenarios::GazeAnchor& anchor) {
  return anchor.event == scenarios::GazeAnchor::Event::kStage ? anchor.stage : scenarios::ToString(anchor.event);
}

}  // namespace

std::optional<int> ArrivalStep(const std::vector<FixationSegment>& fixations, GazeTarget on, int event_step,
                               double policy_hz) {
  const double persistence_s = kinematics::GaltParams{}.k_fix_s;
  int last = -1;
  for (std::size_t i = 0; i < fixations.size(); ++i) {
    if (fixations[i].target == on && fixations[i].start < event_step) last = static_cast<int>(i);
  }
  if (last < 0) return std::nullopt;
  int arrival = fixations[static_cast<std::size_t>(last)].start;
  for (int i = last - 1; i >= 0; --i) {
    const FixationSegment& earlier = fixations[static_cast<std::size_t>(i)];
    if (earlier.target != on) continue;
    // A glance away shorter than a fixation is the same fixation (as GALT's settling rule).
    if ((arrival - earlier.end) / policy_hz >= persistence_s) break;
    arrival = earlier.start;
  }
  return arrival;
}

std::vector<AnchorLead> MeasureGazeAnchors(const std::vector<scenarios::GazeAnchor>& anchors,
                                           const std::vector<FixationSegment>& fixations, const AnchorEvents& events,
                                           double policy_hz) {
  std::vector<AnchorLead> leads;
  for (const scenarios::GazeAnchor& anchor : anchors) {
    AnchorLead lead{anchor.name, std::nullopt};
    if (const std::optional<double> t_event = EventTime(anchor, events)) {
      // The policy step the event falls in (as VerifyGalt places the grasp).
      const int event_step = static_cast<int>(std::floor(*t_event * policy_hz + 1e-9));
      if (const std::optional<int> arrival = ArrivalStep(fixations, TargetOf(anchor.fixation), event_step, policy_hz))
        lead.lead_s = *t_event - *arrival / policy_hz;
    }
    leads.push_back(lead);
  }
  return leads;
}

nlohmann::json GazeAnchorSummaryJson(const std::vector<scenarios::GazeAnchor>& anchors,
                                     const std::vector<const GazeRecord*>& successful_episodes) {
  nlohmann::json rows = nlohmann::json::array();
  for (const scenarios::GazeAnchor& anchor : anchors) {
    std::vector<double> values;
    int missing = 0;
    for (const GazeRecord* record : successful_episodes) {
      if (!record->traced) continue;
      std::optional<double> value;
      for (const AnchorLead& lead : record->anchors) {
        if (lead.name == anchor.name) value = lead.lead_s;
      }
      value ? values.push_back(*value) : static_cast<void>(++missing);
    }
    nlohmann::json row = {{"anchor", anchor.name},
                          {"fixation", scenarios::ToString(anchor.fixation)},
                          {"event", EventName(anchor)},
                          {"n", values.size()},
                          {"n_missing", missing},
                          {"median_s", nullptr},
                          {"q1_s", nullptr},
                          {"q3_s", nullptr},
                          {"iqr_s", nullptr}};
    if (!values.empty()) {
      const double q1 = Quantile(values, 0.25), q3 = Quantile(values, 0.75);
      row["median_s"] = Median(values);
      row["q1_s"] = q1;
      row["q3_s"] = q3;
      row["iqr_s"] = q3 - q1;
    }
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json GazeBlockJson(const std::vector<scenarios::GazeAnchor>& anchors,
                             const std::vector<const GazeRecord*>& successful_episodes) {
  nlohmann::json gaze = GazeSummaryJson(successful_episodes);
  if (!gaze.is_null()) gaze["anchors"] = GazeAnchorSummaryJson(anchors, successful_episodes);
  return gaze;
}

}  // namespace tavis::batch::cell
