#include "batch/cell/galt_summary.h"

#include <utility>

#include "batch/cell/statistics.h"

namespace tavis::batch::cell {

GaltSummary SummarizeGalt(const std::vector<kinematics::GaltResult>& successful_episodes) {
  GaltSummary summary;
  summary.n_episodes = static_cast<int>(successful_episodes.size());
  std::vector<double> values;
  values.reserve(successful_episodes.size());
  for (const kinematics::GaltResult& result : successful_episodes) {
    ++summary.reason_counts[static_cast<std::size_t>(result.reason)];
    if (result.galt_s) values.push_back(*result.galt_s);
  }
  summary.n_valid = static_cast<int>(values.size());
  if (values.empty()) return summary;

  const Spread spread = SpreadOf(std::move(values));
  summary.mean_s = spread.mean;
  summary.median_s = spread.median;
  summary.std_s = spread.std;
  return summary;
}

nlohmann::json GaltSummaryJson(const GaltSummary& summary) {
  nlohmann::json reasons = nlohmann::json::object();
  for (int r = 0; r < kinematics::kGaltReasonCount; ++r) {
    if (summary.reason_counts[r] > 0)
      reasons[kinematics::ToString(static_cast<kinematics::GaltReason>(r))] = summary.reason_counts[r];
  }
  auto optional_number = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(); };
  return {{"n_episodes", summary.n_episodes},          {"n_valid", summary.n_valid},
          {"mean_s", optional_number(summary.mean_s)}, {"median_s", optional_number(summary.median_s)},
          {"std_s", optional_number(summary.std_s)},   {"reasons", reasons}};
}

}  // namespace tavis::batch::cell
