#include "scenarios/expert/grasp_planner.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "scenarios/expert/arm_clearance.h"
#include "scenarios/expert/arm_planner.h"
#include "scenarios/expert/grasp_clearance.h"

namespace tavis::scenarios::expert {
namespace {

constexpr double kWithdrawRise = 0.015;  // m: the pads rise this much while withdrawing
// m: how much farther than the approach distance a withdrawal may go to bring the object out,
// in steps of kWithdrawStep.
constexpr double kMaxExtraWithdrawal = 0.12;
constexpr double kWithdrawStep = 0.03;
// The pads must overlap the object over this height, or this fraction of the object's height if
// that is less: a grip at the very top edge of a low can slides off.
constexpr double kMinPadOverlap = 0.015;  // m
constexpr double kMinPadOverlapFraction = 0.6;
constexpr int kLaterals = 3;  // descents centred, and shifted either way along the closing axis

using kinematics::Side;

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

// A preference tier: which open-hand parts must descend clear of the neighbours (none: any),
// whether the descent and the way out must be straight hand lines the controller can track,
// and whether the arm must keep clear of the fixed obstacles.
struct Tier {
  std::optional<HandParts> clear_parts;
  bool need_trackable_lines;
  bool arm_clear;
};

// The arm configurations of a hand orientation and lateral shift, solved once across tiers.
struct ArmPlan {
  bool reachable = false;
  bool trackable = false;
  ArmJoints pre{}, grasp{}, withdraw{}, lift{};
};

// [arm_clear][candidate x lateral]
using ArmPlanCache = std::array<std::vector<std::optional<ArmPlan>>, 2>;

// The hand's planned path from the grasp on, as the held object's way out extends it.
struct PlannedPath {
  std::vector<double> q;  // full joint vector at its end
  Vec3 pads;              // the pads' centre (world) at its end
  bool trackable;         // the controller can follow its straight hand lines
};

class GraspPlanner {
 public:
  GraspPlanner(const engine::WorldModel& model, const engine::BatchState& state, int env,
               const PickExpertSettings& settings, Side side);

  // Preferred first: a hand that descends clear of the neighbours, palm included, then with
  // its fingers clear; among those, a descent and lift the controller can track as straight
  // hand lines (its IK, started at the planned configuration, can stall on a wrist limit
  // centimetres off the line and push the object with a finger). Then any reachable grasp.
  // To clear a close neighbour the hand may also come down off-centre, one open finger just
  // outside the object's face; closing then slides the object to the hand's centre.
  // Where the scene has fixed obstacles (a screen, shelves, box walls), plans whose arm keeps
  // clear of them all the way come first; the same tiers without that follow.
  std::optional<GraspPlan> Plan(const std::vector<bool>& failed) const;

 private:
  std::vector<Tier> Tiers() const;
  Mat3 HandOrientation(const GraspCandidate& candidate) const;
  // Hand orientations in the order they are tried: those whose open jaws straddle the object
  // with clearance first (a heading the task fixes, as into a box, may leave the object wider
  // across the jaws than they open: the fingers would push it away). Orientations whose pads
  // miss the object's height, and those of grasps that already failed, are not tried.
  std::vector<std::size_t> CandidateOrder(const std::vector<Mat3>& rotations, const std::vector<bool>& failed) const;
  // The first of the candidate's descents (centred, shifted) that meets the tier, if any.
  std::optional<GraspPlan> PlanCandidate(const Tier& tier, std::size_t c, const Mat3& R, ArmPlanCache& plans) const;
  ArmPlan SolveArmPlan(const Mat3& R, bool along_hand, double lateral, const ArmObstacles* avoid) const;

  // Hand target (base frame) that puts the pads' centre at a world point.
  kinematics::PoseTarget TargetFor(const Mat3& R, const Vec3& pad_world) const;
  // Pads' centre height at the grasp: at the object's centre, but with the open hand (turned by
  // R) clear of the surface the object stands on, for low objects such as the tuna can; a level
  // hand's housing reaches lower than its pads.
  double GraspZ(const Mat3& R) const;
  // Raised until the housing clears the support, a level hand's pads can pass over a low object
  // (the tuna can) entirely: such a hand orientation is no grasp.
  bool PadsCoverObject(const Mat3& R) const;
  // The pads' centre at the grasp: over the object, shifted `lateral` along the closing axis.
  Vec3 GraspPoint(const Mat3& R, double lateral) const;
  // The pre-grasp pads' centre from the grasp's, for hand orientation R (approach: the hand's -Z).
  Vec3 ApproachOffset(const Mat3& R, bool along_hand) const;
  // The open hand's `parts`, moved from the pre-grasp to the grasp, stay clear of the other objects.
  bool HandClearsNeighboursOnDescent(const Mat3& R, bool along_hand, double lateral, HandParts parts) const;
  // Ticks a straight hand line takes at `speed`, for its rehearsal.
  int LineTicks(double distance, double speed) const;

  // The held object's way out of an along-hand grasp: moved with the pads by `withdrawal`, then
  // lifted (if the task lifts), its box swept up must clear the fixed obstacles: it has to come
  // out from under peeking-box's lid before it can rise.
  bool WayOutIsClear(const Vec3& pads_after_withdrawal, const Vec3& withdrawal) const;
  static Vec3 WithdrawnPads(const Mat3& R, const Vec3& grasp_pads, double distance);
  // The shortest withdrawal from the approach distance on that brings the object out.
  double WithdrawalDistance(const Mat3& R, const Vec3& grasp_pads) const;
  // Extends the path by a straight hand line to `pads` (orientation R); false if the arm cannot
  // reach its end. `joints`: the arm's configuration there.
  bool ExtendPath(const Mat3& R, const Vec3& pads, const ArmObstacles* avoid, PlannedPath& path,
                  ArmJoints& joints) const;

  const engine::WorldModel& model_;
  const kinematics::RobotModel& robot_;
  const engine::BatchState& state_;
  const int env_;
  const PickExpertSettings& settings_;
  const Side side_;
  const int target_;
  const Vec3 p_object_;
  const double yaw_;  // heading reference of the candidates
  const std::vector<double> q_now_;
  const double object_half_height_;
  const double support_z_;  // height of the surface the object stands on
  const ArmObstacles obstacles_;
  const OrientedBox held_;  // the target, as it will be held
};

GraspPlanner::GraspPlanner(const engine::WorldModel& model, const engine::BatchState& state, int env,
                           const PickExpertSettings& settings, Side side)
    : model_(model),
      robot_(model.robot),
      state_(state),
      env_(env),
      settings_(settings),
      side_(side),
      target_(state.target(env)),
      p_object_(state.ObjectPosition(env, target_)),
      yaw_(settings.reach_heading ? settings.reach_heading(state, env)
                                  : FoldedYaw(state.ObjectOrientation(env, target_))),
      q_now_(state.q_row(env), state.q_row(env) + robot_.num_joints()),
      object_half_height_(HalfExtentAlong(model, state, env, target_, Vec3::UnitZ())),
      support_z_(p_object_.z() - object_half_height_),
      obstacles_(model, state, env, kArmClearance),
      held_(ObjectBox(model, state, env, target_)) {}

std::optional<GraspPlan> GraspPlanner::Plan(const std::vector<bool>& failed) const {
  const std::vector<GraspCandidate>& candidates = settings_.grasp_candidates;
  std::vector<Mat3> rotations;
  for (const GraspCandidate& candidate : candidates) rotations.push_back(HandOrientation(candidate));
  const std::vector<std::size_t> order = CandidateOrder(rotations, failed);
  ArmPlanCache plans;
  for (auto& tier_plans : plans) tier_plans.resize(candidates.size() * kLaterals);
  for (const Tier& tier : Tiers()) {
    for (const std::size_t c : order) {
      if (std::optional<GraspPlan> plan = PlanCandidate(tier, c, rotations[c], plans)) return plan;
    }
  }
  return std::nullopt;
}

std::vector<Tier> GraspPlanner::Tiers() const {
  std::vector<Tier> tiers;
  for (const bool arm_clear : {true, false}) {
    if (arm_clear && obstacles_.empty()) continue;
    for (const Tier tier : {Tier{HandParts::kPadsAndHousing, true, arm_clear}, Tier{HandParts::kPads, true, arm_clear},
                            Tier{std::nullopt, true, arm_clear}, Tier{std::nullopt, false, arm_clear}}) {
      tiers.push_back(tier);
    }
  }
  return tiers;
}

Mat3 GraspPlanner::HandOrientation(const GraspCandidate& candidate) const {
  const double heading = candidate.from_outside ? (side_ == Side::kLeft ? -M_PI / 2 : M_PI / 2) : yaw_;
  return (Eigen::AngleAxisd(heading + candidate.heading_offset, Vec3::UnitZ()) *
          Eigen::AngleAxisd(-candidate.tilt, Vec3::UnitY()) * Eigen::AngleAxisd(candidate.turn, Vec3::UnitZ()))
      .toRotationMatrix();
}

std::vector<std::size_t> GraspPlanner::CandidateOrder(const std::vector<Mat3>& rotations,
                                                      const std::vector<bool>& failed) const {
  std::vector<std::size_t> fitting, too_wide;
  for (std::size_t c = 0; c < rotations.size(); ++c) {
    if (failed[c] || !PadsCoverObject(rotations[c])) continue;
    const double half_width =
        HalfExtentAlong(model_, state_, env_, target_, rotations[c] * robot_.gripper.closing_axis);
    (half_width <= 0.5 * robot_.gripper.open_gap - settings_.clearance ? fitting : too_wide).push_back(c);
  }
  fitting.insert(fitting.end(), too_wide.begin(), too_wide.end());
  return fitting;
}

std::optional<GraspPlan> GraspPlanner::PlanCandidate(const Tier& tier, std::size_t c, const Mat3& R,
                                                     ArmPlanCache& plans) const {
  const GraspCandidate& candidate = settings_.grasp_candidates[c];
  const double half_width = HalfExtentAlong(model_, state_, env_, target_, R * robot_.gripper.closing_axis);
  const double shift = std::max(0.0, 0.5 * robot_.gripper.open_gap - half_width - settings_.clearance);
  const double laterals[kLaterals] = {0.0, shift, -shift};
  // Shifted descents only serve clearance.
  const int num_laterals = tier.clear_parts && shift > 0.0 ? kLaterals : 1;
  for (int l = 0; l < num_laterals; ++l) {
    if (tier.clear_parts && !HandClearsNeighboursOnDescent(R, candidate.along_hand, laterals[l], *tier.clear_parts)) {
      continue;
    }
    std::optional<ArmPlan>& plan = plans[tier.arm_clear ? 1 : 0][c * kLaterals + static_cast<std::size_t>(l)];
    if (!plan) plan = SolveArmPlan(R, candidate.along_hand, laterals[l], tier.arm_clear ? &obstacles_ : nullptr);
    if (!plan->reachable || (tier.need_trackable_lines && !plan->trackable)) continue;
    return GraspPlan{c, tier.arm_clear, candidate.along_hand, plan->pre, plan->grasp, plan->withdraw, plan->lift};
  }
  return std::nullopt;
}

ArmPlan GraspPlanner::SolveArmPlan(const Mat3& R, bool along_hand, double lateral, const ArmObstacles* avoid) const {
  ArmPlan plan;
  const Vec3 grasp_pads = GraspPoint(R, lateral);
  const kinematics::PoseTarget grasp = TargetFor(R, grasp_pads);
  const auto q_grasp = SolveArmConfiguration(robot_, side_, q_now_, grasp, avoid);
  if (!q_grasp) return plan;
  const auto q_pre = SolveArmConfiguration(robot_, side_, *q_grasp,
                                           TargetFor(R, grasp_pads + ApproachOffset(R, along_hand)), avoid, &q_now_);
  if (!q_pre) return plan;
  // Then the held object's way out: withdraw (along-hand grasps), lift (if the task lifts).
  PlannedPath path{*q_grasp, grasp_pads,
                   CanTrackStraightPath(robot_, side_, *q_pre, grasp,
                                        LineTicks(settings_.approach_distance, settings_.descend_speed), avoid)};
  if (along_hand &&
      !ExtendPath(R, WithdrawnPads(R, grasp_pads, WithdrawalDistance(R, grasp_pads)), avoid, path, plan.withdraw)) {
    return plan;
  }
  if (settings_.lift_to_z &&
      !ExtendPath(R, Vec3(path.pads.x(), path.pads.y(), *settings_.lift_to_z), avoid, path, plan.lift)) {
    return plan;
  }
  plan.reachable = true;
  plan.trackable = path.trackable;
  plan.pre = ArmOf(robot_, side_, q_pre->data());
  plan.grasp = ArmOf(robot_, side_, q_grasp->data());
  return plan;
}

kinematics::PoseTarget GraspPlanner::TargetFor(const Mat3& R, const Vec3& pad_world) const {
  return kinematics::PoseTarget{pad_world - robot_.root_world - R * robot_.gripper.pad_center, Quat(R)};
}

double GraspPlanner::GraspZ(const Mat3& R) const {
  const RigidTransform X_pads_ik = MakeTransform(-(R * robot_.gripper.pad_center), R);
  const std::array<OrientedBox, 3> hand = OpenHandBoxes(robot_.gripper, X_pads_ik, robot_.gripper.open_gap);
  const std::size_t parts = settings_.support_under_hand ? hand.size() : 2;  // pads first, then the housing
  double lowest = 0.0;                                                       // below the pads' centre
  for (std::size_t p = 0; p < parts; ++p) {
    const OrientedBox& box = hand[p];
    const double half_height = (box.X.linear().transpose() * Vec3::UnitZ()).cwiseAbs().dot(box.half_size);
    lowest = std::min(lowest, box.X.translation().z() - half_height);
  }
  return std::max(p_object_.z() + settings_.grasp_height, support_z_ - lowest + settings_.clearance);
}

bool GraspPlanner::PadsCoverObject(const Mat3& R) const {
  const double pad_half_height = (R.transpose() * Vec3::UnitZ()).cwiseAbs().dot(0.5 * robot_.gripper.pad_size);
  const double z = GraspZ(R);
  const double overlap =
      std::min(p_object_.z() + object_half_height_, z + pad_half_height) - std::max(support_z_, z - pad_half_height);
  return overlap >= std::min(kMinPadOverlap, kMinPadOverlapFraction * 2.0 * object_half_height_);
}

Vec3 GraspPlanner::GraspPoint(const Mat3& R, double lateral) const {
  return Vec3(p_object_.x(), p_object_.y(), GraspZ(R)) + lateral * (R * robot_.gripper.closing_axis);
}

Vec3 GraspPlanner::ApproachOffset(const Mat3& R, bool along_hand) const {
  return settings_.approach_distance * (along_hand ? Vec3(R.col(2)) : Vec3::UnitZ());
}

bool GraspPlanner::HandClearsNeighboursOnDescent(const Mat3& R, bool along_hand, double lateral,
                                                 HandParts parts) const {
  const Vec3 grasp = GraspPoint(R, lateral);
  constexpr int kSamples = 4;
  for (int i = 0; i <= kSamples; ++i) {
    const Vec3 pad_world = grasp + ApproachOffset(R, along_hand) * i / kSamples;
    const RigidTransform X_W_ik = MakeTransform(pad_world - R * robot_.gripper.pad_center, R);
    if (!OpenHandClearsNeighbours(model_, state_, env_, target_, X_W_ik, robot_.gripper.open_gap, settings_.clearance,
                                  parts)) {
      return false;
    }
  }
  return true;
}

int GraspPlanner::LineTicks(double distance, double speed) const {
  return std::max(1, static_cast<int>(distance / speed * model_.physics.control_hz));
}

bool GraspPlanner::WayOutIsClear(const Vec3& pads_after_withdrawal, const Vec3& withdrawal) const {
  const double rise = settings_.lift_to_z ? std::max(0.0, *settings_.lift_to_z - pads_after_withdrawal.z()) : 0.0;
  const Vec3 half = held_.X.linear().cwiseAbs() * held_.half_size + Vec3(0.0, 0.0, 0.5 * rise);
  const Vec3 centre = held_.X.translation() + withdrawal + Vec3(0.0, 0.0, 0.5 * rise);
  return obstacles_.BoxIsClear({MakeTransform(centre, Mat3::Identity()), half});
}

Vec3 GraspPlanner::WithdrawnPads(const Mat3& R, const Vec3& grasp_pads, double distance) {
  return grasp_pads + distance * R.col(2) + Vec3(0.0, 0.0, kWithdrawRise);
}

double GraspPlanner::WithdrawalDistance(const Mat3& R, const Vec3& grasp_pads) const {
  for (double d = settings_.approach_distance; d <= settings_.approach_distance + kMaxExtraWithdrawal + 1e-9;
       d += kWithdrawStep) {
    if (WayOutIsClear(WithdrawnPads(R, grasp_pads, d), WithdrawnPads(R, grasp_pads, d) - grasp_pads)) return d;
  }
  return settings_.approach_distance;
}

bool GraspPlanner::ExtendPath(const Mat3& R, const Vec3& pads, const ArmObstacles* avoid, PlannedPath& path,
                              ArmJoints& joints) const {
  const kinematics::PoseTarget goal = TargetFor(R, pads);
  const auto q = SolveArmConfiguration(robot_, side_, path.q, goal, avoid);
  if (!q) return false;
  path.trackable =
      path.trackable && CanTrackStraightPath(robot_, side_, path.q, goal,
                                             LineTicks((pads - path.pads).norm(), settings_.slow_hand_speed), avoid);
  joints = ArmOf(robot_, side_, q->data());
  path = {*q, pads, path.trackable};
  return true;
}

}  // namespace

Side ReachSide(const PickExpertSettings& settings, const engine::BatchState& state, int env) {
  if (settings.reach_side) return settings.reach_side(state, env);
  return state.ObjectPosition(env, state.target(env)).y() >= 0.0 ? Side::kLeft : Side::kRight;
}

std::optional<GraspPlan> PlanGrasp(const engine::WorldModel& model, const engine::BatchState& state, int env,
                                   const PickExpertSettings& settings, Side side, const std::vector<bool>& failed) {
  return GraspPlanner(model, state, env, settings, side).Plan(failed);
}

}  // namespace tavis::scenarios::expert
