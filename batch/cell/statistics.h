// The statistics the records and tables report: success-rate intervals, and the spread (mean,
// median, standard deviation, a nearest-rank quantile) of a list of values such as GALT seconds.
// Written once here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tavis::batch::cell {

struct ProportionInterval {
  double low = 0.0;   // fraction in [0, 1]
  double high = 0.0;  // fraction in [0, 1]
};

// Wilson score interval for `successes` out of `trials` (z = 1.96 gives the 95% interval the
// paper reports). trials == 0 yields [0, 1].
ProportionInterval WilsonInterval(int64_t successes, int64_t trials, double z = 1.96);

// Mean, median (the mean of the two middle values when n is even) and population standard
// deviation (two passes, as numpy's std: the mean first, then the mean squared deviation).
struct Spread {
  std::size_t n = 0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;
};

// The spread of `values`, which must not be empty (std::invalid_argument).
Spread SpreadOf(std::vector<double> values);

// The median of `values`, which must not be empty (std::invalid_argument).
double Median(std::vector<double> values);

// The nearest-rank `fraction` quantile of `values` (0 < fraction <= 1): the smallest value with at
// least that fraction of them at or below it, one of the values; `values` must not be empty
// (std::invalid_argument).
double NearestRank(std::vector<double> values, double fraction);

// The q-quantile (q in [0, 1]) of `values` by linear interpolation between the order statistics
// at rank q (n - 1), numpy's default: Quantile(v, 0.5) is the median. `values` must not be empty
// (std::invalid_argument).
double Quantile(std::vector<double> values, double q);

}  // namespace tavis::batch::cell
