// `tavis galt`: the GALT detector on commanded-action CSV files, one JSON object per line.
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/action_csv.h"
#include "kinematics/galt.h"
#include "tools/commands.h"

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
  still processed and the exit status is 1.)";

struct GaltOptions {
  double fps = 0.0;
  bool multi_event = false;
  std::vector<std::string> files;
};

nlohmann::json OptionalSeconds(const std::optional<double>& seconds) {
  return seconds ? nlohmann::json(*seconds) : nlohmann::json(nullptr);
}

nlohmann::ordered_json ResultJson(const std::string& file, const std::optional<int>& event,
                                  const kinematics::GaltResult& result) {
  nlohmann::ordered_json line;
  line["file"] = file;
  if (event) line["event"] = *event;
  line["galt_s"] = OptionalSeconds(result.galt_s);
  line["reason"] = kinematics::ToString(result.reason);
  line["arm"] = result.arm ? nlohmann::json(kinematics::Name(*result.arm))
                           : nlohmann::json(nullptr);
  line["t_head_arrival_s"] = OptionalSeconds(result.t_head_arrival_s);
  line["t_hand_arrival_s"] = OptionalSeconds(result.t_hand_arrival_s);
  line["t_hand_onset_s"] = OptionalSeconds(result.t_hand_onset_s);
  line["arm_reach_s"] = OptionalSeconds(result.arm_reach_s);
  return line;
}

void PrintGalt(const std::string& file, const batch::ActionTrajectory& trajectory,
               const GaltOptions& options) {
  if (!options.multi_event) {
    const kinematics::GaltResult result = kinematics::ComputeGalt(trajectory.view(), options.fps);
    std::cout << ResultJson(file, std::nullopt, result).dump() << "\n";
    return;
  }
  const std::vector<kinematics::GaltResult> events =
      kinematics::ComputeGaltEvents(trajectory.view(), options.fps);
  for (std::size_t i = 0; i < events.size(); ++i) {
    std::cout << ResultJson(file, static_cast<int>(i), events[i]).dump() << "\n";
  }
}

void RunGalt(const GaltOptions& options) {
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
    throw std::runtime_error("galt: " + std::to_string(failed) + " of " +
                             std::to_string(options.files.size()) + " files could not be read");
  }
}

}  // namespace

void RegisterGaltCommand(CLI::App& app) {
  auto options = std::make_shared<GaltOptions>();
  CLI::App* command = app.add_subcommand(
      "galt", "Gaze-Action Lead Time of commanded-action trajectories (CSV, T x 19)");
  command->add_option("--fps", options->fps, "Sampling rate of the rows in Hz (20 for policies)")
      ->required()
      ->check(
          [](const std::string& text) -> std::string {
            char* end = nullptr;
            const double fps = std::strtod(text.c_str(), &end);
            const bool positive = end != text.c_str() && *end == '\0' && fps > 0.0 &&
                                  std::isfinite(fps);
            return positive ? "" : "must be a positive number of rows per second, got " + text;
          },
          "POSITIVE");
  command->add_flag("--multi-event", options->multi_event,
                    "One result per gripper event of each arm instead of the latest event only");
  command->add_option("files", options->files, "CSV files, one episode each")->required();
  command->footer(kFormatHelp);
  command->callback([options] { RunGalt(*options); });
}

}  // namespace tavis::tools
