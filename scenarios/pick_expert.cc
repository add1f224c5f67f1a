#include "scenarios/pick_expert.h"

#include <algorithm>
#include <array>
#include <iterator>
#include <cmath>
#include <optional>

#include "kinematics/forward_kinematics.h"
#include "scenarios/arm_clearance.h"
#include "scenarios/arm_planner.h"
#include "scenarios/gaze.h"
#include "scenarios/grasp_clearance.h"

namespace tavis::scenarios {
namespace {

constexpr double kWithdrawRise = 0.015;  // m: the pads rise this much while withdrawing
// m: how much farther than the approach distance a withdrawal may go to bring the object out,
// in steps of kWithdrawStep.
constexpr double kMaxExtraWithdrawal = 0.12;
constexpr double kWithdrawStep = 0.03;
constexpr double kArmClearance = 0.005;  // m: planned gap between the arm and fixed obstacles
// The pads must overlap the object over this height, or this fraction of the object's height if
// that is less: a grip at the very top edge of a low can slides off.
constexpr double kMinPadOverlap = 0.015;  // m
constexpr double kMinPadOverlapFraction = 0.6;
// m: a gripper this close to its fully shut gap holds nothing (the thinnest object is 21 mm).
constexpr double kEmptyGripMargin = 0.005;

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

// Yaw of a box's most horizontal axis, folded into [-pi/4, pi/4]: a parallel gripper can take
// a box by either pair of side faces, and a cube that fell on its side is still upright.
double FoldedYaw(const Quat& orientation) {
  const Mat3 R = orientation.toRotationMatrix();
  int flattest = 0;
  for (int axis = 1; axis < 3; ++axis) {
    if (std::abs(R(2, axis)) < std::abs(R(2, flattest))) flattest = axis;
  }
  const double yaw = std::atan2(R(1, flattest), R(0, flattest));
  const double quarter = M_PI / 2.0;
  return yaw - quarter * std::round(yaw / quarter);
}

}  // namespace

std::vector<GraspCandidate> TableGraspCandidates() {
  constexpr double kQuarter = M_PI / 2;
  return {
      {0.8, 0.0, 0.0},       {0.8, 0.0, M_PI},       {0.6, 0.0, 0.0},       {0.6, 0.0, M_PI},
      {1.0, 0.0, 0.0},       {1.0, 0.0, M_PI},       {0.8, kQuarter, 0.0},  {0.8, -kQuarter, 0.0},
      {0.8, kQuarter, M_PI}, {0.8, -kQuarter, M_PI}, {0.6, kQuarter, 0.0},  {0.6, -kQuarter, 0.0},
      {0.6, kQuarter, M_PI}, {0.6, -kQuarter, M_PI}, {1.0, kQuarter, 0.0},  {1.0, -kQuarter, 0.0},
  };
}

std::vector<GraspCandidate> TableAndSideGraspCandidates() {
  std::vector<GraspCandidate> candidates = TableGraspCandidates();
  for (const double tilt : {1.0, M_PI / 2 - 0.3, M_PI / 2}) {
    for (const double heading : {0.0, 0.35, -0.35, 0.7, -0.7}) {
      for (const double turn : {0.0, M_PI}) candidates.push_back({tilt, heading, turn, /*along_hand=*/true, /*from_outside=*/true});
    }
  }
  return candidates;
}

std::vector<GraspCandidate> ShelfGraspCandidates() {
  const double level = M_PI / 2;
  std::vector<GraspCandidate> candidates;
  for (const double heading : {0.0, 0.25, -0.25, 0.5, -0.5, 0.75, -0.75}) {
    for (const double tilt : {level, level - 0.2, level + 0.2, level - 0.4}) {
      for (const double turn : {0.0, M_PI}) candidates.push_back({tilt, heading, turn, /*along_hand=*/true});
    }
  }
  return candidates;
}

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
  m.q_plan.assign(state.q_row(env), state.q_row(env) + robot.num_joints());
  for (Side side : kinematics::kSides) m.hand_command[kinematics::Index(side)] = HandPoseCanonical(robot, side, state.q_row(env));
  for (int i = 0; i < kinematics::kNeckDof; ++i) m.neck_command[i] = state.q_row(env)[robot.neck_joints[i]];
  m.neck_goal = m.neck_command;
  m.fixated_point = Vec3::Constant(1e9);
  m.phase = settings_.cue_object >= 0 || !settings_.scan_points.empty() ? Phase::kWatchCue : Phase::kLook;
}

Expert::Gaze PickExpert::gaze(const engine::BatchState& state, int env) const {
  const EnvMemory& m = memory_[env];
  Gaze gaze;
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
    const double rate = std::clamp(settings_.neck_gain * (m.neck_goal[i] - m.neck_command[i]),
                                   -settings_.neck_max_speed, settings_.neck_max_speed);
    m.neck_command[i] += rate * dt;
  }
}

bool PickExpert::PlanGrasp(const engine::WorldModel& model, const engine::BatchState& state, int env,
                           EnvMemory& m) const {
  const kinematics::RobotModel& robot = model.robot;
  const int target = state.target(env);
  const Vec3 p_object = state.ObjectPosition(env, target);
  const double yaw = settings_.reach_heading ? settings_.reach_heading(state, env)
                                             : FoldedYaw(state.ObjectOrientation(env, target));
  m.side = settings_.reach_side ? settings_.reach_side(state, env) : p_object.y() >= 0.0 ? Side::kLeft : Side::kRight;
  const auto& arm_joints = robot.arm(m.side).joints;
  const std::vector<double> q_now(state.q_row(env), state.q_row(env) + robot.num_joints());
  // Hand target (base frame) that puts the pads' centre at a world point.
  auto target_for = [&](const Mat3& R, const Vec3& pad_world) {
    return kinematics::PoseTarget{pad_world - robot.root_world - R * robot.gripper.pad_center, Quat(R)};
  };
  auto arm_of = [&](const std::vector<double>& q) {
    ArmJoints joints{};
    for (int k = 0; k < kinematics::kArmDof; ++k) joints[k] = q[arm_joints[k]];
    return joints;
  };
  // Pads' centre height at the grasp: at the object's centre, but with the open hand (turned by
  // R) clear of the surface the object stands on, for low objects such as the tuna can; a level
  // hand's housing reaches lower than its pads.
  const double object_half_height = HalfExtentAlong(model, state, env, target, Vec3::UnitZ());
  const double support_z = p_object.z() - object_half_height;
  auto grasp_z_for = [&](const Mat3& R) {
    const RigidTransform X_pads_ik = MakeTransform(-(R * robot.gripper.pad_center), R);
    const std::array<OrientedBox, 3> hand = OpenHandBoxes(robot.gripper, X_pads_ik, robot.gripper.open_gap);
    const std::size_t parts = settings_.support_under_hand ? hand.size() : 2;  // pads first, then the housing
    double lowest = 0.0;  // below the pads' centre
    for (std::size_t p = 0; p < parts; ++p) {
      const OrientedBox& box = hand[p];
      const double half_height = (box.X.linear().transpose() * Vec3::UnitZ()).cwiseAbs().dot(box.half_size);
      lowest = std::min(lowest, box.X.translation().z() - half_height);
    }
    return std::max(p_object.z() + settings_.grasp_height, support_z - lowest + settings_.clearance);
  };
  // Raised until the housing clears the support, a level hand's pads can pass over a low object
  // (the tuna can) entirely: such a hand orientation is no grasp.
  auto pads_cover_object = [&](const Mat3& R) {
    const double pad_half_height = (R.transpose() * Vec3::UnitZ()).cwiseAbs().dot(0.5 * robot.gripper.pad_size);
    const double z = grasp_z_for(R);
    const double overlap = std::min(p_object.z() + object_half_height, z + pad_half_height) -
                           std::max(support_z, z - pad_half_height);
    return overlap >= std::min(kMinPadOverlap, kMinPadOverlapFraction * 2.0 * object_half_height);
  };
  // The pads' centre at the grasp: over the object, shifted `lateral` along the closing axis.
  auto grasp_point = [&](const Mat3& R, double lateral) -> Vec3 {
    return Vec3(p_object.x(), p_object.y(), grasp_z_for(R)) + lateral * (R * robot.gripper.closing_axis);
  };
  // The pre-grasp pads' centre from the grasp's, for hand orientation R (approach: the hand's -Z).
  auto approach_offset = [&](const Mat3& R, bool along_hand) -> Vec3 {
    return settings_.approach_distance * (along_hand ? Vec3(R.col(2)) : Vec3::UnitZ());
  };
  // The open hand's `parts`, moved from the pre-grasp to the grasp, stay clear of the other objects.
  auto HandClearsNeighboursOnDescent = [&](const Mat3& R, bool along_hand, double lateral, HandParts parts) {
    const Vec3 grasp = grasp_point(R, lateral);
    constexpr int kSamples = 4;
    for (int i = 0; i <= kSamples; ++i) {
      const Vec3 pad_world = grasp + approach_offset(R, along_hand) * i / kSamples;
      const RigidTransform X_W_ik = MakeTransform(pad_world - R * robot.gripper.pad_center, R);
      if (!OpenHandClearsNeighbours(model, state, env, target, X_W_ik, robot.gripper.open_gap, settings_.clearance, parts)) {
        return false;
      }
    }
    return true;
  };
  // Ticks a straight hand line takes at `speed`, for its rehearsal.
  auto line_ticks = [&](double distance, double speed) {
    return std::max(1, static_cast<int>(distance / speed * model.physics.control_hz));
  };
  // Preferred first: a hand that descends clear of the neighbours, palm included, then with
  // its fingers clear; among those, a descent and lift the controller can track as straight
  // hand lines (its IK, started at the planned configuration, can stall on a wrist limit
  // centimetres off the line and push the object with a finger). Then any reachable grasp.
  // To clear a close neighbour the hand may also come down off-centre, one open finger just
  // outside the object's face; closing then slides the object to the hand's centre.
  // Where the scene has fixed obstacles (a screen, shelves, box walls), plans whose arm keeps
  // clear of them all the way come first; the same tiers without that follow.
  const ArmObstacles obstacles(model, state, env, kArmClearance);
  // The held object's way out of an along-hand grasp: moved with the pads by `withdrawal`, then
  // lifted (if the task lifts), its box swept up must clear the fixed obstacles: it has to come
  // out from under peeking-box's lid before it can rise.
  const OrientedBox held = ObjectBox(model, state, env, target);
  auto way_out_is_clear = [&](const Vec3& pads_after_withdrawal, const Vec3& withdrawal) {
    const double rise = settings_.lift_to_z ? std::max(0.0, *settings_.lift_to_z - pads_after_withdrawal.z()) : 0.0;
    const Vec3 half = held.X.linear().cwiseAbs() * held.half_size + Vec3(0.0, 0.0, 0.5 * rise);
    const Vec3 centre = held.X.translation() + withdrawal + Vec3(0.0, 0.0, 0.5 * rise);
    return obstacles.BoxIsClear({MakeTransform(centre, Mat3::Identity()), half});
  };
  struct Tier {
    std::optional<HandParts> clear_parts;
    bool need_trackable_lines;
    bool arm_clear;
  };
  std::vector<Tier> tiers;
  for (const bool arm_clear : {true, false}) {
    if (arm_clear && obstacles.empty()) continue;
    for (const Tier tier : {Tier{HandParts::kPadsAndHousing, true, arm_clear}, Tier{HandParts::kPads, true, arm_clear},
                            Tier{std::nullopt, true, arm_clear}, Tier{std::nullopt, false, arm_clear}}) {
      tiers.push_back(tier);
    }
  }
  // The arm configurations of a hand orientation and lateral shift, solved once across tiers.
  struct ArmPlan {
    bool reachable = false;
    bool trackable = false;
    ArmJoints pre{}, grasp{}, withdraw{}, lift{};
  };
  auto solve = [&](const Mat3& R, bool along_hand, double lateral, const ArmObstacles* avoid) {
    ArmPlan plan;
    const Vec3 grasp_pads = grasp_point(R, lateral);
    const kinematics::PoseTarget grasp = target_for(R, grasp_pads);
    const auto q_grasp = SolveArmConfiguration(robot, m.side, q_now, grasp, avoid);
    if (!q_grasp) return plan;
    const auto q_pre = SolveArmConfiguration(robot, m.side, *q_grasp,
                                             target_for(R, grasp_pads + approach_offset(R, along_hand)), avoid, &q_now);
    if (!q_pre) return plan;
    plan.trackable = CanTrackStraightPath(robot, m.side, *q_pre, grasp,
                                          line_ticks(settings_.approach_distance, settings_.descend_speed), avoid);
    // Then the held object's way out: withdraw (along-hand grasps), lift (if the task lifts).
    std::vector<double> q_last = *q_grasp;
    Vec3 last_pads = grasp_pads;
    auto move_to = [&](const Vec3& pads, ArmJoints& joints) {
      const kinematics::PoseTarget goal = target_for(R, pads);
      const auto q = SolveArmConfiguration(robot, m.side, q_last, goal, avoid);
      if (!q) return false;
      plan.trackable = plan.trackable && CanTrackStraightPath(robot, m.side, q_last, goal,
                                                              line_ticks((pads - last_pads).norm(), settings_.slow_hand_speed), avoid);
      joints = arm_of(*q);
      q_last = *q;
      last_pads = pads;
      return true;
    };
    if (along_hand) {
      // The shortest withdrawal from the approach distance on that brings the object out.
      auto withdrawn_pads = [&](double distance) -> Vec3 { return grasp_pads + distance * R.col(2) + Vec3(0.0, 0.0, kWithdrawRise); };
      double distance = settings_.approach_distance;
      for (double d = distance; d <= settings_.approach_distance + kMaxExtraWithdrawal + 1e-9; d += kWithdrawStep) {
        if (way_out_is_clear(withdrawn_pads(d), withdrawn_pads(d) - grasp_pads)) {
          distance = d;
          break;
        }
      }
      if (!move_to(withdrawn_pads(distance), plan.withdraw)) return plan;
    }
    if (settings_.lift_to_z && !move_to(Vec3(last_pads.x(), last_pads.y(), *settings_.lift_to_z), plan.lift)) return plan;
    plan.reachable = true;
    plan.pre = arm_of(*q_pre);
    plan.grasp = arm_of(*q_grasp);
    return plan;
  };
  constexpr int kLaterals = 3;  // centred, shifted either way along the closing axis
  const std::vector<GraspCandidate>& candidates = settings_.grasp_candidates;
  // [arm_clear][candidate x lateral]
  std::array<std::vector<std::optional<ArmPlan>>, 2> plans;
  for (auto& tier_plans : plans) tier_plans.resize(candidates.size() * kLaterals);
  // Hand orientations, and the order they are tried in: those whose open jaws straddle the
  // object with clearance first (a heading the task fixes, as into a box, may leave the object
  // wider across the jaws than they open: the fingers would push it away). Orientations whose
  // pads miss the object's height, and those of grasps that already failed, are not tried.
  std::vector<Mat3> rotations;
  std::vector<std::size_t> fitting, too_wide;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    const GraspCandidate& candidate = candidates[c];
    const double heading = candidate.from_outside ? (m.side == Side::kLeft ? -M_PI / 2 : M_PI / 2) : yaw;
    rotations.push_back((Eigen::AngleAxisd(heading + candidate.heading_offset, Vec3::UnitZ()) *
                         Eigen::AngleAxisd(-candidate.tilt, Vec3::UnitY()) *
                         Eigen::AngleAxisd(candidate.turn, Vec3::UnitZ()))
                            .toRotationMatrix());
    const bool failed = std::find(m.failed_candidates.begin(), m.failed_candidates.end(), c) != m.failed_candidates.end();
    if (failed || !pads_cover_object(rotations.back())) continue;
    const double half_width = HalfExtentAlong(model, state, env, target, rotations.back() * robot.gripper.closing_axis);
    (half_width <= 0.5 * robot.gripper.open_gap - settings_.clearance ? fitting : too_wide).push_back(c);
  }
  std::vector<std::size_t> order = fitting;
  order.insert(order.end(), too_wide.begin(), too_wide.end());
  for (const Tier& tier : tiers) {
    for (const std::size_t c : order) {
      const GraspCandidate& candidate = candidates[c];
      const Mat3& R = rotations[c];
      const double half_width = HalfExtentAlong(model, state, env, target, R * robot.gripper.closing_axis);
      const double shift = std::max(0.0, 0.5 * robot.gripper.open_gap - half_width - settings_.clearance);
      const double laterals[kLaterals] = {0.0, shift, -shift};
      // Shifted descents only serve clearance.
      const int num_laterals = tier.clear_parts && shift > 0.0 ? kLaterals : 1;
      for (int l = 0; l < num_laterals; ++l) {
        if (tier.clear_parts && !HandClearsNeighboursOnDescent(R, candidate.along_hand, laterals[l], *tier.clear_parts)) {
          continue;
        }
        std::optional<ArmPlan>& plan = plans[tier.arm_clear ? 1 : 0][c * kLaterals + static_cast<std::size_t>(l)];
        if (!plan) plan = solve(R, candidate.along_hand, laterals[l], tier.arm_clear ? &obstacles : nullptr);
        if (!plan->reachable || (tier.need_trackable_lines && !plan->trackable)) continue;
        m.arm_clear = tier.arm_clear;
        m.candidate = c;
        m.q_pre = plan->pre;
        m.q_grasp = plan->grasp;
        m.q_withdraw = plan->withdraw;
        m.q_lift = plan->lift;
        m.withdraws = candidate.along_hand;
        m.lifts = settings_.lift_to_z.has_value();
        return true;
      }
    }
  }
  return false;
}

void PickExpert::StartSegment(const engine::WorldModel& model, EnvMemory& m, Side side, const ArmJoints& from,
                              const ArmJoints& to, double cartesian_speed) const {
  const kinematics::RobotModel& robot = model.robot;
  const auto& arm_joints = robot.arm(side).joints;
  double joint_distance = 0.0;
  for (int k = 0; k < kinematics::kArmDof; ++k) joint_distance = std::max(joint_distance, std::abs(to[k] - from[k]));
  for (int k = 0; k < kinematics::kArmDof; ++k) m.q_plan[arm_joints[k]] = from[k];
  const Vec3 start = HandPoseCanonical(robot, side, m.q_plan.data()).translation();
  for (int k = 0; k < kinematics::kArmDof; ++k) m.q_plan[arm_joints[k]] = to[k];
  const Vec3 end = HandPoseCanonical(robot, side, m.q_plan.data()).translation();
  const double duration = std::max({joint_distance / settings_.joint_speed, (end - start).norm() / cartesian_speed, 0.1});
  m.segments[kinematics::Index(side)] = {from, to, 0.0, 1.0 / (duration * model.physics.control_hz)};
}

bool PickExpert::FollowSegment(const engine::WorldModel& model, EnvMemory& m, Side side) const {
  const kinematics::RobotModel& robot = model.robot;
  Segment& s = m.segments[kinematics::Index(side)];
  s.progress = std::min(1.0, s.progress + s.rate);
  // Smoothstep timing: the hand starts and stops gently.
  const double blend = s.progress * s.progress * (3.0 - 2.0 * s.progress);
  const auto& arm_joints = robot.arm(side).joints;
  for (int k = 0; k < kinematics::kArmDof; ++k) m.q_plan[arm_joints[k]] = s.from[k] + blend * (s.to[k] - s.from[k]);
  m.hand_command[kinematics::Index(side)] = HandPoseCanonical(robot, side, m.q_plan.data());
  return s.progress >= 1.0;
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
    ArmJoints from{}, to{};
    for (int k = 0; k < kinematics::kArmDof; ++k) from[k] = q_now[robot.arm(side).joints[k]];
    if (!q_peek) {  // this wrist cannot look there: it keeps still
      StartSegment(model, m, side, from, from, settings_.hand_speed);
      continue;
    }
    any = true;
    for (int k = 0; k < kinematics::kArmDof; ++k) to[k] = (*q_peek)[robot.arm(side).joints[k]];
    StartSegment(model, m, side, from, to, settings_.hand_speed);
  }
  return any;
}

void PickExpert::StartReach(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m,
                            int step) const {
  ++m.attempts;
  if (!PlanGrasp(model, state, env, m)) {
    Enter(m, Phase::kGiveUp, step);
    return;
  }
  ArmJoints q_now{};
  for (int k = 0; k < kinematics::kArmDof; ++k) q_now[k] = state.q_row(env)[model.robot.arm(m.side).joints[k]];
  StartSegment(model, m, m.side, q_now, m.q_pre, settings_.hand_speed);
  m.cartesian_approach = ApproachLineIsTrackable(model, state, env, m);
  Enter(m, Phase::kApproach, step);
}

bool PickExpert::HandIsEmpty(const engine::WorldModel& model, const engine::BatchState& state, int env,
                             const EnvMemory& m) const {
  const double gap = state.gripper_gap_row(env)[kinematics::Index(m.side)];
  return gap <= model.robot.gripper.closed_gap + kEmptyGripMargin;
}

void PickExpert::StartRetreat(EnvMemory& m, int step) const {
  m.failed_candidates.push_back(m.candidate);
  Enter(m, Phase::kRetreat, step);
}

bool PickExpert::ApproachLineIsTrackable(const engine::WorldModel& model, const engine::BatchState& state, int env,
                                         EnvMemory& m) const {
  const kinematics::RobotModel& robot = model.robot;
  const auto& arm_joints = robot.arm(m.side).joints;
  for (int k = 0; k < kinematics::kArmDof; ++k) m.q_plan[arm_joints[k]] = m.q_pre[k];
  RigidTransform goal = HandPoseCanonical(robot, m.side, m.q_plan.data());
  const RigidTransform start = m.hand_command[kinematics::Index(m.side)];
  // MoveHandToward's line at hand speed, rehearsed over the same number of ticks.
  const int ticks = std::max(1, static_cast<int>((goal.translation() - start.translation()).norm() /
                                                 settings_.hand_speed * model.physics.control_hz));
  const std::vector<double> q_now(state.q_row(env), state.q_row(env) + robot.num_joints());
  const ArmObstacles obstacles(model, state, env, kArmClearance);
  return CanTrackStraightPath(robot, m.side, q_now, {robot.CanonicalToBase(goal.translation()), Quat(goal.linear())},
                              ticks, m.arm_clear ? &obstacles : nullptr);
}

bool PickExpert::MoveHandToward(const engine::WorldModel& model, EnvMemory& m, const ArmJoints& goal,
                                double speed) const {
  const auto& arm_joints = model.robot.arm(m.side).joints;
  for (int k = 0; k < kinematics::kArmDof; ++k) m.q_plan[arm_joints[k]] = goal[k];
  const RigidTransform target = HandPoseCanonical(model.robot, m.side, m.q_plan.data());
  RigidTransform& hand = m.hand_command[kinematics::Index(m.side)];
  const Vec3 delta = target.translation() - hand.translation();
  const double max_step = speed / model.physics.control_hz;
  const double distance = delta.norm();
  // The same fraction of the remaining translation and rotation: a straight line with the
  // orientation turning in proportion.
  const double fraction = distance > max_step ? max_step / distance : 1.0;
  hand.translation() += fraction * delta;
  // Normalised at every step: repeated matrix-quaternion round trips otherwise drift off the
  // rotation group, and the drift grows until the commanded hand turns away from its target.
  hand.linear() =
      Quat(hand.linear()).normalized().slerp(fraction, Quat(target.linear()).normalized()).normalized().toRotationMatrix();
  return fraction >= 1.0;
}

void PickExpert::Act(const engine::WorldModel& model, const engine::BatchState& state, int env,
                     kinematics::Action& action) {
  EnvMemory& m = memory_[env];
  const int step = state.control_step[env];
  const double elapsed = (step - m.phase_start_step) / model.physics.control_hz;
  UpdateNeck(model, state, env, m);

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
      const bool go = !settings_.wait_for_go || state.task[env].go;
      if (go) Enter(m, Phase::kLook, step);
      break;
    }
    case Phase::kLook: {
      if (NeckError(m) < 0.01) Enter(m, Phase::kSettle, step);
      break;
    }
    case Phase::kSettle:
      if (elapsed < settings_.settle_s) break;
      if (settings_.peek_poses && !m.peeked) {
        m.peeked = true;
        if (StartPeek(model, state, env, m)) {
          Enter(m, Phase::kPeek, step);
          break;
        }
        m.peek_done = true;
      }
      StartReach(model, state, env, m, step);
      break;
    case Phase::kPeek: {
      // Both hands go to their peek poses; the clock for peek_s starts when both have arrived.
      bool arrived = true;
      for (Side side : kinematics::kSides) arrived = FollowSegment(model, m, side) && arrived;
      if (!arrived) m.phase_start_step = step;
      m.peek_done = arrived;
      if (arrived && elapsed >= settings_.peek_s) StartReach(model, state, env, m, step);
      break;
    }
    case Phase::kApproach: {
      const bool arrived = m.cartesian_approach ? MoveHandToward(model, m, m.q_pre, settings_.hand_speed)
                                                : FollowSegment(model, m, m.side);
      if (arrived) Enter(m, Phase::kDescend, step);
      break;
    }
    case Phase::kDescend:
      if (MoveHandToward(model, m, m.q_grasp, settings_.descend_speed)) Enter(m, Phase::kClose, step);
      break;
    case Phase::kClose:
      m.gripper_command[kinematics::Index(m.side)] = 1.0;
      if (elapsed < settings_.close_s) break;
      if (HandIsEmpty(model, state, env, m)) {
        StartRetreat(m, step);
      } else {
        Enter(m, m.withdraws ? Phase::kWithdraw : Phase::kLift, step);
      }
      break;
    case Phase::kWithdraw:
      if (HandIsEmpty(model, state, env, m)) {
        StartRetreat(m, step);
      } else if (MoveHandToward(model, m, m.q_withdraw, settings_.slow_hand_speed)) {
        Enter(m, Phase::kLift, step);
      }
      break;
    case Phase::kLift:
      if (HandIsEmpty(model, state, env, m)) {
        StartRetreat(m, step);
      } else if (m.lifts) {
        MoveHandToward(model, m, m.q_lift, settings_.slow_hand_speed);
      }
      break;
    case Phase::kRetreat:
      // The hand opens where it is (moving closed fingers through the object would push it),
      // then backs out to the failed plan's pre-grasp, and a new plan starts from there.
      m.gripper_command[kinematics::Index(m.side)] = -1.0;
      if (elapsed < settings_.close_s || !MoveHandToward(model, m, m.q_pre, settings_.hand_speed)) break;
      if (m.attempts < settings_.max_attempts) {
        StartReach(model, state, env, m, step);
      } else {
        Enter(m, Phase::kGiveUp, step);
      }
      break;
    case Phase::kGiveUp:
      break;
  }

  for (Side side : kinematics::kSides) WriteArm(action, side, m.hand_command[kinematics::Index(side)]);
  action[kinematics::action::kNeckRoll] = m.neck_command[0];
  action[kinematics::action::kNeckPitch] = m.neck_command[1];
  action[kinematics::action::kNeckYaw] = m.neck_command[2];
  for (Side side : kinematics::kSides) {
    action[kinematics::action::kGripper[kinematics::Index(side)]] = m.gripper_command[kinematics::Index(side)];
  }
}

}  // namespace tavis::scenarios
