// The physics world's broad phase on plain arrays (no ODE types), so that tests can hold it
// against the test of every pair that it replaces.
//
// What a geom's collision category is, which categories it collides with and whether it has a
// body are fixed once the world is built; only the boxes and the enabled flags change from
// substep to substep. The pairs that can ever make contact are therefore listed once
// (CandidatePairs), and a substep tests only those: the static-static pairs, the robot's own
// pairs and the pairs whose categories do not collide are never looked at again.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace tavis::engine::internal {

// Collision categories: the robot does not collide with itself (reference: self-collisions off).
enum CategoryBits : unsigned long { kRobotBit = 1, kObjectBit = 2, kStaticBit = 4 };

// What the broad phase needs of a geom that does not change once the world is built.
struct BroadPhaseGeom {
  unsigned long category = 0;
  unsigned long collides_with = 0;
  bool has_body = false;  // geoms without one (static scene, kinematic objects) never meet each other
  bool is_plane = false;  // the ground: its box is unbounded (for ArmProximity)
};

// Axis-aligned boxes as ODE writes them (dGeomGetAABB): 6 numbers per geom, (min x, max x,
// min y, max y, min z, max z), geoms in creation order.
inline bool BoxesOverlap(const double* a, const double* b) {
  return !(a[0] > b[1] || b[0] > a[1] || a[2] > b[3] || b[2] > a[3] || a[4] > b[5] || b[4] > a[5]);
}

// The geom pairs of a world that may ever touch: i < j, the categories of one collide with the
// other, and at least one has a body; listed by i (rows in ascending i, each row's j ascending),
// the order in which the broad phase hands them to the narrow phase.
class CandidatePairs {
 public:
  explicit CandidatePairs(const std::vector<BroadPhaseGeom>& geoms);

  // Calls visit(i, j) for every candidate pair whose geoms are both enabled and whose boxes
  // overlap, in creation order (i ascending, then j): exactly the pairs, in the order, that the
  // test of every pair would find.
  template <class Visit>
  void ForEachOverlap(const double* aabbs, const uint8_t* enabled, Visit&& visit) const {
    for (std::size_t r = 0; r + 1 < row_start_.size(); ++r) {
      const int i = row_geom_[r];
      if (!enabled[i]) continue;
      const double* box_i = aabbs + 6 * i;
      for (int c = row_start_[r]; c < row_start_[r + 1]; ++c) {
        const int j = partners_[static_cast<std::size_t>(c)];
        if (enabled[j] && BoxesOverlap(box_i, aabbs + 6 * j)) visit(i, j);
      }
    }
  }

  std::size_t size() const { return partners_.size(); }

 private:
  std::vector<int> row_geom_;   // the i of each row that has partners
  std::vector<int> row_start_;  // (rows + 1) offsets into partners_
  std::vector<int> partners_;   // the j of each pair
};

}  // namespace tavis::engine::internal
