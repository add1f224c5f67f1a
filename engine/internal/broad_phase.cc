#include "engine/internal/broad_phase.h"

namespace tavis::engine::internal {

CandidatePairs::CandidatePairs(const std::vector<BroadPhaseGeom>& geoms) {
  row_start_.push_back(0);
  for (std::size_t i = 0; i < geoms.size(); ++i) {
    const BroadPhaseGeom& a = geoms[i];
    const std::size_t row_size_before = partners_.size();
    for (std::size_t j = i + 1; j < geoms.size(); ++j) {
      const BroadPhaseGeom& b = geoms[j];
      if (!(a.category & b.collides_with) && !(b.category & a.collides_with)) continue;
      // Two geoms without a body make no contact joint (nothing to attach it to).
      if (!a.has_body && !b.has_body) continue;
      partners_.push_back(static_cast<int>(j));
    }
    if (partners_.size() == row_size_before) continue;
    row_geom_.push_back(static_cast<int>(i));
    row_start_.push_back(static_cast<int>(partners_.size()));
  }
}

}  // namespace tavis::engine::internal
