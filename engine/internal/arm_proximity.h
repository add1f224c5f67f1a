// Which arms of a physics world follow their servos outside the solver this substep (kinematic
// arms, docs/fidelity.md), decided from the geoms' boxes on plain arrays (no ODE types), so that
// tests can hold it against the loops over every geom pair that it replaces.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "engine/internal/broad_phase.h"

namespace tavis::engine::internal {

// How an arm moves in a substep (docs/fidelity.md, "kinematic arms"). kSimulated: links and
// fingers are bodies in the solver. kGrip: the links follow their servo kinematically, the
// fingers are simulated against the moving palm (a held object away from everything else).
// kKinematic: links and fingers follow their servos (nothing near the arm).
enum class ArmMode { kSimulated, kGrip, kKinematic };

// An arm none of whose geoms comes within this distance of an object or the static scene
// follows its servo kinematically: its bodies leave the LCP (docs/fidelity.md). The margin
// exceeds a substep's motion of any arm point (a 5 rad/s joint swinging the 0.80 m from GR1T2's
// shoulder to past its pads: 2.2 cm at 180 Hz; PhysicsWorld.TheKinematicArmMarginExceedsASubstepsSwingOfEitherArm),
// so every contact begins with the arm already simulated.
constexpr double kKinematicArmMargin = 0.03;  // m

// Which mode each arm takes in a substep, from the geoms' boxes. An object near the static scene
// or another object is supported: an arm near it, or near the static scene, is simulated, so
// that what it presses on pushes back through its effort-limited motors. An arm near only
// unsupported objects (what it holds in the air) grips them with simulated fingers.
// "Near": the boxes come within kKinematicArmMargin of each other; the ground plane, whose box
// is unbounded, is near a box whose bottom is lower than the margin.
class ArmProximity {
 public:
  // `arm_geoms`: the geoms of each arm's bodies (links, housing, pads).
  ArmProximity(const std::vector<BroadPhaseGeom>& geoms, const std::array<std::vector<int>, 2>& arm_geoms);

  // `aabbs` and `enabled` as for CandidatePairs::ForEachOverlap.
  std::array<ArmMode, 2> Modes(const double* aabbs, const uint8_t* enabled);

 private:
  enum class Support : uint8_t { kUnknown, kSupported, kFree };

  bool Near(const double* box, const double* aabbs, int j) const;
  // Whether enabled object geom i is near another enabled object or the static scene; worked out
  // once per substep, for the objects an arm comes near.
  bool Supported(const double* aabbs, const uint8_t* enabled, int i);
  ArmMode ModeOf(int side, const double* aabbs, const uint8_t* enabled);

  std::vector<unsigned long> category_;
  std::vector<uint8_t> is_plane_;
  std::vector<int> supports_;  // geoms whose category has kObjectBit or kStaticBit, ascending
  std::array<std::vector<int>, 2> arm_geoms_;
  std::vector<Support> support_;  // per geom, this substep
};

}  // namespace tavis::engine::internal
