// Per-cell GALT statistics, as the reference's compute_summary reports them (spec 10.2).
#pragma once

#include <array>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "kinematics/galt.h"

namespace tavis::batch::cell {

struct GaltSummary {
  int n_episodes = 0;  // GALT results summarised (the cell's successful episodes)
  int n_valid = 0;     // results with a GALT value (reason ok or ok_post_anchor)
  // Over the valid values; nullopt when n_valid == 0. std_s is the population standard deviation
  // (divisor n, numpy's default), as in the reference.
  std::optional<double> mean_s;
  std::optional<double> median_s;  // mean of the two middle values when n_valid is even
  std::optional<double> std_s;
  // Indexed by static_cast<int>(kinematics::GaltReason).
  std::array<int, kinematics::kGaltReasonCount> reason_counts{};

  int count(kinematics::GaltReason reason) const { return reason_counts[static_cast<std::size_t>(reason)]; }
};

// Summarises the GALT results of a cell's successful episodes; the reference computes GALT only
// for those, so the caller passes exactly them.
GaltSummary SummarizeGalt(const std::vector<kinematics::GaltResult>& successful_episodes);

// The summary as summary.json reports it: n_episodes, n_valid, mean_s, median_s, std_s (null when
// n_valid is 0) and reasons (reason -> count, the non-zero ones).
nlohmann::json GaltSummaryJson(const GaltSummary& summary);

}  // namespace tavis::batch::cell
