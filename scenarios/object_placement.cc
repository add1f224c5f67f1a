#include "scenarios/object_placement.h"

namespace tavis::scenarios {

std::vector<Placement> SampleSeparatedPlacements(const PlacementRanges& ranges, int count,
                                                 engine::RandomStream& rng) {
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

}  // namespace tavis::scenarios
