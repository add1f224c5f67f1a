// A task's stages: the steps toward success an episode is scored on besides success itself (did it
// look at the cue, reach the right object, grasp it, lift it?), so a failing policy's records say
// how far it got. Each task declares its stages in its ScenarioDef, in the order a successful
// episode passes them; StageProgress (stage_progress.h) follows one episode through them.
#pragma once

#include <string>
#include <vector>

namespace tavis::scenarios {

struct StageDef {
  enum class Kind {
    // The head camera's optical axis within max_angle_rad of the cue object's centre, beyond the
    // closest the neck's joint limits let it come (Reachy2's neck pitches 0.35 rad at most, so
    // its head cannot centre a card on the table).
    kCueFixated,
    // A hand's tool centre point within distance_m of the target's bounding box: the policy went
    // for the right object (a hand at the wrong side never reaches it).
    kTargetApproached,
    // A hand closing (gripper command > 0) with its jaws held open by more than the closed gap
    // plus kGripMargin (something between them), its tool centre point within distance_m of the
    // target's box.
    kTargetGrasped,
    // While grasped (as kTargetGrasped within 2 cm), the target moved distance_m in the success rule's direction (up
    // for a lift,
    // toward the robot for a pull-out) from the furthest-back place it has been in the episode,
    // or is past the success rule's threshold.
    kTargetRaised,
  };
  std::string name;  // the record's key, e.g. "target_grasped"
  Kind kind = Kind::kTargetApproached;
  std::string object;          // kCueFixated: the cue's model name
  double distance_m = 0.0;     // kTargetApproached, kTargetGrasped, kTargetRaised
  double max_angle_rad = 0.0;  // kCueFixated
};

// How far beyond their closed gap a closing hand's jaws must be held apart to hold something.
inline constexpr double kGripMargin = 0.005;
// How close a closing hand's tool centre point must be to the target's box for a grasp of it.
inline constexpr double kGraspReach = 0.02;

}  // namespace tavis::scenarios
