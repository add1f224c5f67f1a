// The hand orientations the pick expert tries for a grasp, as catalogues per kind of task.
#pragma once

#include <vector>

namespace tavis::scenarios::expert {

// A grasp orientation: the approach (the hand's -Z) tilted `tilt` rad from straight down toward
// the heading (the object's folded yaw plus heading_offset), the hand then turned `turn` about
// its approach axis. The fingers stay horizontal. The pre-grasp lies straight above the grasp
// (coming down onto a table top), or with `along_hand` back along the hand's approach axis
// (reaching in sideways: into a shelf, around a screen). With `from_outside` the heading is not
// the object's but the reaching arm's inward direction (the left arm heads -y): the hand comes
// in from beside the robot's centre line, around whatever stands in front of the object.
struct GraspCandidate {
  double tilt;
  double heading_offset;
  double turn;
  bool along_hand = false;
  bool from_outside = false;
};

// Table grasps, in the order tried: tilted 0.6-1.0 rad forward, heading in quarter turns (a box
// is symmetric under them), the hand in either half turn (the gripper nearly is).
std::vector<GraspCandidate> TableGraspCandidates();
// The table grasps, then the hand reaching in along itself from the arm's own side, level or
// tilted down, at headings up to 0.7 rad off straight inward (around a screen).
std::vector<GraspCandidate> TableAndSideGraspCandidates();
// Shelf grasps: the hand level (tilt pi/2) or nearly, reaching in straight or turned up to 0.75
// rad, so that the jaws can meet a turned object's faces.
std::vector<GraspCandidate> ShelfGraspCandidates();

}  // namespace tavis::scenarios::expert
