// Success-rate statistics reported for every evaluation cell.
#pragma once

#include <cstdint>

namespace tavis::batch {

struct ProportionInterval {
  double low = 0.0;   // fraction in [0, 1]
  double high = 0.0;  // fraction in [0, 1]
};

// Wilson score interval for `successes` out of `trials` (z = 1.96 gives the 95% interval the
// paper reports). trials == 0 yields [0, 1].
ProportionInterval WilsonInterval(int64_t successes, int64_t trials, double z = 1.96);

}  // namespace tavis::batch
