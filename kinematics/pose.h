// Math vocabulary shared by every module: Eigen-based rigid transforms and rotations.
//
// Poses use monogram notation: X_WC is frame C expressed in frame W; p_WC is C's origin in W;
// R_WC its rotation. Quaternions are (w, x, y, z) wherever they cross an interface, as in
// the reference benchmark.
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tavis {

using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;
using RigidTransform = Eigen::Isometry3d;

// URDF fixed-axis roll-pitch-yaw: R = Rz(yaw) * Ry(pitch) * Rx(roll).
inline Mat3 RotationFromRpy(const Vec3& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

inline RigidTransform MakeTransform(const Vec3& p, const Mat3& R) {
  RigidTransform X = RigidTransform::Identity();
  X.linear() = R;
  X.translation() = p;
  return X;
}

inline RigidTransform TransformFromXyzRpy(const Vec3& xyz, const Vec3& rpy) {
  return MakeTransform(xyz, RotationFromRpy(rpy));
}

// Quaternion from (w, x, y, z) components (Eigen's constructor takes them in that order too,
// but its coeffs() storage is x, y, z, w: this helper keeps call sites unambiguous).
inline Quat QuatFromWxyz(double w, double x, double y, double z) { return Quat(w, x, y, z); }

// Rotation about the world z axis by yaw, then nothing else: the upright pose of tabletop objects.
inline Quat QuatFromYaw(double yaw) { return Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())); }

// Axis-angle vector of a rotation quaternion, as IsaacLab's axis_angle_from_quat computes it
// (the IK pose error): the quaternion is flipped to w >= 0 and, like the reference, an
// unnormalised quaternion scales the result by its norm.
inline Vec3 AxisAngleVector(const Quat& q_in) {
  const Quat q = q_in.w() < 0 ? Quat(-q_in.w(), -q_in.x(), -q_in.y(), -q_in.z()) : q_in;
  const double half_angle = std::atan2(q.vec().norm(), q.w());
  const double angle = 2.0 * half_angle;
  const double sin_half_over_angle = std::abs(angle) > 1e-6 ? std::sin(half_angle) / angle : 0.5 - angle * angle / 48.0;
  return q.vec() / sin_half_over_angle;
}

}  // namespace tavis
