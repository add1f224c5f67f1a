// The canonical 19-D TAVIS action (reference section 5): per arm an IK target position
// (canonical frame) and quaternion (w, x, y, z), absolute neck roll/pitch/yaw, per gripper a
// scalar in [-1, 1] (-1 open, +1 closed).
#pragma once

#include <array>

namespace tavis::kinematics {

enum class Side : int { kLeft = 0, kRight = 1 };
constexpr std::array<Side, 2> kSides = {Side::kLeft, Side::kRight};
inline int Index(Side side) { return static_cast<int>(side); }
inline const char* Name(Side side) { return side == Side::kLeft ? "left" : "right"; }

constexpr int kArmDof = 7;
constexpr int kNeckDof = 3;

namespace action {
constexpr int kSize = 19;
constexpr int kArmPosition[2] = {0, 7};     // x, y, z
constexpr int kArmQuaternion[2] = {3, 10};  // w, x, y, z
constexpr int kNeckRoll = 14;
constexpr int kNeckPitch = 15;
constexpr int kNeckYaw = 16;
// The neck entries in the order of RobotModel::neck_joints (roll, pitch, yaw).
constexpr int kNeck[kNeckDof] = {kNeckRoll, kNeckPitch, kNeckYaw};
constexpr int kGripper[2] = {17, 18};
}  // namespace action

using Action = std::array<double, action::kSize>;

}  // namespace tavis::kinematics
