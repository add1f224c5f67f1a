#include "scenarios/expert/ik_iteration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "kinematics/invariant.h"

namespace tavis::scenarios::expert {
namespace {

using ArmConfiguration = std::array<double, kinematics::kArmDof>;

// The planner iterates 150 steps; the history holds every configuration up to this many.
constexpr int kMaxSteps = 256;
// A configuration is looked for among this many before it: the cycles the planner's seeds fall
// into are a few steps long (2 to 30 measured), and a longer look-back costs every step.
constexpr int kCycleLookBack = 32;

// Bit patterns, not values: the step is a function of the bits (-0 and +0 are different inputs,
// a NaN equals itself), so only bit-equal configurations are known to repeat.
uint64_t Fingerprint(const ArmConfiguration& q) {
  uint64_t hash = 0x9e3779b97f4a7c15ull;
  for (const double value : q) {
    uint64_t bits = 0;
    std::memcpy(&bits, &value, sizeof(bits));
    hash = (hash ^ bits) * 0xff51afd7ed558ccdull;
    hash ^= hash >> 33;
  }
  return hash;
}

bool SameBits(const ArmConfiguration& a, const ArmConfiguration& b) {
  return std::memcmp(a.data(), b.data(), sizeof(ArmConfiguration)) == 0;
}

}  // namespace

IkIteration IterateIk(const kinematics::RobotModel& robot, kinematics::Side side, std::vector<double>& q,
                      const kinematics::PoseTarget& target, const std::vector<int>& arm_links,
                      std::vector<RigidTransform>& X_BL, int max_steps, double still_step, CycleShortcut shortcut) {
  TAVIS_INVARIANT(max_steps >= 0 && max_steps <= kMaxSteps, "IK iteration within its history");
  const std::array<int, kinematics::kArmDof>& joints = robot.arm(side).joints;
  // history[i]: the arm's joints before step i; fingerprints alongside, to compare cheaply.
  std::array<ArmConfiguration, kMaxSteps + 1> history;
  std::array<uint64_t, kMaxSteps + 1> fingerprints;
  IkIteration result;
  for (int i = 0; i < max_steps; ++i) {
    ArmConfiguration& now = history[static_cast<std::size_t>(i)];
    for (int k = 0; k < kinematics::kArmDof; ++k) now[k] = q[joints[k]];
    if (shortcut == CycleShortcut::kOn) {
      fingerprints[static_cast<std::size_t>(i)] = Fingerprint(now);
      for (int period = 1; period <= std::min(i, kCycleLookBack); ++period) {
        const std::size_t before = static_cast<std::size_t>(i - period);
        if (fingerprints[before] != fingerprints[static_cast<std::size_t>(i)] || !SameBits(history[before], now)) {
          continue;
        }
        // From step i - period on the configurations repeat with this period, so the one after
        // max_steps steps is the one (max_steps - i) mod period steps into the cycle.
        const ArmConfiguration& last = history[before + static_cast<std::size_t>((max_steps - i) % period)];
        for (int k = 0; k < kinematics::kArmDof; ++k) q[joints[k]] = last[k];
        kinematics::ComputeLinkPosesOf(robot, q.data(), arm_links, X_BL.data());
        result.cycle_found = true;
        return result;
      }
    }
    kinematics::ComputeLinkPosesOf(robot, q.data(), arm_links, X_BL.data());
    const auto next = kinematics::IkStep(robot, side, q.data(), X_BL.data(), target);
    ++result.steps;
    double change = 0.0;
    for (int k = 0; k < kinematics::kArmDof; ++k) {
      double& q_k = q[joints[k]];
      change = std::max(change, std::abs(next[k] - q_k));
      q_k = next[k];
    }
    if (change < still_step) break;  // a fixed point: further steps would not move the arm
  }
  kinematics::ComputeLinkPosesOf(robot, q.data(), arm_links, X_BL.data());
  return result;
}

}  // namespace tavis::scenarios::expert
