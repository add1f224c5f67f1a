// The pick expert's configuration: what a task sets to adapt the scripted pick to its scene (a cue
// to read first, grasp orientations, wrist peeks, the reaching arm) and the teleoperator's pace.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "kinematics/robot_model.h"
#include "scenarios/expert/expert_mode.h"
#include "scenarios/expert/grasp_candidates.h"

namespace tavis::scenarios::expert {

struct PickExpertSettings {
  // Gaze-first: the head reads the cue and fixates the target before the hands move (the
  // settings below). Head-still: the neck command stays at its reset pose, the scan points, cue
  // looks and head settling are skipped; the hands wait only for the scene to come to rest and,
  // with a go signal, for it (wrist peeks are hand motions and are kept).
  ExpertMode mode = ExpertMode::kGazeFirst;
  // The expert picks the episode's target (TaskVars::target). A cue to read before looking at
  // it (cue card, signal light), or -1: the expert fixates it for cue_look_s once the neck has
  // settled, and with a go signal keeps watching until the task gives it (the light turns green).
  int cue_object = -1;
  double cue_look_s = 0.5;
  // Optional: the task's go signal (wait-then-act's green light); the hands wait for it.
  bool (*go_signal)(const engine::BatchState& state, int env) = nullptr;
  double grasp_height = 0.000;  // m: pad centre above the object's centre at the grasp
  // The surface the object stands on extends under the whole open hand (a table), so its housing
  // must clear it too; a shelf board ends just in front of the object, below the housing.
  bool support_under_hand = true;
  double approach_distance = 0.18;  // m: the pre-grasp pads' centre from the grasp
  // After closing, a hand that reached in along itself first withdraws the way it came, rising
  // off the support; then the pads lift to this world height (success: 1.2), if the task lifts
  // (a shelf's object only has to come out).
  std::optional<double> lift_to_z = 1.27;
  std::vector<GraspCandidate> grasp_candidates = TableGraspCandidates();
  // Heading reference of the grasp candidates: the object's faces (nullptr), or a direction the
  // task gives (reaching straight into a shelf, into a box through its open side).
  double (*reach_heading)(const engine::BatchState& state, int env) = nullptr;
  // World points the head fixates in turn before the cue and the target (scanning shelf rows).
  std::vector<Vec3> scan_points;
  // Optional wrist peeks after the head has settled on the target: the IK-link poses (world)
  // each arm's hand, and with it its wrist camera, takes to look before the reach (peeking-box:
  // one at each side of the box; blocked-clutter-pick-cube: one hand above the cube, the other
  // where it is); both are held for peek_s, then the grasp is planned from there.
  std::array<RigidTransform, 2> (*peek_poses)(const engine::WorldModel& model, const engine::BatchState& state,
                                              int env) = nullptr;
  double peek_s = 0.5;
  // The arm that reaches: the one on the object's side (nullptr), or the task's choice
  // (peeking-box: the arm at the open side).
  kinematics::Side (*reach_side)(const engine::BatchState& state, int env) = nullptr;
  double hand_speed = 0.36;       // m/s, approach
  double descend_speed = 0.20;    // m/s, from the pre-grasp down to the grasp
  double slow_hand_speed = 0.12;  // m/s, lifting the held object
  double joint_speed = 2.0;       // rad/s, the fastest arm joint
  double neck_gain = 5.0;         // 1/s
  double neck_max_speed = 1.5;    // rad/s
  double settle_s = 0.3;          // head still before the hand moves
  double close_s = 0.6;           // gripper closing time
  double clearance = 0.005;       // m: preferred gap between the open hand and other objects
  int max_attempts = 3;           // grasps tried before the expert gives up
};

}  // namespace tavis::scenarios::expert
