// The arm planner's kinematic IK iteration (arm_planner.h): the controller's IK step applied to
// its own result until the arm stops moving or the iterations run out.
#pragma once

#include <vector>

#include "kinematics/inverse_kinematics.h"

namespace tavis::scenarios::expert {

// Whether IterateIk may stop at a repeated configuration (below); kOff iterates every step, for
// tests that hold the shortcut against it.
enum class CycleShortcut { kOn, kOff };

struct IkIteration {
  int steps = 0;             // IK steps computed
  bool cycle_found = false;  // the arm's joints repeated, and the rest was read off the cycle
};

// Applies kinematics::IkStep to q's arm joints up to `max_steps` times (joint limits respected),
// stopping early once a step moves no joint by `still_step` or more; q ends at the last
// configuration. X_BL holds q's poses of the links the arm does not move; `arm_links`
// (kinematics::LinksMovedByArm) are recomputed at each step and hold q's poses at the end.
//
// Each step is a function of the arm's joints alone (the target and the other links are fixed),
// so once the joints repeat a configuration of p steps before, bit for bit, they go round that
// cycle of p configurations for good, none of whose steps stops the iteration (it did not stop
// before). With CycleShortcut::kOn the configuration after `max_steps` steps is then read off the
// cycle instead of computed: the same numbers, without the remaining steps.
IkIteration IterateIk(const kinematics::RobotModel& robot, kinematics::Side side, std::vector<double>& q,
                      const kinematics::PoseTarget& target, const std::vector<int>& arm_links,
                      std::vector<RigidTransform>& X_BL, int max_steps, double still_step,
                      CycleShortcut shortcut = CycleShortcut::kOn);

}  // namespace tavis::scenarios::expert
