#include "batch/report/paired_statistics.h"

#include <algorithm>
#include <cmath>

namespace tavis::batch::report {

double McNemarExactP(int64_t first_only, int64_t second_only) {
  const int64_t n = first_only + second_only;
  if (n == 0) return 1.0;
  const int64_t k = std::min(first_only, second_only);
  // Sum of binomial probabilities in log space: C(n, i) / 2^n overflows a double past n ~ 1000.
  const double log_half_n = static_cast<double>(n) * std::log(0.5);
  const double log_n_factorial = std::lgamma(static_cast<double>(n) + 1.0);
  double tail = 0.0;
  for (int64_t i = 0; i <= k; ++i) {
    tail += std::exp(log_n_factorial - std::lgamma(static_cast<double>(i) + 1.0) -
                     std::lgamma(static_cast<double>(n - i) + 1.0) + log_half_n);
  }
  return std::min(1.0, 2.0 * tail);
}

}  // namespace tavis::batch::report
