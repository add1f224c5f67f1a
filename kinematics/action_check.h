// Which canonical actions a step accepts. The hot loop never throws: an action that fails these
// checks ends its episode as invalid_action, naming the entry, its value and the reason, and the
// other episodes go on. The bounds are far outside anything a policy means (arms reach about
// 0.7 m from the hip frame), so they catch garbage, not ambitious targets.
#pragma once

#include "kinematics/action.h"

namespace tavis::kinematics {

// An IK target farther than this from the canonical frame's origin on any axis, m.
constexpr double kMaxTargetCoordinate = 10.0;
// Quaternion components beyond this magnitude are garbage (their norm would overflow), and a
// norm below kMinQuaternionNorm has no orientation to normalise.
constexpr double kMaxQuaternionComponent = 1e6;
constexpr double kMinQuaternionNorm = 1e-6;

struct ActionDefect {
  int entry = -1;           // index in the 19-D action; -1: none
  double value = 0.0;       // the entry's value
  const char* reason = "";  // static text: "not finite", "position beyond 10 m", ...

  bool found() const { return entry >= 0; }
};

// The first defect of `action`: a non-finite entry, an arm target coordinate beyond
// kMaxTargetCoordinate, or an arm quaternion that is zero or absurdly large (named by its first
// entry). Neck and gripper entries only need to be finite: they are clamped to their ranges.
ActionDefect FindActionDefect(const Action& action);

}  // namespace tavis::kinematics
