#include "batch/report/gaze_section.h"

#include <string>

#include "batch/cell/gaze_anchors.h"
#include "batch/report/pooled_cells.h"
#include "scenarios/registry.h"

namespace tavis::batch::report {

using Json = nlohmann::ordered_json;

Json GazeRows(const std::vector<CellEpisodes>& cells) {
  Json rows = Json::array();
  for (const PooledCell& pooled : PoolBySetting(cells)) {
    std::vector<const cell::GazeRecord*> successful;
    Json verified = Json::array(), unverified = Json::array();
    for (const cell::EpisodeRecord& record : pooled.episodes) {
      if (!record.success) continue;
      successful.push_back(&record.gaze);
      if (!record.gaze.traced || !record.galt || !record.galt->galt_s) continue;
      (record.gaze.galt_verified_s ? verified : unverified).push_back(*record.galt->galt_s);
    }
    const nlohmann::json gaze = cell::GazeBlockJson(scenarios::FindScenario(pooled.task).gaze_anchors, successful);
    if (gaze.is_null()) continue;  // a robot without a head camera
    rows.push_back({{"task", pooled.task},
                    {"robot", pooled.robot},
                    {"split", pooled.split},
                    {"camera", ToString(pooled.camera)},
                    {"gaze", Json::parse(gaze.dump())},
                    {"galt_verified_values_s", verified},
                    {"galt_unverified_values_s", unverified}});
  }
  return rows;
}

namespace {

std::string PercentOrDash(const Json& fraction) { return fraction.is_null() ? "-" : Percent(fraction); }

}  // namespace

std::vector<TextTable> GazeTables(const Json& rows) {
  TextTable gaze{"gaze",
                 "Gaze: verified GALT and gaze on target (successful episodes)",
                 {"policy", "task", "robot", "split", "camera", "successful", "with GALT", "verified", "verified %",
                  "verified median s", "gaze on target %", "cue before reach %"},
                 {},
                 ""};
  TextTable anchors{"gaze_anchors",
                    "Gaze anchors: lead time from the head's arrival to an action event (s, successful episodes)",
                    {"policy", "task", "robot", "split", "camera", "anchor", "fixation", "event", "n", "missing",
                     "median s", "q1 s", "q3 s", "IQR s"},
                    {},
                    ""};
  for (const Json& row : rows) {
    const Json& block = row["gaze"];
    const std::vector<std::string> setting{row["label"], row["task"], row["robot"], row["split"], row["camera"]};
    std::vector<std::string> line = setting;
    for (const char* count : {"n_episodes", "n_with_galt", "n_verified"})
      line.push_back(std::to_string(block[count].get<int64_t>()));
    line.push_back(PercentOrDash(block["verified_fraction"]));
    line.push_back(Seconds(block["galt_verified_median_s"]));
    line.push_back(PercentOrDash(block["gaze_on_target_ratio_mean"]));
    line.push_back(PercentOrDash(block["cue_before_reach_fraction"]));
    gaze.rows.push_back(line);
    for (const Json& anchor : block["anchors"]) {
      std::vector<std::string> cells = setting;
      cells.push_back(anchor["anchor"]);
      cells.push_back(anchor["fixation"]);
      cells.push_back(anchor["event"]);
      cells.push_back(std::to_string(anchor["n"].get<int64_t>()));
      cells.push_back(std::to_string(anchor["n_missing"].get<int64_t>()));
      for (const char* key : {"median_s", "q1_s", "q3_s", "iqr_s"}) cells.push_back(Seconds(anchor[key]));
      anchors.rows.push_back(cells);
    }
  }
  gaze.note =
      "Definitions: docs/gaze.md. Over the successful episodes: verified, those whose GALT the head's fixation at the "
      "grasp confirms (of those with a GALT value); gaze on target, the mean share of the 3 s before the grasp the "
      "head's optical axis was on the target; cue before reach, the share whose cue was fixated before the reach "
      "onset (-: the task has no cue, or no episode a reach onset).";
  anchors.note =
      "Definitions: docs/gaze.md, \"Anchors\": each task's anchors, from the first step of the fixation on the cue or "
      "target that precedes the event (the reach onset and grasp of the episode's GALT, or a stage's first tick). "
      "Median and quartiles (linear interpolation) over the episodes with a value; missing: successful episodes "
      "without one.";
  return {gaze, anchors};
}

}  // namespace tavis::batch::report
