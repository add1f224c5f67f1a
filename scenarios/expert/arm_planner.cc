#include "scenarios/expert/arm_planner.h"

#include <algorithm>
#include <cmath>

#include "kinematics/robot_buffers.h"
#include "scenarios/expert/arm_clearance.h"
#include "scenarios/expert/arm_reach.h"
#include "scenarios/expert/ik_iteration.h"

namespace tavis::scenarios::expert {
namespace {

constexpr double kPositionTolerance = 0.002;
constexpr double kAngleTolerance = 0.03;
constexpr int kIterationsPerSeed = 150;
constexpr int kSeeds = 24;
constexpr double kStillStep = 1e-9;  // rad: a step that moves no joint this much reached a fixed point
// A seed has converged when its score (Converge: position error in units of kPositionTolerance
// plus angle error in units of kAngleTolerance) is at most this.
constexpr double kConverged = 2.0;
// A converged seed's hand is within kConverged * kPositionTolerance of the target; a target this
// much farther than the arm reaches is out of reach of every seed (and of rounding).
constexpr double kReachRounding = 1e-6;  // m

// Iterates the controller's IK step kinematically (joint limits respected); returns the error.
// X_BL holds q's poses of the links the arm does not move; `arm_links` (LinksMovedByArm) are
// recomputed at each step.
double Converge(const kinematics::RobotModel& robot, kinematics::Side side, std::vector<double>& q,
                const kinematics::PoseTarget& target, const std::vector<int>& arm_links,
                std::vector<RigidTransform>& X_BL) {
  IterateIk(robot, side, q, target, arm_links, X_BL, kIterationsPerSeed, kStillStep);
  const Vec6 error = kinematics::IkPoseError(robot, side, X_BL.data(), target);
  return error.head<3>().norm() / kPositionTolerance + error.tail<3>().norm() / kAngleTolerance;
}

// The i-th seed: a fixed low-discrepancy spread over the joint ranges (golden-ratio sequence),
// so planning is deterministic.
void SpreadSeed(const kinematics::RobotModel& robot, kinematics::Side side, int i, std::vector<double>& q) {
  const auto& joints = robot.arm(side).joints;
  for (int k = 0; k < kinematics::kArmDof; ++k) {
    const kinematics::Joint& joint = robot.joints[joints[k]];
    const double u = std::fmod(0.5 + (i + 1) * (0.6180339887498949 + 0.1 * k), 1.0);
    // Stay within the middle of wide ranges: full turns are never the useful branch.
    const double low = std::max(joint.lower, joint.default_position - 2.0);
    const double high = std::min(joint.upper, joint.default_position + 2.0);
    q[joints[k]] = low + u * (high - low);
  }
}

}  // namespace

std::optional<std::vector<double>> SolveArmConfiguration(const kinematics::RobotModel& robot, kinematics::Side side,
                                                         const std::vector<double>& q_start,
                                                         const kinematics::PoseTarget& target,
                                                         const ArmObstacles* obstacles,
                                                         const std::vector<double>* clear_path_from) {
  // Seeds differ in the arm's joints only: the other links' poses are computed once.
  std::vector<RigidTransform> X_BL(robot.links.size());
  kinematics::ComputeLinkPoses(robot, q_start.data(), X_BL.data());
  // No seed can converge on a target beyond the arm's reach: the answer is known without them.
  const ArmReach reach = ArmReachOf(robot, side, X_BL.data());
  if ((target.position - reach.centre).norm() > reach.radius + kConverged * kPositionTolerance + kReachRounding) {
    return std::nullopt;
  }
  const std::vector<int> arm_links = kinematics::LinksMovedByArm(robot, side);
  std::vector<double> best;
  double best_score = 1e300;
  for (int seed = -1; seed < kSeeds; ++seed) {
    std::vector<double> q = q_start;
    if (seed >= 0) SpreadSeed(robot, side, seed, q);
    const double score = Converge(robot, side, q, target, arm_links, X_BL);
    // Only a converged seed better than the best so far can be the answer (a converged one beats
    // any that is not): the others skip the clearance checks, which leaves the result unchanged.
    if (!(score <= kConverged && score < best_score)) continue;
    if (obstacles && !obstacles->ArmIsClear(robot, side, X_BL.data())) continue;
    if (obstacles && clear_path_from && !obstacles->JointPathIsClear(robot, side, *clear_path_from, q)) continue;
    best_score = score;
    best = q;
    if (seed < 0) break;  // the start's own basin is preferred
  }
  if (best_score > kConverged) return std::nullopt;
  return best;
}

bool CanTrackStraightPath(const kinematics::RobotModel& robot, kinematics::Side side,
                          const std::vector<double>& q_start, const kinematics::PoseTarget& goal, int ticks,
                          const ArmObstacles* obstacles) {
  constexpr double kPathTolerance = 0.01;
  std::vector<RigidTransform> X_BL(robot.links.size());
  std::vector<double> q = q_start;
  kinematics::ComputeLinkPoses(robot, q.data(), X_BL.data());
  const std::vector<int> arm_links = kinematics::LinksMovedByArm(robot, side);
  const RigidTransform start = X_BL[robot.arm(side).ik_link];
  const Quat start_orientation(start.linear());
  for (int tick = 1; tick <= ticks + 30; ++tick) {
    const double s = std::min(1.0, static_cast<double>(tick) / ticks);
    const kinematics::PoseTarget target{(1.0 - s) * start.translation() + s * goal.position,
                                        start_orientation.slerp(s, goal.orientation)};
    const auto next = kinematics::IkStep(robot, side, q.data(), X_BL.data(), target);
    for (int k = 0; k < kinematics::kArmDof; ++k) q[robot.arm(side).joints[k]] = next[k];
    kinematics::ComputeLinkPosesOf(robot, q.data(), arm_links, X_BL.data());
    const Vec6 error = kinematics::IkPoseError(robot, side, X_BL.data(), target);
    if (error.head<3>().norm() > kPathTolerance) return false;
    if (obstacles && !obstacles->ArmIsClear(robot, side, X_BL.data())) return false;
  }
  const Vec6 final_error = kinematics::IkPoseError(robot, side, X_BL.data(), goal);
  return final_error.head<3>().norm() < kPositionTolerance && final_error.tail<3>().norm() < kAngleTolerance;
}

RigidTransform HandPoseCanonical(const kinematics::RobotModel& robot, kinematics::Side side, const double* q) {
  CheckFitsRobotBuffers(robot);
  LinkPoses X_BL;
  kinematics::ComputeLinkPoseChain(robot, q, robot.arm(side).ik_link, X_BL.data());
  RigidTransform X = X_BL[robot.arm(side).ik_link];
  X.translation() = robot.BaseToCanonical(X.translation());
  return X;
}

}  // namespace tavis::scenarios::expert
