#include "batch/cell/failure_events.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "kinematics/forward_kinematics.h"
#include "kinematics/gripper_geometry.h"
#include "kinematics/robot_buffers.h"
#include "scenarios/expert/gaze.h"
#include "scenarios/registry.h"

namespace tavis::batch::cell {
namespace {

constexpr std::array<const char*, kNumFailureEvents> kNames = {
    "wrong_object_touched",    "wrong_object_lifted",   "target_dropped",    "object_knocked_over",
    "object_out_of_workspace", "gripper_table_contact", "both_arms_moved",   "opposite_arm_used",
    "reach_before_cue",        "reach_before_go",       "cue_never_fixated", "target_never_fixated",
    "time_out_still",          "time_out_moving",
};

// Settling, as the scripted expert waits for the scene (scenarios/expert/pick_expert.cc).
constexpr double kRestLinearSpeed = 0.02;  // m/s
constexpr double kRestAngularSpeed = 0.2;  // rad/s
constexpr double kRestS = 0.1;
constexpr double kMaxSettleS = 1.0;

constexpr double kMovedM = 0.02;              // wrong_object_touched: pushed this far
constexpr double kLiftedM = 0.03;             // wrong_object_lifted, as the lift stage's 3 cm
constexpr double kKnockedOverRad = M_PI / 4;  // object_knocked_over
constexpr double kFallenM = 0.10;             // object_out_of_workspace
constexpr double kDroppedS = 0.1;             // target_dropped: out of every hand this long
constexpr double kContactMarginM = 0.0;       // gripper_table_contact: a corner inside the part
constexpr double kHandMovedM = 0.05;          // both_arms_moved
constexpr double kReachM = 0.05;              // a reach: the target_approached stage's distance
// ... by a hand that has left its start: Reachy2's resting hand can stand within 5 cm of an object.
constexpr double kLeftStartM = 0.02;
constexpr double kDroppedFallM = 0.02;   // target_dropped (a lift): fallen this far from its highest since lifted
constexpr double kSideM = 0.10;          // opposite_arm_used: a target this far off the midline has a side
constexpr double kTimeOutWindowS = 1.0;  // time_out_still / time_out_moving: the last second
constexpr double kTimeOutMovingM = 0.02;
constexpr double kFixationAngleRad = 0.15;  // target_never_fixated, as PickStages' cue_fixated

bool HasCueStage(const scenarios::ScenarioDef& scenario) {
  return std::any_of(scenario.stages.begin(), scenario.stages.end(), [](const scenarios::StageDef& stage) {
    return stage.kind == scenarios::StageDef::Kind::kCueFixated;
  });
}

// Whether `point` lies within `margin` of the box of `half` extents at X_WB.
bool NearBox(const Vec3& point, const RigidTransform& X_WB, const Vec3& half, double margin) {
  const Vec3 local = X_WB.inverse() * point;
  return (local.cwiseAbs() - half).maxCoeff() <= margin;
}

}  // namespace

const char* ToString(FailureEvent event) { return kNames[static_cast<std::size_t>(event)]; }

bool ParseFailureEvent(const std::string& text, FailureEvent* event) {
  for (int i = 0; i < kNumFailureEvents; ++i) {
    if (text != kNames[static_cast<std::size_t>(i)]) continue;
    *event = static_cast<FailureEvent>(i);
    return true;
  }
  return false;
}

std::vector<FailureEvent> AllFailureEvents() {
  std::vector<FailureEvent> events;
  for (int i = 0; i < kNumFailureEvents; ++i) events.push_back(static_cast<FailureEvent>(i));
  return events;
}

std::vector<FailureEvent> ApplicableEvents(const scenarios::ScenarioDef& scenario, bool head_moves) {
  const bool cue = HasCueStage(scenario);
  const bool go = scenario.success.after_go != nullptr;
  std::vector<FailureEvent> events;
  for (FailureEvent event : AllFailureEvents()) {
    switch (event) {
      case FailureEvent::kReachBeforeCue:
        if (!cue || go || !head_moves) continue;
        break;
      case FailureEvent::kReachBeforeGo:
        if (!go) continue;
        break;
      case FailureEvent::kCueNeverFixated:
        if (!cue || !head_moves) continue;
        break;
      case FailureEvent::kTargetNeverFixated:
        if (!head_moves) continue;
        break;
      default: break;
    }
    events.push_back(event);
  }
  return events;
}

std::vector<FailureEvent> ApplicableEvents(const std::string& task, bool head_moves) {
  return ApplicableEvents(scenarios::FindScenario(task), head_moves);
}

HandFrames ComputeHandFrames(const kinematics::RobotModel& robot, const double* q) {
  CheckFitsRobotBuffers(robot);
  HandFrames hands;
  LinkPoses X_BL;
  for (const kinematics::Side side : kinematics::kSides) {
    const int link = robot.arm(side).ik_link;
    kinematics::ComputeLinkPoseChain(robot, q, link, X_BL.data());
    const int s = kinematics::Index(side);
    hands.X_W_ik[static_cast<std::size_t>(s)] =
        Eigen::Translation3d(robot.root_world) * X_BL[static_cast<std::size_t>(link)];
    hands.tcp[static_cast<std::size_t>(s)] = hands.X_W_ik[static_cast<std::size_t>(s)] * robot.gripper.tcp;
  }
  return hands;
}

FailureEventDetector::FailureEventDetector(const scenarios::ScenarioDef& scenario, const engine::WorldModel& model,
                                           bool head_moves)
    : scenario_(scenario),
      model_(model),
      head_moves_(head_moves),
      fixation_angle_rad_(kFixationAngleRad),
      gripper_(model.robot.gripper),
      objects_(model.objects.size()) {
  CheckFitsRobotBuffers(model.robot);
  for (std::size_t i = 0; i < scenario.stages.size(); ++i) {
    const scenarios::StageDef& stage = scenario.stages[i];
    if (stage.kind == scenarios::StageDef::Kind::kCueFixated) cue_stage_ = static_cast<int>(i);
    if (stage.kind == scenarios::StageDef::Kind::kTargetRaised) raised_stage_ = static_cast<int>(i);
  }
  Start();
}

void FailureEventDetector::Start() {
  first_ticks_.fill(-1);
  std::fill(objects_.begin(), objects_.end(), ObjectWatch{});
  started_ = false;
  hand_moved_ = {false, false};
  target_side_ = -1;
  target_fixated_ = false;
  drop_start_tick_ = -1;
  highest_since_lift_ = -std::numeric_limits<double>::infinity();
}

bool FailureEventDetector::LeftStart(const HandFrames& hands, std::size_t hand) const {
  return (hands.tcp[hand] - start_tcp_[hand]).norm() >= kLeftStartM;
}

void FailureEventDetector::Fire(FailureEvent event, int tick) {
  int& first = first_ticks_[static_cast<std::size_t>(event)];
  if (first < 0) first = tick;
}

double FailureEventDetector::HandToObject(const engine::BatchState& state, int env, const Vec3& tcp, int object) const {
  const Vec3 half = BoundingHalfSize(model_.objects[static_cast<std::size_t>(object)].shape);
  const Vec3 local = state.ObjectOrientation(env, object).conjugate() * (tcp - state.ObjectPosition(env, object));
  return (local.cwiseAbs() - half).cwiseMax(0.0).norm();
}

bool FailureEventDetector::Held(const engine::BatchState& state, int env, const HandFrames& hands, int object) const {
  for (const kinematics::Side side : kinematics::kSides) {
    const int hand = kinematics::Index(side);
    const bool closing = state.gripper_command_row(env)[hand] > 0.0;
    const bool holding = state.gripper_gap_row(env)[hand] > model_.robot.gripper.closed_gap + scenarios::kGripMargin;
    if (closing && holding &&
        HandToObject(state, env, hands.tcp[static_cast<std::size_t>(hand)], object) <= scenarios::kGraspReach)
      return true;
  }
  return false;
}

void FailureEventDetector::WatchObjects(const engine::BatchState& state, int env, const HandFrames& hands, int tick) {
  const int rest_ticks = static_cast<int>(std::lround(kRestS * model_.physics.control_hz));
  const int settle_by = start_tick_ + static_cast<int>(std::lround(kMaxSettleS * model_.physics.control_hz));
  const int target = state.target(env);
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    ObjectWatch& watch = objects_[i];
    if (!watch.watched) continue;
    const int object = static_cast<int>(i);
    const Vec3 position = state.ObjectPosition(env, object);
    const Vec3 up = state.ObjectOrientation(env, object) * Vec3::UnitZ();
    if (!watch.settled) {
      const double* v = state.object_velocity_row(env, object);
      const bool at_rest = Vec3(v[0], v[1], v[2]).norm() < kRestLinearSpeed &&
                           Vec3(v[3], v[4], v[5]).norm() < kRestAngularSpeed && tick > start_tick_;
      watch.rest_ticks = at_rest ? watch.rest_ticks + 1 : 0;
      if (watch.rest_ticks < rest_ticks && tick < settle_by) continue;
      watch.settled = true;
      watch.position = position;
      watch.up = up;
      continue;
    }
    const bool held = Held(state, env, hands, object);
    if (object != target) {
      if (held || (position - watch.position).norm() >= kMovedM) Fire(FailureEvent::kWrongObjectTouched, tick);
      if (position.z() - watch.position.z() >= kLiftedM) Fire(FailureEvent::kWrongObjectLifted, tick);
    }
    if (!held && std::acos(std::clamp(up.dot(watch.up), -1.0, 1.0)) > kKnockedOverRad)
      Fire(FailureEvent::kObjectKnockedOver, tick);
    if (watch.position.z() - position.z() >= kFallenM) Fire(FailureEvent::kObjectOutOfWorkspace, tick);
  }
}

bool FailureEventDetector::GripperTouchesFixedPart(const engine::BatchState& state, int env,
                                                   const HandFrames& hands) const {
  const kinematics::GripperGeometry& gripper = gripper_;
  for (const kinematics::Side side : kinematics::kSides) {
    const int hand = kinematics::Index(side);
    const RigidTransform& X_W_ik = hands.X_W_ik[static_cast<std::size_t>(hand)];
    const double hand_gap = state.gripper_gap_row(env)[hand];
    const std::array<std::pair<RigidTransform, Vec3>, 3> boxes = {{
        {X_W_ik * gripper.X_IkHousing(), 0.5 * gripper.spec().housing_size},
        {X_W_ik * gripper.X_IkPad(kinematics::kJawSigns[0], hand_gap), 0.5 * gripper.spec().pad_size},
        {X_W_ik * gripper.X_IkPad(kinematics::kJawSigns[1], hand_gap), 0.5 * gripper.spec().pad_size},
    }};
    for (const auto& [X_WB, half] : boxes) {
      for (int corner = 0; corner < 8; ++corner) {
        const Vec3 sign((corner & 1) ? 1.0 : -1.0, (corner & 2) ? 1.0 : -1.0, (corner & 4) ? 1.0 : -1.0);
        const Vec3 point = X_WB * half.cwiseProduct(sign);
        if (point.z() <= kContactMarginM) return true;  // the floor
        for (const engine::StaticPart& part : model_.static_parts) {
          if (part.collides && NearBox(point, part.X_WS, BoundingHalfSize(part.shape), kContactMarginM)) return true;
        }
      }
    }
  }
  return false;
}

void FailureEventDetector::WatchReach(const engine::BatchState& state, int env, const HandFrames& hands,
                                      const std::vector<int>& stage_ticks, int tick) {
  const bool go_rule = scenario_.success.after_go != nullptr;
  const bool cue_rule = !go_rule && cue_stage_ >= 0 && head_moves_;
  if (!go_rule && !cue_rule) return;
  const bool allowed =
      go_rule ? scenario_.success.after_go(state, env) : stage_ticks[static_cast<std::size_t>(cue_stage_)] >= 0;
  if (allowed) return;
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    if (!objects_[i].watched) continue;
    for (std::size_t hand = 0; hand < 2; ++hand) {
      if (!LeftStart(hands, hand)) continue;
      if (HandToObject(state, env, hands.tcp[hand], static_cast<int>(i)) > kReachM) continue;
      Fire(go_rule ? FailureEvent::kReachBeforeGo : FailureEvent::kReachBeforeCue, tick);
      return;
    }
  }
}

void FailureEventDetector::Observe(const engine::BatchState& state, int env, const HandFrames& hands,
                                   const std::vector<int>& stage_ticks) {
  const int tick = state.control_step[env];
  const int target = state.target(env);
  if (!started_) {
    started_ = true;
    start_tick_ = tick;
    start_tcp_ = hands.tcp;
    for (std::size_t i = 0; i < objects_.size(); ++i) {
      objects_[i].watched = model_.objects[i].motion == engine::ObjectMotion::kDynamic &&
                            state.object_enabled_at(env, static_cast<int>(i)) != 0;
    }
    const double y = state.ObjectPosition(env, target).y() - model_.robot.root_world.y();
    target_side_ = y >= kSideM    ? kinematics::Index(kinematics::Side::kLeft)
                   : y <= -kSideM ? kinematics::Index(kinematics::Side::kRight)
                                  : -1;
  }
  WatchObjects(state, env, hands, tick);
  if (GripperTouchesFixedPart(state, env, hands)) Fire(FailureEvent::kGripperTableContact, tick);
  for (std::size_t hand = 0; hand < 2; ++hand) {
    if ((hands.tcp[hand] - start_tcp_[hand]).norm() >= kHandMovedM) hand_moved_[hand] = true;
  }
  if (hand_moved_[0] && hand_moved_[1]) Fire(FailureEvent::kBothArmsMoved, tick);
  if (target_side_ >= 0) {
    const int opposite = 1 - target_side_;
    if (LeftStart(hands, static_cast<std::size_t>(opposite)) &&
        HandToObject(state, env, hands.tcp[static_cast<std::size_t>(opposite)], target) <= kReachM)
      Fire(FailureEvent::kOppositeArmUsed, tick);
  }
  WatchReach(state, env, hands, stage_ticks, tick);
  if (head_moves_ && !target_fixated_) {
    const Vec3 centre = state.ObjectPosition(env, target);
    const double best = scenarios::expert::ClosestGazeError(model_.robot, state.q_row(env), centre);
    target_fixated_ =
        scenarios::expert::GazeError(model_.robot, state.q_row(env), centre) <= best + fixation_angle_rad_;
  }
  // Dropped: lifted (the raised stage reached), then out of every hand for kDroppedS and, for a
  // lift, fallen kDroppedFallM from its highest since (a target that slips in a closed grip is not).
  if (raised_stage_ >= 0 && stage_ticks[static_cast<std::size_t>(raised_stage_)] >= 0 &&
      objects_[static_cast<std::size_t>(target)].watched) {
    const double z = state.ObjectPosition(env, target).z();
    highest_since_lift_ = std::max(highest_since_lift_, z);
    const bool lift = scenario_.success.kind == scenarios::SuccessRule::Kind::kLiftAbove;
    if (Held(state, env, hands, target)) {
      drop_start_tick_ = -1;
    } else {
      if (drop_start_tick_ < 0) drop_start_tick_ = tick;
      const bool long_enough =
          tick - drop_start_tick_ >= static_cast<int>(std::lround(kDroppedS * model_.physics.control_hz));
      if (long_enough && (!lift || highest_since_lift_ - z >= kDroppedFallM))
        Fire(FailureEvent::kTargetDropped, drop_start_tick_);
    }
  }
}

std::vector<EventFired> FailureEventDetector::Finish(const engine::BatchState& state, int env,
                                                     const std::vector<int>& stage_ticks,
                                                     const std::array<std::vector<Vec3>, 2>& tcp_log) const {
  std::array<int, kNumFailureEvents> ticks = first_ticks_;
  const int last = state.control_step[env];
  const auto fire = [&](FailureEvent event) {
    int& first = ticks[static_cast<std::size_t>(event)];
    if (first < 0) first = last;
  };
  if (head_moves_ && cue_stage_ >= 0 && stage_ticks[static_cast<std::size_t>(cue_stage_)] < 0)
    fire(FailureEvent::kCueNeverFixated);
  if (head_moves_ && !target_fixated_) fire(FailureEvent::kTargetNeverFixated);
  if (state.end[env] == engine::EpisodeEnd::kTimeOut) {
    const std::size_t window = static_cast<std::size_t>(std::lround(kTimeOutWindowS * model_.physics.control_hz));
    bool moving = false;
    for (const std::vector<Vec3>& log : tcp_log) {
      double path = 0.0;
      for (std::size_t i = log.size() > window ? log.size() - window : 1; i < log.size(); ++i)
        path += (log[i] - log[i - 1]).norm();
      moving = moving || path >= kTimeOutMovingM;
    }
    fire(moving ? FailureEvent::kTimeOutMoving : FailureEvent::kTimeOutStill);
  }
  std::vector<EventFired> fired;
  for (const FailureEvent event : ApplicableEvents(scenario_, head_moves_)) {
    const int tick = ticks[static_cast<std::size_t>(event)];
    if (tick >= 0) fired.push_back({event, tick});
  }
  return fired;
}

}  // namespace tavis::batch::cell
