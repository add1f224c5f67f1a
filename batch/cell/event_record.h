// The JSON of an episode's failure events and motion quality (episodes.jsonl), of a cell's
// aggregates of them (summary.json), and reading them back. Line keys (docs/events.md):
//   "events": {event: the control tick it first fired}, the events that fired only (an empty object
//   for none);  "motion": {"left"|"right": {"path_m": m, "jerk_rms": m/s^3, "sparc": negative, null
//   for an arm that did not move}}.
// Summary keys: "events": {event: episodes it fired in, for every event; null for one that cannot
// fire in the cell (failure_events.h, ApplicableEvents)};  "motion": {"left"|"right": {"path_m",
// "jerk_rms", "sparc": the median over the episodes that have one, null when none}}.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/episode_recorder.h"

namespace tavis::batch::cell {

// The hands' keys, by kinematics::Index.
inline constexpr std::array<const char*, 2> kHandKeys = {"left", "right"};

// Adds the record's events and motion to its line (nothing for a record without them).
void AddEventsJson(const EpisodeRecord& record, nlohmann::json& line);

// Reads them back; a line without them (written before they existed) leaves them unset. Throws
// std::invalid_argument naming a malformed key or an unknown event.
void ParseEventsJson(const nlohmann::json& line, EpisodeRecord& record);

// The summary's "events" of a cell of `task` (the head moving or not) over `episodes`: per event
// the episodes it fired in (those with events recorded), null where it cannot fire.
nlohmann::json EventCountsJson(const std::string& task, bool head_moves, const std::vector<EpisodeRecord>& episodes);

// The summary's "motion": per hand the medians of its measures over the episodes that have them.
nlohmann::json MotionMediansJson(const std::vector<EpisodeRecord>& episodes);

}  // namespace tavis::batch::cell
