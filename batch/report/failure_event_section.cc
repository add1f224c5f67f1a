#include "batch/report/failure_event_section.h"

#include <cstdio>
#include <string>

#include "batch/camera_protocol.h"
#include "batch/cell/event_record.h"
#include "batch/cell/failure_events.h"
#include "batch/report/pooled_cells.h"

namespace tavis::batch::report {

using Json = nlohmann::ordered_json;

Json FailureEventRows(const std::vector<CellEpisodes>& cells) {
  Json rows = Json::array();
  for (const PooledCell& pooled : PoolBySetting(cells)) {
    const std::string& task = pooled.task;
    const CameraProtocol camera = pooled.camera;
    const std::vector<cell::EpisodeRecord>& records = pooled.episodes;
    Json events = Json::object();
    // In the events' declared order (the cell's JSON object sorts its keys).
    const nlohmann::json counts = cell::EventCountsJson(task, !UsesFixedView(camera), records);
    for (const cell::FailureEvent event : cell::AllFailureEvents()) events[ToString(event)] = counts[ToString(event)];
    rows.push_back({{"task", task},
                    {"robot", pooled.robot},
                    {"split", pooled.split},
                    {"camera", ToString(camera)},
                    {"episodes", static_cast<int64_t>(records.size())},
                    {"events", events},
                    {"motion", Json::parse(cell::MotionMediansJson(records).dump())}});
  }
  return rows;
}

namespace {

// A median with `decimals` decimals, "-" for none.
std::string Fixed(const Json& value, int decimals) {
  if (value.is_null()) return "-";
  char text[32];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value.get<double>());
  return text;
}

}  // namespace

std::vector<TextTable> FailureEventTables(const Json& rows) {
  TextTable events{"failure_events",
                   "Failure events: episodes (of the row's) in which each event fired",
                   {"policy", "task", "robot", "split", "camera", "episodes"},
                   {},
                   ""};
  for (const cell::FailureEvent event : cell::AllFailureEvents()) events.header.push_back(ToString(event));
  TextTable motion{"motion_quality",
                   "Motion quality: medians per arm of the tool centre point's path, RMS jerk and SPARC",
                   {"policy", "task", "robot", "split", "camera", "left path m", "left jerk m/s^3", "left SPARC",
                    "right path m", "right jerk m/s^3", "right SPARC"},
                   {},
                   ""};
  for (const Json& row : rows) {
    std::vector<std::string> cells{row["label"], row["task"],   row["robot"],
                                   row["split"], row["camera"], std::to_string(row["episodes"].get<int64_t>())};
    std::vector<std::string> arms{row["label"], row["task"], row["robot"], row["split"], row["camera"]};
    for (const cell::FailureEvent event : cell::AllFailureEvents()) {
      const Json& count = row["events"][ToString(event)];
      cells.push_back(count.is_null() ? "n/a" : std::to_string(count.get<int64_t>()));
    }
    for (const char* hand : cell::kHandKeys) {
      const Json& arm = row["motion"][hand];
      arms.push_back(Fixed(arm["path_m"], 3));
      arms.push_back(Fixed(arm["jerk_rms"], 1));
      arms.push_back(Fixed(arm["sparc"], 2));
    }
    events.rows.push_back(cells);
    motion.rows.push_back(arms);
  }
  events.note =
      "Definitions: docs/events.md. n/a: the event cannot fire in the cell (the cue and gaze events need a head that "
      "moves; reach_before_cue a cue and no go signal; reach_before_go a go signal).";
  motion.note =
      "Per arm over the row's episodes: path length of the tool centre point (m), RMS of its jerk by third "
      "differences at 60 Hz (m/s^3), SPARC of its speed (closer to 0 is smoother; over the episodes in which the arm "
      "moved 1 cm or more). -: no episode has the measure.";
  return {events, motion};
}

}  // namespace tavis::batch::report
