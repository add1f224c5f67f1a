// Object placement: IsaacLab's randomize_object_pose rejection sampler (reference 4.3), on the
// episode's stream, and writing an upright object pose.
#pragma once

#include <vector>

#include "engine/batch_state.h"
#include "engine/random.h"
#include "kinematics/pose.h"

namespace tavis::scenarios {

struct Range {
  double low = 0.0;
  double high = 0.0;
};

struct PlacementRanges {
  Range x, y, z, roll, pitch, yaw;
  double min_separation = 0.0;
};

// Ranges of x and y only (the others zero), for tasks that place by x and y.
inline PlacementRanges XyRanges(Range x, Range y) {
  PlacementRanges ranges;
  ranges.x = x;
  ranges.y = y;
  return ranges;
}

struct Placement {
  Vec3 position = Vec3::Zero();
  double yaw = 0.0;  // roll and pitch are drawn (to keep the draw order) but our primitives are z-up
};

// For each of `count` objects in order, up to 5000 tries: draw x, y, z, roll, pitch, yaw (all
// six, even for constant ranges); accept the first object, the last try, or a pose whose 3-D
// distance to every accepted one is strictly greater than min_separation.
std::vector<Placement> SampleSeparatedPlacements(const PlacementRanges& ranges, int count, engine::RandomStream& rng);

// Writes an object's pose, standing on its base turned `yaw` about the vertical (the
// reference's place_object; our primitives are modelled z-up), and enables it.
void PlaceUpright(engine::BatchState& state, int env, int object, const Vec3& position, double yaw);

}  // namespace tavis::scenarios
