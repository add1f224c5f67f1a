#include "batch/report/stage_funnel_section.h"

#include <algorithm>
#include <map>
#include <string>
#include <tuple>

#include "batch/camera_protocol.h"
#include "batch/cell/stage_record.h"
#include "batch/report/pooled_cells.h"
#include "scenarios/split.h"

namespace tavis::batch::report {

using Json = nlohmann::ordered_json;

Json StageFunnelRows(const std::vector<CellEpisodes>& cells) {
  Json rows = Json::array();
  for (const PooledCell& pooled : PoolBySetting(cells)) {
    const std::string& task = pooled.task;
    const CameraProtocol camera = pooled.camera;
    const std::vector<cell::EpisodeRecord>& records = pooled.episodes;
    int64_t successes = 0, faults = 0;
    for (const cell::EpisodeRecord& record : records) {
      successes += record.success ? 1 : 0;
      faults += record.end == engine::EpisodeEnd::kPhysicsBlowUp ? 1 : 0;
    }
    Json stages = Json::array();
    for (const nlohmann::json& step : cell::FunnelJson(cell::StageFunnel(cell::FunnelStages(task, camera), records))) {
      stages.push_back({{"stage", step["stage"]},
                        {"applies", step["applies"]},
                        {"reached", step["reached"]},
                        {"reached_alone", step["reached_alone"]}});
    }
    rows.push_back({{"task", task},
                    {"robot", pooled.robot},
                    {"split", pooled.split},
                    {"camera", ToString(camera)},
                    {"episodes", static_cast<int64_t>(records.size())},
                    {"successes", successes},
                    {"simulator_faults", faults},
                    {"stages", stages}});
  }
  return rows;
}

namespace {

// A count as a percent of `episodes`: "-" when either is unknown (a summary written before a
// count existed, or no episodes).
std::string Share(const Json& count, int64_t episodes) {
  if (count.is_null() || episodes <= 0) return "-";
  return Percent(static_cast<double>(count.get<int64_t>()) / static_cast<double>(episodes));
}

// The text of a camera's row at one stage: "n/a" where the stage does not apply to the camera.
std::string StageShare(const Json& row, const std::string& stage, const char* count) {
  for (const Json& step : row["stages"]) {
    if (step["stage"] != stage) continue;
    if (step.contains("applies") && !step["applies"].get<bool>()) return "n/a";
    return Share(step.contains(count) ? step[count] : Json(), row["episodes"].get<int64_t>());
  }
  return "-";
}

}  // namespace

std::vector<TextTable> StageFunnelTables(const Json& rows) {
  // The cameras the rows have, in the protocols' order (head beside fixed), then any other name.
  std::vector<std::string> cameras;
  for (const std::string& camera : CameraProtocolNames()) {
    if (std::any_of(rows.begin(), rows.end(), [&](const Json& row) { return row["camera"] == camera; }))
      cameras.push_back(camera);
  }
  for (const Json& row : rows) {
    if (std::find(cameras.begin(), cameras.end(), row["camera"]) == cameras.end()) cameras.push_back(row["camera"]);
  }
  TextTable funnel{"stage_funnel",
                   "Stage funnel, the cameras side by side: episodes (%) that reached each stage and every earlier "
                   "stage that applies, and that reached it alone",
                   {"policy", "task", "robot", "split", "stage"},
                   {},
                   ""};
  for (const std::string& camera : cameras) {
    funnel.header.push_back(camera + " %");
    funnel.header.push_back(camera + " alone %");
  }
  // A group: one label, task, robot and split; its rows are its cameras.
  using Group = std::tuple<std::string, std::string, std::string, std::string>;
  std::vector<Group> order;
  std::map<Group, std::vector<const Json*>> groups;
  for (const Json& row : rows) {
    const Group group{row["label"], row["task"], row["robot"], row["split"]};
    if (!groups.count(group)) order.push_back(group);
    groups[group].push_back(&row);
  }
  for (const Group& group : order) {
    const auto& [label, task, robot, split] = group;
    // The task's stages, from the group's first row that has them (one written before stages
    // existed has none).
    std::vector<std::string> stages;
    for (const Json* row : groups[group]) {
      if (!stages.empty()) break;
      for (const Json& step : (*row)["stages"]) stages.push_back(step["stage"]);
    }
    for (const std::string& stage : stages) {
      std::vector<std::string> cells{label, task, robot, split, stage};
      for (const std::string& camera : cameras) {
        const auto found = std::find_if(groups[group].begin(), groups[group].end(),
                                        [&](const Json* row) { return (*row)["camera"] == camera; });
        cells.push_back(found == groups[group].end() ? "-" : StageShare(**found, stage, "reached"));
        cells.push_back(found == groups[group].end() ? "-" : StageShare(**found, stage, "reached_alone"));
      }
      funnel.rows.push_back(cells);
    }
  }
  funnel.note =
      "head %, fixed %, ...: of that camera's episodes, those that reached the stage and every earlier stage that "
      "applies; "
      "alone: those that reached it whatever came before, comparable across cameras stage by stage. n/a: the stage "
      "does not apply to the camera (a fixed view zeroes the neck, so it has no gaze stage and its later stages are "
      "counted without it); -: no cells of that camera, or a summary written before the count existed.";

  TextTable episodes{"stage_funnel_episodes",
                     "Stage funnel: episodes, success rate and simulator faults per camera",
                     {"policy", "task", "robot", "split", "camera", "episodes", "success %", "simulator faults"},
                     {},
                     ""};
  for (const Json& row : rows) {
    const int64_t count = row["episodes"].get<int64_t>();
    episodes.rows.push_back({row["label"], row["task"], row["robot"], row["split"], row["camera"],
                             std::to_string(count), Share(row["successes"], count),
                             std::to_string(row["simulator_faults"].get<int64_t>())});
  }
  episodes.note =
      "Simulator faults are episodes whose physics blew up (physics_blow_up): every success rate counts them as "
      "failures; they are the simulator's, not the policy's.";
  return {funnel, episodes};
}

}  // namespace tavis::batch::report
