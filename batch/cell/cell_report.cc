#include "batch/cell/cell_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "batch/action_csv.h"
#include "batch/cell/cell_provenance.h"
#include "batch/cell/episode_times.h"
#include "batch/cell/event_record.h"
#include "batch/cell/galt_summary.h"
#include "batch/cell/gaze_anchors.h"
#include "batch/cell/stage_record.h"
#include "batch/cell/statistics.h"
#include "batch/output/atomic_file.h"
#include "batch/output/output_folder.h"
#include "batch/remote/value_json.h"
#include "scenarios/registry.h"

namespace tavis::batch::cell {
namespace {

// The GALT summary over the successful episodes' results in `slot`, computed at `fps`.
nlohmann::json GaltJson(const CellResult& result, std::optional<kinematics::GaltResult> EpisodeRecord::*slot,
                        double fps) {
  std::vector<kinematics::GaltResult> results;
  for (const EpisodeRecord& record : result.episodes) {
    if (record.*slot) results.push_back(*(record.*slot));
  }
  nlohmann::json galt = GaltSummaryJson(SummarizeGalt(results));
  galt["fps"] = fps;
  return galt;
}

// count, mean, median, 95th percentile (nearest rank) and maximum of `values_ms`; null when empty.
nlohmann::json MillisecondsJson(const std::vector<double>& values_ms) {
  if (values_ms.empty()) return nullptr;
  const std::size_t n = values_ms.size();
  return {{"count", n},
          {"mean_ms", std::accumulate(values_ms.begin(), values_ms.end(), 0.0) / static_cast<double>(n)},
          {"median_ms", NearestRank(values_ms, 0.5)},
          {"p95_ms", NearestRank(values_ms, 0.95)},
          {"max_ms", *std::max_element(values_ms.begin(), values_ms.end())}};
}

// What ended an invalid_action episode. A non-finite value is written as its name ("nan",
// "inf", "-inf"), which JSON has no number for.
nlohmann::json InvalidActionJson(const engine::InvalidAction& fault) {
  nlohmann::json value = fault.value;
  if (!std::isfinite(fault.value)) value = std::isnan(fault.value) ? "nan" : (fault.value > 0 ? "inf" : "-inf");
  return {{"entry", fault.entry >= 0 ? nlohmann::json(fault.entry) : nlohmann::json()},
          {"value", fault.entry >= 0 ? value : nlohmann::json()},
          {"reason", fault.reason}};
}

// How many episodes ended each way, for the ends that occurred.
nlohmann::json EndCountsJson(const std::vector<EpisodeRecord>& episodes) {
  std::map<std::string, int64_t> counts;
  for (const EpisodeRecord& record : episodes) ++counts[engine::ToString(record.end)];
  return counts;
}

}  // namespace

std::string EpisodeJsonLine(const EpisodeRecord& record, uint64_t seed) {
  nlohmann::json line = {
      {"episode", record.episode},
      {"seed", seed},
      {"success", record.success},
      {"end", engine::ToString(record.end)},
      {"length_steps", record.length_steps},
      {"length_control_ticks", record.length_control_ticks},
      {"solver_messages", record.solver_messages},
  };
  if (record.end == engine::EpisodeEnd::kInvalidAction)
    line["invalid_action"] = InvalidActionJson(record.invalid_action);
  auto add_galt = [&line](const std::optional<kinematics::GaltResult>& galt, const std::string& prefix) {
    if (!galt) return;
    line[prefix + "_s"] = galt->galt_s ? nlohmann::json(*galt->galt_s) : nlohmann::json();
    line[prefix + "_reason"] = kinematics::ToString(galt->reason);
  };
  add_galt(record.galt, "galt");
  add_galt(record.galt_policy_rate, "galt_policy_rate");
  AddStagesJson(record, line);
  AddEventsJson(record, line);
  AddGazeJson(record.gaze, line);
  return line.dump();
}

void WriteReplayCsv(const EpisodeRecord& record, const std::filesystem::path& out_dir) {
  const std::filesystem::path dir = out_dir / "actions";
  output::MakeOwnFolder(dir);  // never a link to elsewhere
  const std::filesystem::path path = dir / EpisodeActionsName(record.episode);
  WriteActionCsv(output::FreshPartialPath(path), record.replay_actions, ActionFileFormat::kGzip);
  output::RenamePartialIntoPlace(path);
}

void WriteCellReport(const CellResult& result, const RunInfo& info, const std::string& out_dir) {
  std::filesystem::create_directories(out_dir);
  std::string episodes_text;
  std::string times_text;
  bool timed = false;
  for (const EpisodeRecord& record : result.episodes) {
    if (!record.replay_actions.empty()) WriteReplayCsv(record, out_dir);
    episodes_text += EpisodeJsonLine(record, result.config.seed) + "\n";
    times_text += EpisodeTimesJsonLine(record.episode, record.times) + "\n";
    timed = timed || record.times.has_value();
  }
  // Episodes run by a cell are timed; those of the Python module's env, whose loop is its
  // caller's, are not, and get no time file.
  if (timed) output::WriteFileAtomically(std::filesystem::path(out_dir) / "episode_times.jsonl", times_text);
  output::WriteFileAtomically(std::filesystem::path(out_dir) / "episodes.jsonl", episodes_text);
  WriteCellSummary(result, info, out_dir);
}

void WriteCellSummary(const CellResult& result, const RunInfo& info, const std::string& out_dir,
                      const std::string& label) {
  const EvaluationCellConfig& config = result.config;
  const int n = static_cast<int>(result.episodes.size());
  const ProportionInterval ci = WilsonInterval(result.successes, n);
  // The settings summary.json records (cell_settings.h), then the results.
  nlohmann::json summary = RecordedSettingsJson(config, CellRecord::kSummary, result.requests.has_value());
  if (config.actions_file.empty()) summary["actions_file"] = nullptr;  // as summaries have always said
  const nlohmann::json results = {
      {"n_episodes", n},
      {"n_successful", result.successes},
      {"success_rate", n > 0 ? static_cast<double>(result.successes) / n : 0.0},
      {"ci_low", ci.low},
      {"ci_high", ci.high},
      {"ends", EndCountsJson(result.episodes)},
      // Episodes the simulator failed (physics blew up): counted as failures in the success
      // rate, reported apart from the policy's.
      {"simulator_faults",
       std::count_if(result.episodes.begin(), result.episodes.end(),
                     [](const EpisodeRecord& record) { return record.end == engine::EpisodeEnd::kPhysicsBlowUp; })},
      {"stages", FunnelJson(StageFunnel(FunnelStages(config.task, config.camera), result.episodes))},
      {"events", EventCountsJson(config.task, !UsesFixedView(config.camera), result.episodes)},
      {"motion", MotionMediansJson(result.episodes)},
      {"wall_s", result.wall_s},
      {"envs", result.envs},
      {"threads", info.threads},
      {"resumed_episodes", info.resumed_episodes},
      {"control_ticks", result.control_ticks},
      {"control_ticks_per_s", result.wall_s > 0 ? static_cast<double>(result.control_ticks) / result.wall_s : 0.0},
      {"render",
       {{"cameras", result.rendered_cameras},
        {"width", result.render_width},
        {"height", result.render_height},
        {"images", result.rendered_images}}},
  };
  summary.update(results);
  // null under the fixed protocol, where no GALT is computed (as in the reference).
  summary["galt"] =
      !UsesFixedView(config.camera) ? GaltJson(result, &EpisodeRecord::galt, result.galt_fps) : nlohmann::json();
  std::vector<const GazeRecord*> gaze;
  for (const EpisodeRecord& record : result.episodes) {
    if (record.success) gaze.push_back(&record.gaze);
  }
  const std::vector<scenarios::GazeAnchor>& anchors = scenarios::FindScenario(config.task).gaze_anchors;
  if (nlohmann::json gaze_summary = GazeBlockJson(anchors, gaze); !gaze_summary.is_null())
    summary["gaze"] = gaze_summary;
  if (result.galt_policy_rate_fps > 0.0) {
    summary["galt_policy_rate"] = GaltJson(result, &EpisodeRecord::galt_policy_rate, result.galt_policy_rate_fps);
  }
  if (result.requests) {
    nlohmann::json metadata = nlohmann::json::array();
    for (const remote::Value& message : result.server_metadata) metadata.push_back(remote::ToJson(message));
    summary["server_metadata"] = metadata;
    summary["observation_keys"] = result.observation_keys_source;
    if (!config.observation_dataset.empty()) summary["layout_differences"] = result.layout_differences;
    summary["policy_image"] = {{"width", config.image_width}, {"height", config.image_height}};
    const std::vector<int>& batch_sizes = result.requests->envs_per_request;
    int64_t env_requests = 0;
    for (int envs : batch_sizes) env_requests += envs;
    summary["requests"] = {
        {"count", result.requests->round_trip_ms.size()},
        {"env_requests", env_requests},
        {"mean_batch_size", batch_sizes.empty() ? 0.0 : static_cast<double>(env_requests) / batch_sizes.size()},
        {"policy_ticks", result.requests->policy_ticks},
        {"wait_s", result.requests->wait_ms / 1000.0},
        {"reconnects", result.requests->reconnects},
        {"round_trip", MillisecondsJson(result.requests->round_trip_ms)},
        {"server_infer", MillisecondsJson(result.requests->server_infer_ms)}};
  }
  // Where the cell came from and how it ran: never compared (cell_provenance.h).
  summary["provenance"] = CellProvenanceJson(result, {label, info.threads});
  output::WriteFileAtomically(std::filesystem::path(out_dir) / "summary.json", summary.dump(2) + "\n");
}

std::string CellSummaryLine(const CellResult& result) {
  const int n = static_cast<int>(result.episodes.size());
  const ProportionInterval ci = WilsonInterval(result.successes, n);
  char line[512];
  std::snprintf(line, sizeof(line),
                "%s %s %s policy=%s camera=%s: success %d/%d = %.1f%% [%.1f, %.1f] (95%% Wilson), %.1f s",
                result.config.task.c_str(), result.config.robot.c_str(), scenarios::ToString(result.config.split),
                result.config.policy.c_str(), ToString(result.config.camera), result.successes, n,
                n > 0 ? 100.0 * result.successes / n : 0.0, 100.0 * ci.low, 100.0 * ci.high, result.wall_s);
  const auto invalid = [](const EpisodeRecord& record) { return record.end == engine::EpisodeEnd::kInvalidAction; };
  const auto first = std::find_if(result.episodes.begin(), result.episodes.end(), invalid);
  if (first == result.episodes.end()) return line;
  std::string text = line;
  text += "; " + std::to_string(std::count_if(result.episodes.begin(), result.episodes.end(), invalid)) +
          " ended invalid_action (first: episode " + std::to_string(first->episode);
  if (first->invalid_action.entry >= 0) {
    text += ", entry " + std::to_string(first->invalid_action.entry) + " = " +
            InvalidActionJson(first->invalid_action)["value"].dump();
  }
  return text + ": " + first->invalid_action.reason + ")";
}

}  // namespace tavis::batch::cell
