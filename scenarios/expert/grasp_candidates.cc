#include "scenarios/expert/grasp_candidates.h"

#include <cmath>

namespace tavis::scenarios::expert {

std::vector<GraspCandidate> TableGraspCandidates() {
  constexpr double kQuarter = M_PI / 2;
  return {
      {0.8, 0.0, 0.0},       {0.8, 0.0, M_PI},       {0.6, 0.0, 0.0},      {0.6, 0.0, M_PI},
      {1.0, 0.0, 0.0},       {1.0, 0.0, M_PI},       {0.8, kQuarter, 0.0}, {0.8, -kQuarter, 0.0},
      {0.8, kQuarter, M_PI}, {0.8, -kQuarter, M_PI}, {0.6, kQuarter, 0.0}, {0.6, -kQuarter, 0.0},
      {0.6, kQuarter, M_PI}, {0.6, -kQuarter, M_PI}, {1.0, kQuarter, 0.0}, {1.0, -kQuarter, 0.0},
  };
}

std::vector<GraspCandidate> TableAndSideGraspCandidates() {
  std::vector<GraspCandidate> candidates = TableGraspCandidates();
  for (const double tilt : {1.0, M_PI / 2 - 0.3, M_PI / 2}) {
    for (const double heading : {0.0, 0.35, -0.35, 0.7, -0.7}) {
      for (const double turn : {0.0, M_PI})
        candidates.push_back({tilt, heading, turn, /*along_hand=*/true, /*from_outside=*/true});
    }
  }
  return candidates;
}

std::vector<GraspCandidate> ShelfGraspCandidates() {
  const double level = M_PI / 2;
  std::vector<GraspCandidate> candidates;
  for (const double heading : {0.0, 0.25, -0.25, 0.5, -0.5, 0.75, -0.75}) {
    for (const double tilt : {level, level - 0.2, level + 0.2, level - 0.4}) {
      for (const double turn : {0.0, M_PI}) candidates.push_back({tilt, heading, turn, /*along_hand=*/true});
    }
  }
  return candidates;
}

}  // namespace tavis::scenarios::expert
