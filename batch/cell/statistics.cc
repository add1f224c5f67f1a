#include "batch/cell/statistics.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <utility>

namespace tavis::batch::cell {

ProportionInterval WilsonInterval(int64_t successes, int64_t trials, double z) {
  if (trials <= 0) return {0.0, 1.0};
  const double n = static_cast<double>(trials);
  const double p = static_cast<double>(successes) / n;
  const double z2 = z * z;
  const double centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
  const double half = z / (1.0 + z2 / n) * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

double Median(std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("the median of no values");
  std::sort(values.begin(), values.end());
  const std::size_t middle = values.size() / 2;
  return values.size() % 2 == 1 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
}

double NearestRank(std::vector<double> values, double fraction) {
  if (values.empty()) throw std::invalid_argument("a quantile of no values");
  std::sort(values.begin(), values.end());
  const double rank = std::ceil(fraction * static_cast<double>(values.size()));
  return values[static_cast<std::size_t>(std::clamp(rank, 1.0, static_cast<double>(values.size()))) - 1];
}

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) throw std::invalid_argument("a quantile of no values");
  std::sort(values.begin(), values.end());
  const double rank = q * static_cast<double>(values.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(rank));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (rank - static_cast<double>(below)) * (values[above] - values[below]);
}

Spread SpreadOf(std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("the spread of no values");
  Spread spread;
  spread.n = values.size();
  const double n = static_cast<double>(values.size());
  spread.mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
  double squared_deviations = 0.0;
  for (const double value : values) squared_deviations += (value - spread.mean) * (value - spread.mean);
  spread.std = std::sqrt(squared_deviations / n);
  spread.median = Median(std::move(values));
  return spread;
}

}  // namespace tavis::batch::cell
