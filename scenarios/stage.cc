#include "scenarios/scenario.h"

namespace tavis::scenarios {

std::vector<StageDef> PickStages(const SuccessRule& success, const std::string& cue) {
  std::vector<StageDef> stages;
  if (!cue.empty()) {
    StageDef fixated;
    fixated.name = "cue_fixated";
    fixated.kind = StageDef::Kind::kCueFixated;
    fixated.object = cue;
    // Beyond the best fixation the neck allows; at reset the cue sits about 1 rad off the axis.
    fixated.max_angle_rad = 0.15;
    stages.push_back(fixated);
  }
  StageDef approached;
  approached.name = "target_approached";
  approached.kind = StageDef::Kind::kTargetApproached;
  approached.distance_m = 0.05;
  stages.push_back(approached);
  StageDef grasped;
  grasped.name = "target_grasped";
  grasped.kind = StageDef::Kind::kTargetGrasped;
  grasped.distance_m = kGraspReach;
  stages.push_back(grasped);
  const bool pull_out = success.kind == SuccessRule::Kind::kPullOutPast;
  StageDef raised;
  raised.name = pull_out ? "target_pulled" : "target_lifted";
  raised.kind = StageDef::Kind::kTargetRaised;
  raised.distance_m = 0.03;
  stages.push_back(raised);
  return stages;
}

}  // namespace tavis::scenarios
