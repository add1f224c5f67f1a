// The paper's GALT validation table (reference spec 11.3, "Validation numbers"): per robot, the
// detection rate, mean and median GALT of the teleoperated episodes, at the dataset rate and at
// the 20 Hz policy rate (every fps/20-th frame, as a policy sees the episode).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/galt_summary.h"
#include "kinematics/galt.h"

namespace tavis::batch::report {

inline constexpr double kPolicyRateHz = 20.0;

struct GaltValidationRow {
  std::string robot;
  double rate_hz = 0.0;
  int stride = 1;             // dataset frames per sample at this rate
  cell::GaltSummary summary;  // "detected" = n_valid: reason ok or ok_post_anchor, as summary.json counts
};

// Frames per 20 Hz sample: fps / 20. Throws std::invalid_argument naming the fps unless it is a
// positive multiple of 20.
int PolicyRateStride(double fps);

// GALT of every episode sampled every `stride`-th frame (starting at frame 0), at fps / stride.
std::vector<kinematics::GaltResult> ComputeGaltEveryNth(const std::vector<kinematics::TrajectoryView>& episodes,
                                                        double fps, int stride);

// The two rows of one robot: `at_fps` (the GALT of every episode at the dataset rate, already
// computed for the per-episode output) and the episodes downsampled to 20 Hz.
std::vector<GaltValidationRow> GaltValidationRows(const std::string& robot,
                                                  const std::vector<kinematics::TrajectoryView>& episodes, double fps,
                                                  const std::vector<kinematics::GaltResult>& at_fps);

// Markdown: | robot | rate | episodes | detected | mean s | median s |, e.g.
// | gr1t2 | 60 Hz | 800 | 790 (98.8 %) | 2.57 | 2.57 |; "-" where no GALT was detected.
std::string GaltValidationMarkdown(const std::vector<GaltValidationRow>& rows);

// The rows' numbers: robot, rate_hz, stride, detection_rate (n_valid / n_episodes, 0 without
// episodes), then cell::GaltSummaryJson's keys (n_episodes, n_valid, mean_s, median_s, std_s, reasons).
nlohmann::ordered_json GaltValidationJson(const std::vector<GaltValidationRow>& rows);

}  // namespace tavis::batch::report
