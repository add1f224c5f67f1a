#include "scenarios/object_placement.h"

#include <algorithm>

namespace tavis::scenarios {

std::vector<Placement> SampleSeparatedPlacements(const PlacementRanges& ranges, int count, engine::RandomStream& rng) {
  constexpr int kMaxTries = 5000;
  std::vector<Placement> accepted;
  accepted.reserve(count);
  for (int object = 0; object < count; ++object) {
    for (int attempt = 0; attempt < kMaxTries; ++attempt) {
      Placement candidate;
      candidate.position.x() = rng.Uniform(ranges.x.low, ranges.x.high);
      candidate.position.y() = rng.Uniform(ranges.y.low, ranges.y.high);
      candidate.position.z() = rng.Uniform(ranges.z.low, ranges.z.high);
      rng.Uniform(ranges.roll.low, ranges.roll.high);
      rng.Uniform(ranges.pitch.low, ranges.pitch.high);
      candidate.yaw = rng.Uniform(ranges.yaw.low, ranges.yaw.high);
      bool separated = true;
      for (const Placement& other : accepted) {
        if (!((candidate.position - other.position).norm() > ranges.min_separation)) {
          separated = false;
          break;
        }
      }
      if (accepted.empty() || separated || attempt == kMaxTries - 1) {
        accepted.push_back(candidate);
        break;
      }
    }
  }
  return accepted;
}

void PlaceUpright(engine::BatchState& state, int env, int object, const Vec3& position, double yaw) {
  const Quat q = QuatFromYaw(yaw);
  const double values[engine::kObjectPoseSize] = {position.x(), position.y(), position.z(), q.w(), q.x(), q.y(), q.z()};
  std::copy(values, values + engine::kObjectPoseSize, state.object_pose_row(env, object));
  state.object_enabled_at(env, object) = 1;
}

}  // namespace tavis::scenarios
