#include "batch/cell/stage_record.h"

#include <stdexcept>
#include <string>
#include <variant>

#include "kinematics/invariant.h"
#include "scenarios/registry.h"

namespace tavis::batch::cell {
namespace {

// The target's keys the record itself writes; the others are the task's facts.
bool IsRecordsTargetKey(const std::string& key) { return key == "object" || key == "moved_tick"; }

}  // namespace

void AddStagesJson(const EpisodeRecord& record, nlohmann::json& line) {
  line["prompt"] = record.prompt;
  nlohmann::json target = {{"object", record.target_object}};
  for (const scenarios::TargetFact& fact : record.target) {
    TAVIS_INVARIANT(!IsRecordsTargetKey(fact.key), "a task's fact does not take a key of the record's");
    std::visit([&](const auto& value) { target[fact.key] = value; }, fact.value);
  }
  if (record.target_move_tick) {
    target["moved_tick"] = *record.target_move_tick >= 0 ? nlohmann::json(*record.target_move_tick) : nlohmann::json();
  }
  line["target"] = target;
  nlohmann::json reached = nlohmann::json::object();
  nlohmann::json ticks = nlohmann::json::object();
  for (const StageReached& stage : record.stages) {
    reached[stage.name] = stage.reached();
    ticks[stage.name] = stage.reached() ? nlohmann::json(stage.first_tick) : nlohmann::json();
  }
  line["stages"] = reached;
  line["stage_ticks"] = ticks;
}

void ParseStagesJson(const nlohmann::json& line, EpisodeRecord& record) {
  if (line.contains("prompt")) record.prompt = line.at("prompt").get<std::string>();
  if (line.contains("target")) {
    const nlohmann::json& target = line.at("target");
    record.target_object = target.at("object").get<std::string>();
    for (const auto& [key, value] : target.items()) {
      if (IsRecordsTargetKey(key)) continue;
      if (value.is_string()) {
        record.target.push_back({key, value.get<std::string>()});
      } else if (value.is_number_integer()) {
        record.target.push_back({key, value.get<int>()});
      } else {
        throw std::invalid_argument("target." + key + " " + value.dump() + " is not a text or a whole number");
      }
    }
    if (target.contains("moved_tick")) {
      const nlohmann::json& tick = target.at("moved_tick");
      record.target_move_tick = tick.is_null() ? -1 : tick.get<int>();
    }
  }
  if (!line.contains("stage_ticks")) return;
  // A JSON object does not keep the task's order of its stages (the keys come back sorted):
  // StageFunnel looks stages up by name in the order it is given.
  for (const auto& [name, tick] : line.at("stage_ticks").items()) {
    if (!tick.is_null() && !tick.is_number_integer()) {
      throw std::invalid_argument("stage_ticks." + name + " " + tick.dump() + " is not a control tick or null");
    }
    record.stages.push_back({name, tick.is_null() ? -1 : tick.get<int>()});
  }
}

namespace {

bool Reached(const EpisodeRecord& record, const std::string& stage) {
  for (const StageReached& entry : record.stages) {
    if (entry.name == stage) return entry.reached();
  }
  return false;
}

}  // namespace

std::vector<std::string> StageNames(const std::string& task) {
  std::vector<std::string> names;
  for (const scenarios::StageDef& stage : scenarios::FindScenario(task).stages) names.push_back(stage.name);
  return names;
}

std::vector<FunnelStage> FunnelStages(const std::string& task, CameraProtocol camera) {
  std::vector<FunnelStage> stages;
  for (const scenarios::StageDef& stage : scenarios::FindScenario(task).stages) {
    const bool needs_head = stage.kind == scenarios::StageDef::Kind::kCueFixated;
    stages.push_back({stage.name, !(needs_head && UsesFixedView(camera))});
  }
  return stages;
}

std::vector<FunnelStep> StageFunnel(const std::vector<FunnelStage>& stages,
                                    const std::vector<EpisodeRecord>& episodes) {
  std::vector<FunnelStep> funnel;
  for (const FunnelStage& stage : stages) funnel.push_back({stage.name, stage.applies, 0, 0});
  for (const EpisodeRecord& record : episodes) {
    bool every_earlier = true;
    for (FunnelStep& step : funnel) {
      if (!step.applies) continue;
      const bool reached = Reached(record, step.stage);
      every_earlier = every_earlier && reached;
      step.reached += every_earlier ? 1 : 0;
      step.reached_alone += reached ? 1 : 0;
    }
  }
  return funnel;
}

nlohmann::json FunnelJson(const std::vector<FunnelStep>& funnel) {
  nlohmann::json steps = nlohmann::json::array();
  for (const FunnelStep& step : funnel) {
    const auto count = [&](int64_t value) { return step.applies ? nlohmann::json(value) : nlohmann::json(); };
    steps.push_back({{"stage", step.stage},
                     {"applies", step.applies},
                     {"reached", count(step.reached)},
                     {"reached_alone", count(step.reached_alone)}});
  }
  return steps;
}

}  // namespace tavis::batch::cell
