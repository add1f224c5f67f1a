#include "kinematics/inverse_kinematics.h"

#include <algorithm>

#include <Eigen/Cholesky>

namespace tavis::kinematics {

Vec6 IkPoseError(const RobotModel& robot, Side side, const RigidTransform* X_BL, const PoseTarget& target) {
  const RigidTransform& X_BE = X_BL[robot.arm(side).ik_link];
  const Quat current(X_BE.linear());
  Vec6 error;
  error.head<3>() = target.position - X_BE.translation();
  error.tail<3>() = AxisAngleVector(target.orientation * current.inverse());
  return error;
}

std::array<double, kArmDof> IkStep(const RobotModel& robot, Side side, const double* q, const RigidTransform* X_BL,
                                   const PoseTarget& target) {
  using Vector7 = Eigen::Matrix<double, kArmDof, 1>;
  const ArmSpec& arm = robot.arm(side);
  const ArmJacobian J_full = ComputeArmJacobian(robot, side, X_BL);
  const Vec6 error = IkPoseError(robot, side, X_BL, target);
  const double lambda_sq = robot.ik_damping * robot.ik_damping;

  Vector7 q_arm, q_rest, lower, upper;
  for (int i = 0; i < kArmDof; ++i) {
    const Joint& joint = robot.joints[arm.joints[i]];
    q_arm[i] = q[arm.joints[i]];
    q_rest[i] = joint.default_position;
    lower[i] = joint.lower;
    upper[i] = joint.upper;
  }

  // The reference leaves limits to the physics engine, which makes the step stall when a joint
  // saturates (and the null-space target of Reachy2 lies on its shoulder-roll limit). Joints the
  // step would push past a limit are pinned there and the step is re-solved with the rest.
  // The damped pseudo-inverse is applied, never formed: J+ e = J^T (J J^T + l^2 I)^-1 e, and the
  // null-space projection (I - J+ J) v = v - J+ (J v), with one 6x6 Cholesky factor per pass.
  Vector7 free = Vector7::Ones();
  Vector7 step = Vector7::Zero();
  const Vector7 rest_pull = robot.nullspace_gain * (q_rest - q_arm);
  for (int pass = 0; pass <= kArmDof; ++pass) {
    const ArmJacobian J = J_full * free.asDiagonal();
    const Vector7 pinned_motion = (Vector7::Ones() - free).cwiseProduct(step);
    const Vec6 remaining_error = error - J_full * pinned_motion;
    Eigen::Matrix<double, 6, 6> JJt = J * J.transpose();
    JJt.diagonal().array() += lambda_sq;
    const Eigen::LLT<Eigen::Matrix<double, 6, 6>> factor(JJt);
    const Vector7 primary = J.transpose() * factor.solve(remaining_error);
    const Vector7 secondary = rest_pull - J.transpose() * factor.solve(J * rest_pull);
    const Vector7 free_step = primary + free.cwiseProduct(secondary);
    bool pinned_any = false;
    for (int i = 0; i < kArmDof; ++i) {
      if (free[i] == 0.0) continue;
      const double next = q_arm[i] + free_step[i];
      step[i] = free_step[i];
      if (next > upper[i] || next < lower[i]) {
        step[i] = std::clamp(next, lower[i], upper[i]) - q_arm[i];
        free[i] = 0.0;
        pinned_any = true;
      }
    }
    if (!pinned_any) break;
  }

  std::array<double, kArmDof> out{};
  for (int i = 0; i < kArmDof; ++i) out[i] = q_arm[i] + step[i];
  return out;
}

}  // namespace tavis::kinematics
