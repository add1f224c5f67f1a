// The physics world's broad phase (CandidatePairs) and kinematic-arm proximity (ArmProximity)
// against the loops over every geom pair that they replaced, on random scenes: the same pairs in
// the same order, and the same arm modes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "engine/internal/arm_proximity.h"
#include "engine/internal/broad_phase.h"

namespace tavis::engine::internal {
namespace {

// A random world of the physics world's kinds of geoms, in its creation order: robot links
// (static ones without a body, arm links with), two grippers' housing and pads, dynamic
// objects, kinematic objects and static parts (no body), and the ground plane last.
struct Scene {
  std::vector<BroadPhaseGeom> geoms;
  std::array<std::vector<int>, 2> arm_geoms;
  std::vector<double> aabbs;
  std::vector<uint8_t> enabled;
};

Scene RandomScene(std::mt19937& rng) {
  Scene scene;
  std::uniform_int_distribution<int> count(0, 4);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto add = [&](unsigned long category, unsigned long collides_with, bool has_body, bool is_plane = false) {
    scene.geoms.push_back({category, collides_with, has_body, is_plane});
    return static_cast<int>(scene.geoms.size()) - 1;
  };
  for (int i = count(rng); i > 0; --i) add(kRobotBit, kObjectBit | kStaticBit, false);  // torso
  for (int side = 0; side < 2; ++side) {
    for (int i = 1 + count(rng); i > 0; --i) {
      scene.arm_geoms[side].push_back(add(kRobotBit, kObjectBit | kStaticBit, true));
    }
  }
  for (int i = count(rng); i > 0; --i) add(kObjectBit, kRobotBit | kObjectBit | kStaticBit, true);
  for (int i = count(rng) / 2; i > 0; --i) add(kStaticBit, kRobotBit | kObjectBit, false);  // kinematic objects
  for (int i = count(rng) / 2; i > 0; --i) add(kStaticBit, kRobotBit | kObjectBit, false);  // static parts
  add(kStaticBit, kRobotBit | kObjectBit, false, true);                                     // the ground
  // Boxes of 1-10 cm half size in a 40 cm cube just above the ground: many pairs overlap, many
  // come within the kinematic-arm margin, many do not.
  for (const BroadPhaseGeom& geom : scene.geoms) {
    const double inf = std::numeric_limits<double>::infinity();
    if (geom.is_plane) {
      scene.aabbs.insert(scene.aabbs.end(), {-inf, inf, -inf, inf, -inf, 0.0});
    } else {
      for (int axis = 0; axis < 3; ++axis) {
        const double centre = 0.4 * unit(rng) + (axis == 2 ? 0.02 : 0.0);
        const double half = 0.01 + 0.09 * unit(rng);
        scene.aabbs.push_back(centre - half);
        scene.aabbs.push_back(centre + half);
      }
    }
    scene.enabled.push_back(unit(rng) < 0.85 ? 1 : 0);
  }
  // Robot geoms are never disabled.
  for (std::size_t g = 0; g < scene.geoms.size(); ++g) {
    if (scene.geoms[g].category == kRobotBit) scene.enabled[g] = 1;
  }
  return scene;
}

// The broad phase as it was: every pair in creation order, through the enabled flags, the
// category bits, the boxes, and Collide's return for two geoms without a body.
std::vector<std::pair<int, int>> EveryPairTested(const Scene& scene) {
  std::vector<std::pair<int, int>> pairs;
  const int n = static_cast<int>(scene.geoms.size());
  for (int i = 0; i < n; ++i) {
    if (!scene.enabled[i]) continue;
    for (int j = i + 1; j < n; ++j) {
      if (!scene.enabled[j]) continue;
      const BroadPhaseGeom& a = scene.geoms[i];
      const BroadPhaseGeom& b = scene.geoms[j];
      if (!(a.category & b.collides_with) && !(b.category & a.collides_with)) continue;
      const double* box_a = &scene.aabbs[6 * i];
      const double* box_b = &scene.aabbs[6 * j];
      if (box_a[0] > box_b[1] || box_b[0] > box_a[1] || box_a[2] > box_b[3] || box_b[2] > box_a[3] ||
          box_a[4] > box_b[5] || box_b[4] > box_a[5]) {
        continue;
      }
      if (!a.has_body && !b.has_body) continue;
      pairs.emplace_back(i, j);
    }
  }
  return pairs;
}

// The arm modes as they were decided: Near over every pair of geoms.
bool NearAsBefore(const Scene& scene, int i, int j) {
  const double* box_a = &scene.aabbs[6 * i];
  const double* box_b = &scene.aabbs[6 * j];
  constexpr double m = kKinematicArmMargin;
  if (scene.geoms[j].is_plane) return box_a[4] < m;
  if (scene.geoms[i].is_plane) return box_b[4] < m;
  return !(box_a[0] > box_b[1] + m || box_b[0] > box_a[1] + m || box_a[2] > box_b[3] + m || box_b[2] > box_a[3] + m ||
           box_a[4] > box_b[5] + m || box_b[4] > box_a[5] + m);
}

std::array<ArmMode, 2> ArmModesAsBefore(const Scene& scene) {
  const int n = static_cast<int>(scene.geoms.size());
  std::vector<uint8_t> supported(scene.geoms.size(), 0);
  for (int i = 0; i < n; ++i) {
    if (scene.geoms[i].category != kObjectBit || !scene.enabled[i]) continue;
    for (int j = 0; j < n && !supported[i]; ++j) {
      if (j == i || (scene.geoms[j].category & (kObjectBit | kStaticBit)) == 0) continue;
      if (scene.enabled[j] && NearAsBefore(scene, i, j)) supported[i] = 1;
    }
  }
  std::array<ArmMode, 2> modes{};
  for (int side = 0; side < 2; ++side) {
    ArmMode mode = ArmMode::kKinematic;
    for (int a : scene.arm_geoms[side]) {
      for (int j = 0; j < n && mode != ArmMode::kSimulated; ++j) {
        const unsigned long category = scene.geoms[j].category;
        if ((category & (kObjectBit | kStaticBit)) == 0 || !scene.enabled[j] || !NearAsBefore(scene, a, j)) continue;
        mode = (category == kObjectBit && !supported[j]) ? ArmMode::kGrip : ArmMode::kSimulated;
      }
    }
    modes[side] = mode;
  }
  return modes;
}

TEST(CandidatePairs, FindTheSamePairsInTheSameOrderAsTestingEveryPair) {
  std::mt19937 rng(20261126);
  std::size_t pairs_found = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const Scene scene = RandomScene(rng);
    const CandidatePairs candidates(scene.geoms);
    std::vector<std::pair<int, int>> found;
    candidates.ForEachOverlap(scene.aabbs.data(), scene.enabled.data(),
                              [&](int i, int j) { found.emplace_back(i, j); });
    ASSERT_EQ(found, EveryPairTested(scene)) << "trial " << trial;
    pairs_found += found.size();
  }
  EXPECT_GT(pairs_found, 1000u);  // the scenes are crowded enough to test the order
}

TEST(CandidatePairs, NeverListTwoGeomsWithoutABodyOrCategoriesThatDoNotCollide) {
  const std::vector<BroadPhaseGeom> geoms = {
      {kRobotBit, kObjectBit | kStaticBit, false},                 // torso
      {kRobotBit, kObjectBit | kStaticBit, true},                  // arm link
      {kRobotBit, kObjectBit | kStaticBit, true},                  // another arm link
      {kObjectBit, kRobotBit | kObjectBit | kStaticBit, true},     // object
      {kStaticBit, kRobotBit | kObjectBit, false},                 // table
      {kStaticBit, kRobotBit | kObjectBit, false, /*plane*/ true}  // ground
  };
  const CandidatePairs candidates(geoms);
  // Every box overlaps every other, every geom is enabled: the candidates themselves come out.
  const std::vector<double> aabbs(6 * geoms.size(), 0.0);
  const std::vector<uint8_t> enabled(geoms.size(), 1);
  std::vector<std::pair<int, int>> found;
  candidates.ForEachOverlap(aabbs.data(), enabled.data(), [&](int i, int j) { found.emplace_back(i, j); });
  const std::vector<std::pair<int, int>> expected = {{0, 3}, {1, 3}, {1, 4}, {1, 5}, {2, 3},
                                                     {2, 4}, {2, 5}, {3, 4}, {3, 5}};
  EXPECT_EQ(found, expected);
  EXPECT_EQ(candidates.size(), expected.size());
}

TEST(ArmProximity, GivesTheModesOfTheTestOverEveryPair) {
  std::mt19937 rng(7);
  std::array<int, 3> seen{};  // how often each mode came out, so that every branch is exercised
  for (int trial = 0; trial < 2000; ++trial) {
    const Scene scene = RandomScene(rng);
    ArmProximity proximity(scene.geoms, scene.arm_geoms);
    const std::array<ArmMode, 2> modes = proximity.Modes(scene.aabbs.data(), scene.enabled.data());
    const std::array<ArmMode, 2> expected = ArmModesAsBefore(scene);
    ASSERT_EQ(modes[0], expected[0]) << "trial " << trial;
    ASSERT_EQ(modes[1], expected[1]) << "trial " << trial;
    for (ArmMode mode : modes) ++seen[static_cast<std::size_t>(mode)];
    // Called again on the same boxes (its per-substep memory is reset), and after moving the
    // arms far away: the same as the old test of the moved scene.
    EXPECT_EQ(proximity.Modes(scene.aabbs.data(), scene.enabled.data()), expected);
    Scene moved = scene;
    for (int a : scene.arm_geoms[0]) {
      for (int k = 0; k < 6; ++k) moved.aabbs[6 * a + k] += (k < 4 ? 5.0 : 1.0);
    }
    EXPECT_EQ(proximity.Modes(moved.aabbs.data(), moved.enabled.data()), ArmModesAsBefore(moved));
  }
  for (int mode = 0; mode < 3; ++mode) EXPECT_GT(seen[static_cast<std::size_t>(mode)], 100) << "mode " << mode;
}

TEST(ArmProximity, AnArmBoxWithANanBoundStillComparesAsEveryPairDid) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    Scene scene = RandomScene(rng);
    // A NaN compares false: the old test took such a box as near anything not the ground.
    scene.aabbs[6 * scene.arm_geoms[1].front() + static_cast<std::size_t>(trial % 6)] =
        std::numeric_limits<double>::quiet_NaN();
    ArmProximity proximity(scene.geoms, scene.arm_geoms);
    ASSERT_EQ(proximity.Modes(scene.aabbs.data(), scene.enabled.data()), ArmModesAsBefore(scene)) << "trial " << trial;
  }
}

}  // namespace
}  // namespace tavis::engine::internal
