#include "batch/init_pose_warmup.h"

namespace tavis::batch {

kinematics::Action InitPoseWarmupAction(const kinematics::RobotModel& robot, engine::RandomStream& rng) {
  namespace layout = kinematics::action;
  kinematics::Action action{};
  for (kinematics::Side side : kinematics::kSides) {
    const int i = kinematics::Index(side);
    const RigidTransform& rest = robot.arm(side).rest_pose_canonical;
    for (int k = 0; k < 3; ++k) {
      action[layout::kArmPosition[i] + k] = rest.translation()[k] + rng.Normal(0.0, kInitPosePositionNoise);
    }
    const Quat q(rest.linear());
    action[layout::kArmQuaternion[i]] = q.w();
    action[layout::kArmQuaternion[i] + 1] = q.x();
    action[layout::kArmQuaternion[i] + 2] = q.y();
    action[layout::kArmQuaternion[i] + 3] = q.z();
    action[layout::kGripper[i]] = -1.0;
  }
  action[layout::kNeckRoll] = 0.0;
  action[layout::kNeckPitch] = rng.Normal(0.0, kInitPoseNeckNoise);
  action[layout::kNeckYaw] = rng.Normal(0.0, kInitPoseNeckNoise);
  return action;
}

}  // namespace tavis::batch
