// A privileged scripted expert that picks one object and lifts it, looking before it reaches
// (the human teleoperator's timing that GALT measures): it first reads the task's cue if there is
// one (fixates a card, watches a light until it turns green), then turns the head to fixate the object
// and lets the neck settle, then plans a grasp the arm can reach and moves the nearer arm above
// the object, descends, closes and lifts. The approach is a straight hand line when the
// controller can track it (checked kinematically beforehand), otherwise a straight joint-space
// path (arm_planner.h); descending and lifting are straight hand lines. All are speed-limited at
// the control rate; the commanded action is the hand pose along the way, as a teleoperator's is.
// A grasp that closes on nothing, or loses the object on the way out, is retried as a
// teleoperator would: open, back out to the pre-grasp, plan again from what is there now with
// another hand orientation.
#pragma once

#include <optional>

#include <array>
#include <vector>

#include "scenarios/scenario.h"

namespace tavis::scenarios {

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

struct PickExpertSettings {
  // The expert picks the episode's target (TaskVars::target). A cue to read before looking at
  // it (cue card, signal light), or -1: the expert fixates it for cue_look_s once the neck has
  // settled, and with wait_for_go keeps watching until the task says go (the light turns green).
  int cue_object = -1;
  double cue_look_s = 0.5;
  bool wait_for_go = false;
  double grasp_height = 0.000;    // m: pad centre above the object's centre at the grasp
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

class PickExpert : public Expert {
 public:
  PickExpert(const engine::WorldModel& model, int num_envs, PickExpertSettings settings);
  void Reset(const engine::WorldModel& model, const engine::BatchState& state, int env) override;
  void Act(const engine::WorldModel& model, const engine::BatchState& state, int env,
           kinematics::Action& action) override;
  Gaze gaze(const engine::BatchState& state, int env) const override;

  enum class Phase { kWatchCue, kLook, kSettle, kPeek, kApproach, kDescend, kClose, kWithdraw, kLift, kRetreat, kGiveUp };
  Phase phase(int env) const { return memory_[env].phase; }
  // Grasps started in the env's episode so far (retries after a miss count).
  int attempts(int env) const { return memory_[env].attempts; }

 private:
  using ArmJoints = std::array<double, kinematics::kArmDof>;

  // A straight joint-space segment, traversed at a speed set by its length.
  struct Segment {
    ArmJoints from{};
    ArmJoints to{};
    double progress = 0.0;  // 0..1
    double rate = 0.0;      // progress per control tick
  };

  struct EnvMemory {
    Phase phase = Phase::kLook;
    std::size_t scan_index = 0;  // scan points fixated so far
    int phase_start_step = 0;
    kinematics::Side side = kinematics::Side::kLeft;
    std::array<RigidTransform, 2> hand_command;  // IK link targets, canonical frame
    std::array<double, 3> neck_command{};
    std::array<double, 3> neck_goal{};
    Vec3 fixated_point = Vec3::Zero();
    std::array<double, 2> gripper_command{-1.0, -1.0};
    std::vector<double> q_plan;  // full joint vector used to evaluate the arm path
    ArmJoints q_pre{}, q_grasp{}, q_withdraw{}, q_lift{};
    bool withdraws = false;  // an along-hand grasp: withdraw before lifting
    bool lifts = false;
    std::array<Segment, 2> segments;  // per arm
    bool peeked = false;
    bool peek_done = false;  // the wrists have held their peek poses, or could not take them
    bool cartesian_approach = false;
    bool arm_clear = false;  // the plan keeps the arm clear of the scene's fixed obstacles
    std::size_t candidate = 0;                  // grasp candidate of the current plan
    std::vector<std::size_t> failed_candidates;  // candidates whose grasp missed or dropped the object
    int attempts = 0;
  };

  void Enter(EnvMemory& m, Phase phase, int step) const;
  // Largest distance of the neck command from its fixation goal, rad.
  static double NeckError(const EnvMemory& m);
  void UpdateNeck(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m) const;
  bool PlanGrasp(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m) const;
  // True if the reaching hand's gripper has closed on nothing (fully shut).
  bool HandIsEmpty(const engine::WorldModel& model, const engine::BatchState& state, int env, const EnvMemory& m) const;
  // Gives up the current grasp: opens the hand and backs out to the pre-grasp (kRetreat).
  void StartRetreat(EnvMemory& m, int step) const;
  void StartSegment(const engine::WorldModel& model, EnvMemory& m, kinematics::Side side, const ArmJoints& from,
                    const ArmJoints& to, double cartesian_speed) const;
  // Advances the arm's segment and writes its commanded hand pose; true when it has ended.
  bool FollowSegment(const engine::WorldModel& model, EnvMemory& m, kinematics::Side side) const;
  // Plans both arms' joint-space paths to their peek poses (an arm that cannot reach its pose
  // keeps still); false if neither can peek.
  bool StartPeek(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m) const;
  // Plans the grasp from the current state and starts the approach (or gives up).
  void StartReach(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m,
                  int step) const;
  // True if the controller can follow a straight hand line from the current pose to the pre-grasp.
  bool ApproachLineIsTrackable(const engine::WorldModel& model, const engine::BatchState& state, int env,
                               EnvMemory& m) const;
  // Moves the commanded hand straight toward the pose of arm configuration `goal`; true there.
  bool MoveHandToward(const engine::WorldModel& model, EnvMemory& m, const ArmJoints& goal, double speed) const;

  PickExpertSettings settings_;
  std::vector<EnvMemory> memory_;
};

}  // namespace tavis::scenarios
