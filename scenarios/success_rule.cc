#include "scenarios/scenario.h"

namespace tavis::scenarios {

SuccessRule LiftAbove(double height_m) {
  SuccessRule rule;
  rule.kind = SuccessRule::Kind::kLiftAbove;
  rule.threshold_m = height_m;
  return rule;
}

SuccessRule PullOutPast(double x_m) {
  SuccessRule rule;
  rule.kind = SuccessRule::Kind::kPullOutPast;
  rule.threshold_m = x_m;
  return rule;
}

bool ScenarioDef::Succeeded(const engine::BatchState& state, int env) const {
  if (success.after_go != nullptr && !success.after_go(state, env)) return false;
  const int target = state.target(env);
  const Vec3 position = state.ObjectPosition(env, target);
  const bool placed = success.kind == SuccessRule::Kind::kLiftAbove ? position.z() > success.threshold_m
                                                                    : position.x() < success.threshold_m;
  return placed && state.ObjectLinearVelocity(env, target).norm() < success.max_speed_mps;
}

}  // namespace tavis::scenarios
