#include "batch/report/galt_validation.h"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace tavis::batch::report {
namespace {

// Shortest "%g" form: 60 -> "60", 29.97 -> "29.97".
std::string FormatNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", value);
  return text;
}

std::string FormatFixed(double value, int decimals) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  return text;
}

std::string FormatSeconds(const std::optional<double>& seconds) { return seconds ? FormatFixed(*seconds, 2) : "-"; }

double DetectionRate(const cell::GaltSummary& summary) {
  return summary.n_episodes > 0 ? static_cast<double>(summary.n_valid) / summary.n_episodes : 0.0;
}

}  // namespace

int PolicyRateStride(double fps) {
  const double stride = std::round(fps / kPolicyRateHz);
  if (!(stride >= 1.0) || stride * kPolicyRateHz != fps) {
    throw std::invalid_argument("cannot downsample " + FormatNumber(fps) + " fps to the " +
                                FormatNumber(kPolicyRateHz) + " Hz policy rate: the fps must be a multiple of " +
                                FormatNumber(kPolicyRateHz));
  }
  return static_cast<int>(stride);
}

std::vector<kinematics::GaltResult> ComputeGaltEveryNth(const std::vector<kinematics::TrajectoryView>& episodes,
                                                        double fps, int stride) {
  std::vector<kinematics::TrajectoryView> sampled;
  sampled.reserve(episodes.size());
  for (const kinematics::TrajectoryView& episode : episodes) sampled.push_back(episode.Downsampled(stride));
  return kinematics::ComputeGaltBatch(sampled, fps / stride);
}

std::vector<GaltValidationRow> GaltValidationRows(const std::string& robot,
                                                  const std::vector<kinematics::TrajectoryView>& episodes, double fps,
                                                  const std::vector<kinematics::GaltResult>& at_fps) {
  const int stride = PolicyRateStride(fps);
  return {
      GaltValidationRow{robot, fps, 1, cell::SummarizeGalt(at_fps)},
      GaltValidationRow{robot, fps / stride, stride, cell::SummarizeGalt(ComputeGaltEveryNth(episodes, fps, stride))}};
}

std::string GaltValidationMarkdown(const std::vector<GaltValidationRow>& rows) {
  std::ostringstream out;
  out << "| robot | rate | episodes | detected | mean s | median s |\n"
      << "|---|---|---:|---:|---:|---:|\n";
  for (const GaltValidationRow& row : rows) {
    out << "| " << row.robot << " | " << FormatNumber(row.rate_hz) << " Hz | " << row.summary.n_episodes << " | "
        << row.summary.n_valid << " (" << FormatFixed(100.0 * DetectionRate(row.summary), 1) << " %) | "
        << FormatSeconds(row.summary.mean_s) << " | " << FormatSeconds(row.summary.median_s) << " |\n";
  }
  return out.str();
}

nlohmann::ordered_json GaltValidationJson(const std::vector<GaltValidationRow>& rows) {
  nlohmann::ordered_json json = nlohmann::ordered_json::array();
  for (const GaltValidationRow& row : rows) {
    nlohmann::ordered_json entry;
    entry["robot"] = row.robot;
    entry["rate_hz"] = row.rate_hz;
    entry["stride"] = row.stride;
    entry["detection_rate"] = DetectionRate(row.summary);
    const nlohmann::json summary = cell::GaltSummaryJson(row.summary);
    for (const auto& [key, value] : summary.items()) entry[key] = value;
    json.push_back(entry);
  }
  return json;
}

}  // namespace tavis::batch::report
