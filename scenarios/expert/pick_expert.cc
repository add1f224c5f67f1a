#include "scenarios/expert/pick_expert.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "kinematics/servo.h"
#include "scenarios/expert/arm_clearance.h"
#include "scenarios/expert/arm_planner.h"
#include "scenarios/expert/gaze.h"

namespace tavis::scenarios::expert {
namespace {

// m: a gripper this close to its fully shut gap holds nothing (the thinnest object is 21 mm).
constexpr double kEmptyGripMargin = 0.005;

// Head-still: the objects are dropped onto their supports at the episode's start (reference 2)
// and a grasp is planned from where they lie, so the hands wait until every object has been
// still this long (a bounce's apex is still for under a tick), or at most kMaxSceneWaitS.
constexpr double kRestS = 0.1;
constexpr double kMaxSceneWaitS = 1.0;
constexpr double kRestLinearSpeed = 0.02;  // m/s
constexpr double kRestAngularSpeed = 0.2;  // rad/s

using kinematics::Side;

void WriteArm(kinematics::Action& action, Side side, const RigidTransform& X_CanonicalHand) {
  const int p = kinematics::action::kArmPosition[kinematics::Index(side)];
  const int r = kinematics::action::kArmQuaternion[kinematics::Index(side)];
  const Quat q(X_CanonicalHand.linear());
  for (int k = 0; k < 3; ++k) action[p + k] = X_CanonicalHand.translation()[k];
  action[r] = q.w();
  action[r + 1] = q.x();
  action[r + 2] = q.y();
  action[r + 3] = q.z();
}

}  // namespace

PickExpert::PickExpert(const engine::WorldModel&, int num_envs, PickExpertSettings settings)
    : settings_(settings), memory_(num_envs) {}

void PickExpert::Enter(EnvMemory& m, Phase phase, int step) const {
  m.phase = phase;
  m.phase_start_step = step;
}

void PickExpert::Reset(const engine::WorldModel& model, const engine::BatchState& state, int env) {
  const kinematics::RobotModel& robot = model.robot;
  EnvMemory& m = memory_[env];
  m = EnvMemory();
  m.hands.Reset(robot, state.q_row(env));
  for (int i = 0; i < kinematics::kNeckDof; ++i) m.neck_command[i] = state.q_row(env)[robot.neck_joints[i]];
  m.neck_goal = m.neck_command;
  m.fixated_point = Vec3::Constant(1e9);
  m.failed_candidates.assign(settings_.grasp_candidates.size(), false);
  // The episode's clock starts here, not at control tick 0: under ood-init-pose the arms' warm-up
  // has already run 0.5 s of ticks, which a phase timed from tick 0 (the cue's look) counted as done.
  m.phase_start_step = state.control_step[env];
  if (head_still()) {
    m.phase = Phase::kWaitToAct;
  } else {
    m.phase = settings_.cue_object >= 0 || !settings_.scan_points.empty() ? Phase::kWatchCue : Phase::kLook;
  }
}

Expert::Gaze PickExpert::gaze(const engine::BatchState& state, int env) const {
  const EnvMemory& m = memory_[env];
  Gaze gaze;
  if (head_still()) return gaze;  // the head fixates nothing
  if (m.phase == Phase::kWatchCue) {
    if (m.scan_index < settings_.scan_points.size()) return gaze;
    gaze.object = settings_.cue_object;
  } else {
    gaze.object = state.target(env);
  }
  // kLook ends the tick the neck settles; a task that peeks reads the target with its wrists.
  const bool head_still = m.phase != Phase::kLook && NeckError(m) < 0.01;
  gaze.settled = head_still && (m.phase == Phase::kWatchCue || !settings_.peek_poses || m.peek_done);
  return gaze;
}

double PickExpert::NeckError(const EnvMemory& m) {
  double error = 0.0;
  for (int i = 0; i < kinematics::kNeckDof; ++i) error = std::max(error, std::abs(m.neck_goal[i] - m.neck_command[i]));
  return error;
}

void PickExpert::UpdateNeck(const engine::WorldModel& model, const engine::BatchState& state, int env,
                            EnvMemory& m) const {
  Vec3 p_object;
  if (m.phase == Phase::kWatchCue && m.scan_index < settings_.scan_points.size()) {
    p_object = settings_.scan_points[m.scan_index];
  } else if (m.phase == Phase::kWatchCue) {
    p_object = state.ObjectPosition(env, settings_.cue_object);
  } else {
    p_object = state.ObjectPosition(env, state.target(env));
  }
  // Re-aim only when the object has moved noticeably: the solve is the expert's costliest step.
  // The command is the teleoperator's head turning to the object, past the neck's limits where
  // the object lies beyond them (Reachy2 looking down at the table): the robot clamps it.
  if ((p_object - m.fixated_point).norm() > 0.01) {
    m.neck_goal = FixationNeckAngles(model.robot, state.q_row(env), p_object, NeckLimits::kIgnore);
    m.fixated_point = p_object;
  }
  const double dt = 1.0 / model.physics.control_hz;
  for (int i = 0; i < kinematics::kNeckDof; ++i) {
    const double rate =
        kinematics::ServoVelocity(settings_.neck_gain, m.neck_goal[i] - m.neck_command[i], settings_.neck_max_speed);
    m.neck_command[i] += rate * dt;
  }
}

bool PickExpert::SceneAtRest(const engine::WorldModel& model, const engine::BatchState& state, int env) {
  for (int object = 0; object < model.num_objects(); ++object) {
    if (!state.object_enabled_at(env, object)) continue;
    if (model.objects[static_cast<std::size_t>(object)].motion == engine::ObjectMotion::kKinematic) continue;
    const double* v = state.object_velocity_row(env, object);
    if (Vec3(v[0], v[1], v[2]).norm() >= kRestLinearSpeed || Vec3(v[3], v[4], v[5]).norm() >= kRestAngularSpeed)
      return false;
  }
  return true;
}

void PickExpert::StartHands(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m,
                            int step) const {
  if (settings_.peek_poses && !m.peeked) {
    m.peeked = true;
    if (StartPeek(model, state, env, m)) {
      Enter(m, Phase::kPeek, step);
      return;
    }
    m.peek_done = true;
  }
  StartReach(model, state, env, m, step);
}

bool PickExpert::StartPeek(const engine::WorldModel& model, const engine::BatchState& state, int env,
                           EnvMemory& m) const {
  const kinematics::RobotModel& robot = model.robot;
  const std::array<RigidTransform, 2> peeks = settings_.peek_poses(model, state, env);
  const ArmObstacles obstacles(model, state, env, kArmClearance);
  const std::vector<double> q_now(state.q_row(env), state.q_row(env) + robot.num_joints());
  bool any = false;
  for (Side side : kinematics::kSides) {
    const RigidTransform& X_W_ik = peeks[kinematics::Index(side)];
    const kinematics::PoseTarget target{X_W_ik.translation() - robot.root_world, Quat(X_W_ik.linear())};
    const auto q_peek = SolveArmConfiguration(robot, side, q_now, target, &obstacles, &q_now);
    const ArmJoints from = ArmOf(robot, side, q_now.data());
    any = any || q_peek.has_value();
    // A wrist that cannot look there keeps still.
    const ArmJoints to = q_peek ? ArmOf(robot, side, q_peek->data()) : from;
    m.hands.StartSegment(model, side, from, to, settings_.joint_speed, settings_.hand_speed);
  }
  return any;
}

void PickExpert::StartReach(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m,
                            int step) const {
  ++m.attempts;
  m.side = ReachSide(settings_, state, env);
  if (m.attempts == 1) m.reach_start = ArmOf(model.robot, m.side, state.q_row(env));
  const std::optional<GraspPlan> plan = PlanGrasp(model, state, env, settings_, m.side, m.failed_candidates);
  if (!plan) {
    Enter(m, Phase::kGiveUp, step);
    return;
  }
  m.grasp = *plan;
  m.hands.StartSegment(model, m.side, ArmOf(model.robot, m.side, state.q_row(env)), m.grasp.pre, settings_.joint_speed,
                       settings_.hand_speed);
  m.cartesian_approach = ApproachLineIsTrackable(model, state, env, m);
  Enter(m, Phase::kApproach, step);
}

bool PickExpert::HandIsEmpty(const engine::WorldModel& model, const engine::BatchState& state, int env,
                             const EnvMemory& m) const {
  const double gap = state.gripper_gap_row(env)[kinematics::Index(m.side)];
  return gap <= model.robot.gripper.closed_gap + kEmptyGripMargin;
}

void PickExpert::StartRetreat(EnvMemory& m, int step) const {
  m.failed_candidates[m.grasp.candidate] = true;
  Enter(m, Phase::kRetreat, step);
}

void PickExpert::NoticeTargetMove(const engine::BatchState& state, int env, EnvMemory& m, int step) const {
  if (state.task[env].target_move_tick < 0 || m.saw_target_move) return;
  m.saw_target_move = true;
  switch (m.phase) {
    case Phase::kApproach:  // on its way: it turns back from where it is
    case Phase::kDescend:   // at or past the pre-grasp: back out the way it came first
    case Phase::kClose:
      m.back_out = m.phase != Phase::kApproach;
      ++m.replans;
      Enter(m, Phase::kReplan, step);
      break;
    case Phase::kSettle: Enter(m, Phase::kLook, step); break;
    default: break;  // no plan yet (it will be made where the target is now), or already holding it
  }
}

void PickExpert::BackOutToReplan(const engine::WorldModel& model, const engine::BatchState& state, int env,
                                 EnvMemory& m, int step) const {
  // The hand opens and backs out, and the arm goes back the way it came to where the first reach
  // started, while the head turns to the target's new place (UpdateNeck); then the look, the
  // settling and a new plan from there, as before the first reach.
  m.gripper_command[kinematics::Index(m.side)] = -1.0;
  if (m.back_out && !m.returning && !m.hands.MoveToward(model, m.side, m.grasp.pre, settings_.hand_speed)) return;
  if (!m.returning) {
    m.returning = true;
    m.hands.StartSegment(model, m.side, ArmOf(model.robot, m.side, state.q_row(env)), m.reach_start,
                         settings_.joint_speed, settings_.hand_speed);
  }
  if (!m.hands.FollowSegment(model.robot, m.side)) return;
  m.returning = false;
  if (head_still()) {
    StartReach(model, state, env, m, step);
  } else {
    Enter(m, Phase::kLook, step);
  }
}

bool PickExpert::ApproachLineIsTrackable(const engine::WorldModel& model, const engine::BatchState& state, int env,
                                         EnvMemory& m) const {
  const kinematics::RobotModel& robot = model.robot;
  const RigidTransform goal = m.hands.PoseAt(robot, m.side, m.grasp.pre);
  const RigidTransform start = m.hands.command(m.side);
  // MoveToward's line at hand speed, rehearsed over the same number of ticks.
  const int ticks = std::max(1, static_cast<int>((goal.translation() - start.translation()).norm() /
                                                 settings_.hand_speed * model.physics.control_hz));
  const std::vector<double> q_now(state.q_row(env), state.q_row(env) + robot.num_joints());
  const ArmObstacles obstacles(model, state, env, kArmClearance);
  return CanTrackStraightPath(robot, m.side, q_now, {robot.CanonicalToBase(goal.translation()), Quat(goal.linear())},
                              ticks, m.grasp.arm_clear ? &obstacles : nullptr);
}

// long: the phase machine is one switch, so that each phase's exit reads beside its entry and the
// order of the phases is the order of the cases; each case is short, the hard parts are functions.
void PickExpert::Act(const engine::WorldModel& model, const engine::BatchState& state, int env,
                     kinematics::Action& action) {
  EnvMemory& m = memory_[env];
  const int step = state.control_step[env];
  const double elapsed = (step - m.phase_start_step) / model.physics.control_hz;
  if (!head_still()) UpdateNeck(model, state, env, m);
  NoticeTargetMove(state, env, m, step);

  switch (m.phase) {
    case Phase::kWatchCue: {
      // Each scan point, then the cue, is looked at for cue_look_s once the neck has settled.
      if (NeckError(m) >= 0.01) m.phase_start_step = step;
      if (elapsed < settings_.cue_look_s) break;
      if (m.scan_index < settings_.scan_points.size()) {
        ++m.scan_index;
        m.phase_start_step = step;
        if (m.scan_index < settings_.scan_points.size() || settings_.cue_object >= 0) break;
      }
      const bool go = settings_.go_signal == nullptr || settings_.go_signal(state, env);
      if (go) Enter(m, Phase::kLook, step);
      break;
    }
    case Phase::kLook: {
      if (NeckError(m) < 0.01) Enter(m, Phase::kSettle, step);
      break;
    }
    case Phase::kSettle:
      if (elapsed < settings_.settle_s) break;
      StartHands(model, state, env, m, step);
      break;
    case Phase::kWaitToAct: {
      // The clock counts the scene's still time; the go signal is the task's own wait.
      if (!SceneAtRest(model, state, env)) m.phase_start_step = step;
      const double still_s = (step - m.phase_start_step) / model.physics.control_hz;
      const bool scene_ready = still_s >= kRestS || step >= kMaxSceneWaitS * model.physics.control_hz;
      const bool go = settings_.go_signal == nullptr || settings_.go_signal(state, env);
      if (scene_ready && go) StartHands(model, state, env, m, step);
      break;
    }
    case Phase::kPeek: {
      // Both hands go to their peek poses; the clock for peek_s starts when both have arrived.
      bool arrived = true;
      for (Side side : kinematics::kSides) arrived = m.hands.FollowSegment(model.robot, side) && arrived;
      if (!arrived) m.phase_start_step = step;
      m.peek_done = arrived;
      if (arrived && elapsed >= settings_.peek_s) StartReach(model, state, env, m, step);
      break;
    }
    case Phase::kApproach: {
      const bool arrived = m.cartesian_approach ? m.hands.MoveToward(model, m.side, m.grasp.pre, settings_.hand_speed)
                                                : m.hands.FollowSegment(model.robot, m.side);
      if (arrived) Enter(m, Phase::kDescend, step);
      break;
    }
    case Phase::kDescend:
      if (m.hands.MoveToward(model, m.side, m.grasp.grasp, settings_.descend_speed)) Enter(m, Phase::kClose, step);
      break;
    case Phase::kClose:
      m.gripper_command[kinematics::Index(m.side)] = 1.0;
      if (elapsed < settings_.close_s) break;
      if (HandIsEmpty(model, state, env, m)) {
        StartRetreat(m, step);
      } else {
        Enter(m, m.grasp.withdraws ? Phase::kWithdraw : Phase::kLift, step);
      }
      break;
    case Phase::kWithdraw:
      if (HandIsEmpty(model, state, env, m)) {
        StartRetreat(m, step);
      } else if (m.hands.MoveToward(model, m.side, m.grasp.withdraw, settings_.slow_hand_speed)) {
        Enter(m, Phase::kLift, step);
      }
      break;
    case Phase::kLift:
      if (HandIsEmpty(model, state, env, m)) {
        StartRetreat(m, step);
      } else if (settings_.lift_to_z) {
        m.hands.MoveToward(model, m.side, m.grasp.lift, settings_.slow_hand_speed);
      }
      break;
    case Phase::kRetreat:
      // The hand opens where it is (moving closed fingers through the object would push it),
      // then backs out to the failed plan's pre-grasp, and a new plan starts from there.
      m.gripper_command[kinematics::Index(m.side)] = -1.0;
      if (elapsed < settings_.close_s || !m.hands.MoveToward(model, m.side, m.grasp.pre, settings_.hand_speed)) break;
      if (m.attempts - m.replans < settings_.max_attempts) {
        StartReach(model, state, env, m, step);
      } else {
        Enter(m, Phase::kGiveUp, step);
      }
      break;
    case Phase::kReplan: BackOutToReplan(model, state, env, m, step); break;
    case Phase::kGiveUp: break;
  }

  for (Side side : kinematics::kSides) WriteArm(action, side, m.hands.command(side));
  action[kinematics::action::kNeckRoll] = m.neck_command[0];
  action[kinematics::action::kNeckPitch] = m.neck_command[1];
  action[kinematics::action::kNeckYaw] = m.neck_command[2];
  for (Side side : kinematics::kSides) {
    action[kinematics::action::kGripper[kinematics::Index(side)]] = m.gripper_command[kinematics::Index(side)];
  }
}

}  // namespace tavis::scenarios::expert
