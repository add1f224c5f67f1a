// `tavis galt`: the GALT detector on commanded-action CSV files or on a LeRobot dataset's
// episodes, one JSON object per line; for a dataset also the paper's validation table.
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/action_csv.h"
#include "batch/dataset/reader/dataset_actions.h"
#include "batch/dataset/reader/dataset_galt.h"
#include "batch/dataset/reader/dataset_info.h"
#include "batch/report/galt_validation.h"
#include "kinematics/galt.h"
#include "tools/commands.h"
#include "tools/option_parsing.h"

namespace tavis::tools {
namespace {

constexpr const char* kFormatHelp = R"(Input format:
  One CSV file per episode: one row per policy step (sampled at --fps), 19 comma-separated
  numbers per row, the canonical action in canonical-frame coordinates (0-based columns):
    0-2   left end-effector target x, y, z (m)      3-6   left target quaternion w, x, y, z
    7-9   right end-effector target x, y, z (m)     10-13 right target quaternion w, x, y, z
    14-16 neck roll, pitch, yaw (rad)               17, 18 left, right gripper (-1 open, +1 closed)
  A gripper command >= 0 counts as closed. An optional header row (no numeric field) may come
  first; blank lines are skipped. Values must be finite numbers.

Output:
  One JSON object per file (per gripper event with --multi-event, with an "event" index) with
  keys file, galt_s, reason, arm, t_head_arrival_s, t_hand_arrival_s, t_hand_onset_s,
  arm_reach_s (null where absent). Reasons: ok, ok_post_anchor, no_grasp, no_hand_onset,
  no_fixation, outlier_low, outlier_high, ambiguous_arms, too_short.
  A file that cannot be read is reported on stderr with its line number; the other files are
  still processed and the exit status is 1.

Dataset mode (--dataset DIR, instead of CSV files):
  A LeRobot dataset, codebase_version v3.0 (data/*/*.parquet) or v2.1
  (data/chunk-*/episode_*.parquet): the float32 `action` column (19 wide), grouped by
  episode_index with frame_index 0..T-1. The rate is meta/info.json's fps (1 to 1000; another
  value is refused, naming the file); --fps overrides it (with a note on stderr) only for a
  dataset whose info.json is known to be wrong.
  Prints one JSON object per episode, with "episode" (episode_index) and "task" (the episode's
  tasks from the episode metadata, joined by "; "; null when absent) in place of "file", then a
  blank line and the paper's validation table in Markdown: per robot (info.json robot_type,
  "unknown" when null) one row at the dataset rate and one at 20 Hz, taking every (fps/20)-th
  frame from frame 0 (the fps must be a multiple of 20). "detected" counts the valid GALTs
  (reason ok or ok_post_anchor); mean and median are over them, as summary.json's n_valid,
  mean_s and median_s. --table-only prints the table alone; --json-out FILE writes its numbers.
  Any unreadable or malformed dataset file is an error naming the file; exit status 1.)";

constexpr double kMinFps = batch::dataset::reader::kMinDatasetFps;
constexpr double kMaxFps = batch::dataset::reader::kMaxDatasetFps;

struct GaltOptions {
  double fps = 0.0;  // 0: not given
  bool multi_event = false;
  std::vector<std::string> files;
  std::string dataset;
  bool table_only = false;
  std::string json_out;
};

nlohmann::json OptionalSeconds(const std::optional<double>& seconds) {
  return seconds ? nlohmann::json(*seconds) : nlohmann::json(nullptr);
}

// `line` holds the keys naming the episode (file, or episode and task); the result's follow.
nlohmann::ordered_json ResultJson(nlohmann::ordered_json line, const std::optional<int>& event,
                                  const kinematics::GaltResult& result) {
  if (event) line["event"] = *event;
  line["galt_s"] = OptionalSeconds(result.galt_s);
  line["reason"] = kinematics::ToString(result.reason);
  line["arm"] = result.arm ? nlohmann::json(kinematics::Name(*result.arm)) : nlohmann::json(nullptr);
  line["t_head_arrival_s"] = OptionalSeconds(result.t_head_arrival_s);
  line["t_hand_arrival_s"] = OptionalSeconds(result.t_hand_arrival_s);
  line["t_hand_onset_s"] = OptionalSeconds(result.t_hand_onset_s);
  line["arm_reach_s"] = OptionalSeconds(result.arm_reach_s);
  return line;
}

void PrintGalt(const std::string& file, const batch::ActionTrajectory& trajectory, const GaltOptions& options) {
  if (!options.multi_event) {
    const kinematics::GaltResult result = kinematics::ComputeGalt(trajectory.view(), options.fps);
    std::cout << ResultJson({{"file", file}}, std::nullopt, result).dump() << "\n";
    return;
  }
  const std::vector<kinematics::GaltResult> events = kinematics::ComputeGaltEvents(trajectory.view(), options.fps);
  for (std::size_t i = 0; i < events.size(); ++i) {
    std::cout << ResultJson({{"file", file}}, static_cast<int>(i), events[i]).dump() << "\n";
  }
}

void RunGaltOnFiles(const GaltOptions& options) {
  int failed = 0;
  for (const std::string& file : options.files) {
    try {
      PrintGalt(file, batch::ReadActionCsv(file), options);
    } catch (const std::exception& e) {
      std::cout.flush();
      std::cerr << "tavis galt: error: " << e.what() << "\n";
      ++failed;
    }
  }
  std::cout.flush();
  if (failed > 0) {
    throw std::runtime_error("galt: " + std::to_string(failed) + " of " + std::to_string(options.files.size()) +
                             " files could not be read");
  }
}

// The rate GALT runs at: info.json's fps unless --fps overrides it.
double DatasetRate(const batch::dataset::reader::DatasetInfo& info, const GaltOptions& options) {
  if (options.fps == 0.0) {
    if (!(info.fps >= kMinFps && info.fps <= kMaxFps)) {
      throw std::invalid_argument(options.dataset + "/meta/info.json: fps must be a number from 1 to 1000, got " +
                                  nlohmann::json(info.fps).dump() + " (give --fps F if the file is wrong)");
    }
    return info.fps;
  }
  if (options.fps == info.fps) return info.fps;
  std::cerr << "tavis galt: note: --fps " << options.fps << " overrides the dataset's fps " << info.fps
            << " (meta/info.json)\n";
  return options.fps;
}

nlohmann::json TaskJson(const std::vector<std::string>& tasks) {
  if (tasks.empty()) return nullptr;
  std::string joined = tasks.front();
  for (std::size_t i = 1; i < tasks.size(); ++i) joined += "; " + tasks[i];
  return joined;
}

void WriteTableJson(const std::string& path, const batch::dataset::reader::DatasetInfo& info,
                    const GaltOptions& options, double fps, const std::vector<batch::report::GaltValidationRow>& rows) {
  nlohmann::ordered_json json;
  json["dataset"] = options.dataset;
  json["codebase_version"] = info.codebase_version;
  json["fps"] = fps;
  json["rows"] = batch::report::GaltValidationJson(rows);
  std::ofstream out(path);
  out << json.dump(2) << "\n";
  out.close();
  if (!out) throw std::runtime_error("galt: cannot write --json-out " + path);
}

void RunGaltOnDataset(const GaltOptions& options) {
  batch::dataset::reader::DatasetActions read = batch::dataset::reader::ReadDatasetActions(options.dataset);
  const double fps = DatasetRate(read.info, options);
  batch::report::PolicyRateStride(fps);  // refuse before any output

  const batch::dataset::reader::DatasetGalt galt = batch::dataset::reader::ComputeDatasetGalt(std::move(read), fps);
  const batch::dataset::reader::DatasetActions& actions = galt.actions;
  const std::vector<kinematics::GaltResult>& results = galt.results;
  const std::vector<batch::report::GaltValidationRow> rows =
      batch::report::GaltValidationRows(actions.info.robot_type.value_or("unknown"), galt.views, fps, results);

  if (!options.table_only) {
    for (std::size_t i = 0; i < results.size(); ++i) {
      const batch::dataset::reader::EpisodeActions& episode = actions.episodes[i];
      std::cout << ResultJson({{"episode", episode.episode_index}, {"task", TaskJson(episode.tasks)}}, std::nullopt,
                              results[i])
                       .dump()
                << "\n";
    }
    std::cout << "\n";
  }
  std::cout << batch::report::GaltValidationMarkdown(rows) << std::flush;
  if (!options.json_out.empty()) WriteTableJson(options.json_out, actions.info, options, fps, rows);
}

void RunGalt(const GaltOptions& options) {
  const bool dataset_mode = !options.dataset.empty();
  if (dataset_mode == !options.files.empty()) {
    throw std::invalid_argument("galt: give either CSV files or --dataset DIR (exactly one of them)");
  }
  if (dataset_mode) {
    if (options.multi_event) throw std::invalid_argument("galt: --multi-event applies to CSV files only");
    RunGaltOnDataset(options);
    return;
  }
  if (options.fps == 0.0) throw std::invalid_argument("galt: --fps is required with CSV files");
  if (options.table_only || !options.json_out.empty()) {
    throw std::invalid_argument("galt: --table-only and --json-out apply to --dataset only");
  }
  RunGaltOnFiles(options);
}

}  // namespace

void RegisterGaltCommand(CLI::App& app) {
  auto options = std::make_shared<GaltOptions>();
  CLI::App* command = app.add_subcommand(
      "galt", "Gaze-Action Lead Time of commanded-action trajectories (CSV files, T x 19, or a LeRobot dataset)");
  // Bounded: a rate far outside what a robot records at (1e9, 1e-300) gives confident nonsense
  // and overflows the step counts derived from it.
  command->add_option_function<std::string>(
      "--fps",
      [options](const std::string& text) { options->fps = ParseNumberInRange("--fps", text, kMinFps, kMaxFps); },
      "Sampling rate of the rows in Hz, 1 to 1000 (20 for policies); required with CSV files, "
      "with --dataset it overrides meta/info.json's fps");
  command->add_flag("--multi-event", options->multi_event,
                    "One result per gripper event of each arm instead of the latest event only");
  command->add_option("--dataset", options->dataset,
                      "LeRobot dataset directory (v3.0 or v2.1) instead of CSV files: GALT per episode "
                      "and the validation table at the dataset rate and at 20 Hz");
  command->add_flag("--table-only", options->table_only, "With --dataset: print only the validation table");
  command->add_option("--json-out", options->json_out, "With --dataset: write the table's numbers to this JSON file");
  command->add_option("files", options->files, "CSV files, one episode each");
  command->footer(kFormatHelp);
  command->callback([options] { RunGalt(*options); });
}

}  // namespace tavis::tools
