#include "kinematics/action_check.h"

#include <cmath>

namespace tavis::kinematics {

ActionDefect FindActionDefect(const Action& action) {
  for (int i = 0; i < action::kSize; ++i) {
    if (!std::isfinite(action[i])) return {i, action[i], "not finite"};
  }
  for (Side side : kSides) {
    const int p = action::kArmPosition[Index(side)];
    for (int k = p; k < p + 3; ++k) {
      if (std::abs(action[k]) > kMaxTargetCoordinate) return {k, action[k], "IK target coordinate beyond 10 m"};
    }
    const int r = action::kArmQuaternion[Index(side)];
    double norm_squared = 0.0;
    for (int k = r; k < r + 4; ++k) {
      if (std::abs(action[k]) > kMaxQuaternionComponent) return {k, action[k], "quaternion component beyond 1e6"};
      norm_squared += action[k] * action[k];
    }
    if (std::sqrt(norm_squared) < kMinQuaternionNorm) return {r, action[r], "zero quaternion (norm below 1e-6)"};
  }
  return {};
}

}  // namespace tavis::kinematics
