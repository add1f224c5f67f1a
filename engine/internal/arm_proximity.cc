#include "engine/internal/arm_proximity.h"

#include <algorithm>
#include <limits>

#include "kinematics/invariant.h"

namespace tavis::engine::internal {

ArmProximity::ArmProximity(const std::vector<BroadPhaseGeom>& geoms, const std::array<std::vector<int>, 2>& arm_geoms)
    : arm_geoms_(arm_geoms), support_(geoms.size(), Support::kUnknown) {
  for (std::size_t g = 0; g < geoms.size(); ++g) {
    // Near() takes the plane's side only as the second geom: the ground is static scene.
    TAVIS_INVARIANT(!geoms[g].is_plane || geoms[g].category == kStaticBit, "only the static ground is a plane");
    category_.push_back(geoms[g].category);
    is_plane_.push_back(geoms[g].is_plane ? 1 : 0);
    if (geoms[g].category & (kObjectBit | kStaticBit)) supports_.push_back(static_cast<int>(g));
  }
}

bool ArmProximity::Near(const double* a, const double* aabbs, int j) const {
  constexpr double m = kKinematicArmMargin;
  if (is_plane_[static_cast<std::size_t>(j)]) return a[4] < m;
  const double* b = aabbs + 6 * j;
  return !(a[0] > b[1] + m || b[0] > a[1] + m || a[2] > b[3] + m || b[2] > a[3] + m || a[4] > b[5] + m ||
           b[4] > a[5] + m);
}

bool ArmProximity::Supported(const double* aabbs, const uint8_t* enabled, int i) {
  Support& support = support_[static_cast<std::size_t>(i)];
  if (support == Support::kUnknown) {
    support = Support::kFree;
    for (const int j : supports_) {
      if (j == i || !enabled[j] || !Near(aabbs + 6 * i, aabbs, j)) continue;
      support = Support::kSupported;
      break;
    }
  }
  return support == Support::kSupported;
}

ArmMode ArmProximity::ModeOf(int side, const double* aabbs, const uint8_t* enabled) {
  const std::vector<int>& arm = arm_geoms_[static_cast<std::size_t>(side)];
  // The box around all the arm's boxes: a geom it is not near, no part of the arm is near (the
  // same comparisons, against bounds at least as far out). A NaN bound would compare otherwise,
  // so a box with one is not used.
  double arm_box[6] = {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                       std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                       std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  bool arm_box_usable = true;
  for (const int a : arm) {
    const double* box = aabbs + 6 * a;
    for (int k = 0; k < 6; k += 2) {
      arm_box[k] = std::min(arm_box[k], box[k]);
      arm_box[k + 1] = std::max(arm_box[k + 1], box[k + 1]);
      arm_box_usable = arm_box_usable && box[k] == box[k] && box[k + 1] == box[k + 1];
    }
  }
  ArmMode mode = ArmMode::kKinematic;
  for (const int j : supports_) {
    if (!enabled[j] || (arm_box_usable && !Near(arm_box, aabbs, j))) continue;
    if (std::none_of(arm.begin(), arm.end(), [&](int a) { return Near(aabbs + 6 * a, aabbs, j); })) continue;
    if (category_[static_cast<std::size_t>(j)] == kObjectBit && !Supported(aabbs, enabled, j)) {
      mode = ArmMode::kGrip;
      continue;
    }
    return ArmMode::kSimulated;
  }
  return mode;
}

std::array<ArmMode, 2> ArmProximity::Modes(const double* aabbs, const uint8_t* enabled) {
  std::fill(support_.begin(), support_.end(), Support::kUnknown);
  return {ModeOf(0, aabbs, enabled), ModeOf(1, aabbs, enabled)};
}

}  // namespace tavis::engine::internal
