// What went wrong in an episode, besides how far it got (its stages): failure events detected from
// the state at every control tick, each kept with the control tick it first fired at. One detector
// per env slot, shown the same states as the slot's StageProgress (the state each action is
// chosen in, then the episode's last); it allocates nothing per tick. The events' definitions are
// in docs/events.md; in short:
//   wrong_object_touched   an object other than the target grasped, or moved 2 cm from where it settled
//   wrong_object_lifted    an object other than the target 3 cm above where it settled
//   target_dropped         the target, once lifted (pulled), out of every hand for 0.1 s (a lift: and
//                          fallen 2 cm from its highest since)
//   object_knocked_over    an object, not held, tilted more than 45 degrees from how it settled
//   object_out_of_workspace an object 10 cm below where it settled (off its table or shelf)
//   gripper_table_contact  a corner of a gripper's housing or pads inside a fixed part (table, shelf,
//                          screen) or below the floor
//   both_arms_moved        each hand's tool centre point 5 cm or more from where the episode began
//   opposite_arm_used      the hand on the other side than a target 10 cm or more off the midline within 5 cm of it
//   reach_before_cue       a hand within 5 cm of an object before the cue was fixated (a task with a cue
//                          stage and no go signal, head camera only: conditional-pick's card)
//   reach_before_go        the same before the task's go signal (wait-then-act's green light)
//   cue_never_fixated      the task's cue stage never reached (head camera only)
//   target_never_fixated   the target never within 0.15 rad of the head's optical axis beyond the best
//                          the neck allows, the cue_fixated rule (head camera only)
//   time_out_still         timed out with neither hand travelling 2 cm in the last second
//   time_out_moving        timed out with a hand travelling 2 cm or more in the last second
// A reach (opposite_arm_used, reach_before_*) is by a hand that has left its start by 2 cm.
// "Settled": an object's pose once it has been at rest (below 2 cm/s and 0.2 rad/s) for 0.1 s, as
// the scripted expert waits for it (objects are dropped onto their supports at the start), or 1 s
// into the episode at the latest; an object has no events before.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "kinematics/gripper_geometry.h"
#include "kinematics/pose.h"
#include "scenarios/scenario.h"

namespace tavis::batch::cell {

enum class FailureEvent : uint8_t {
  kWrongObjectTouched = 0,
  kWrongObjectLifted,
  kTargetDropped,
  kObjectKnockedOver,
  kObjectOutOfWorkspace,
  kGripperTableContact,
  kBothArmsMoved,
  kOppositeArmUsed,
  kReachBeforeCue,
  kReachBeforeGo,
  kCueNeverFixated,
  kTargetNeverFixated,
  kTimeOutStill,
  kTimeOutMoving,
};
inline constexpr int kNumFailureEvents = 14;

// The record's name of an event ("target_dropped").
const char* ToString(FailureEvent event);
// The event named `text`; false for another text.
bool ParseFailureEvent(const std::string& text, FailureEvent* event);
// Every event, in declared order.
std::vector<FailureEvent> AllFailureEvents();

// The events that can fire in a cell of the task: the cue and gaze events need a head that moves
// (not under a fixed view, which zeroes the neck), reach_before_cue a cue stage and no go signal,
// reach_before_go a go signal. In declared order.
std::vector<FailureEvent> ApplicableEvents(const scenarios::ScenarioDef& scenario, bool head_moves);
// The same by the task's name; throws std::invalid_argument for an unknown task.
std::vector<FailureEvent> ApplicableEvents(const std::string& task, bool head_moves);

// An event of an episode and the control tick it first fired at.
struct EventFired {
  FailureEvent event = FailureEvent::kWrongObjectTouched;
  int first_tick = 0;

  bool operator==(const EventFired& other) const { return event == other.event && first_tick == other.first_tick; }
};

// The world poses of both hands at one control tick: the IK link frame (the gripper's boxes
// hang from it) and the tool centre point, by kinematics::Index(side).
struct HandFrames {
  std::array<RigidTransform, 2> X_W_ik;
  std::array<Vec3, 2> tcp;
};
HandFrames ComputeHandFrames(const kinematics::RobotModel& robot, const double* q);

class FailureEventDetector {
 public:
  // Throws std::invalid_argument naming a cue a stage declares that the world does not hold.
  FailureEventDetector(const scenarios::ScenarioDef& scenario, const engine::WorldModel& model, bool head_moves);

  // A new episode: nothing seen yet.
  void Start();
  // The env's state at control tick state.control_step[env], with its hands' frames and the
  // stages' first ticks so far (StageProgress::first_ticks, already shown this state).
  void Observe(const engine::BatchState& state, int env, const HandFrames& hands, const std::vector<int>& stage_ticks);
  // After Observe of the episode's last state: the events that fired, in declared order, with
  // those decided by how it ended. `tcp_log`: each hand's tool centre point at every tick shown.
  std::vector<EventFired> Finish(const engine::BatchState& state, int env, const std::vector<int>& stage_ticks,
                                 const std::array<std::vector<Vec3>, 2>& tcp_log) const;

 private:
  struct ObjectWatch {
    bool watched = false;  // dynamic and enabled in this episode
    bool settled = false;
    int rest_ticks = 0;
    Vec3 position = Vec3::Zero();  // where it settled
    Vec3 up = Vec3::UnitZ();       // its z axis then
  };

  void Fire(FailureEvent event, int tick);
  // The hand's tool centre point has left where it was at the episode's first tick (2 cm).
  bool LeftStart(const HandFrames& hands, std::size_t hand) const;
  bool Fired(FailureEvent event) const { return first_ticks_[static_cast<std::size_t>(event)] >= 0; }
  void WatchObjects(const engine::BatchState& state, int env, const HandFrames& hands, int tick);
  // A closing hand holding something with its tool centre point within kGraspReach of
  // `object`'s box (the target_grasped stage's rule, for any object).
  bool Held(const engine::BatchState& state, int env, const HandFrames& hands, int object) const;
  double HandToObject(const engine::BatchState& state, int env, const Vec3& tcp, int object) const;
  bool GripperTouchesFixedPart(const engine::BatchState& state, int env, const HandFrames& hands) const;
  void WatchReach(const engine::BatchState& state, int env, const HandFrames& hands,
                  const std::vector<int>& stage_ticks, int tick);

  const scenarios::ScenarioDef& scenario_;
  const engine::WorldModel& model_;
  const bool head_moves_;
  int cue_stage_ = -1;     // index of the cue_fixated stage, -1 if none
  int raised_stage_ = -1;  // index of the target_lifted / target_pulled stage, -1 if none
  double fixation_angle_rad_;
  const kinematics::GripperGeometry gripper_;
  std::array<int, kNumFailureEvents> first_ticks_{};
  std::vector<ObjectWatch> objects_;  // per object of the world
  bool started_ = false;
  int start_tick_ = 0;
  std::array<Vec3, 2> start_tcp_{};
  std::array<bool, 2> hand_moved_{};
  int target_side_ = -1;  // kinematics::Index of the target's side, -1 near the midline or unknown
  bool target_fixated_ = false;
  int drop_start_tick_ = -1;  // the tick the lifted target left every hand, -1 while held
  double highest_since_lift_ = 0.0;
};

}  // namespace tavis::batch::cell
