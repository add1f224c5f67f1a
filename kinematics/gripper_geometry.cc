#include "kinematics/gripper_geometry.h"

#include <algorithm>
#include <cmath>

#include "kinematics/invariant.h"

namespace tavis::kinematics {

GripperGeometry::GripperGeometry(const GripperSpec& spec)
    : spec_(spec),
      pad_thickness_(std::abs(spec.pad_size.dot(spec.closing_axis))),
      finger_travel_(0.5 * (spec.open_gap - spec.closed_gap)),
      housing_bottom_(spec.housing_center.z() - 0.5 * spec.housing_size.z()),
      visual_finger_length_(housing_bottom_ - spec.pad_center.z()),
      visual_finger_centre_(spec.pad_center.x(), spec.pad_center.y(),
                            spec.pad_center.z() + 0.5 * visual_finger_length_) {}

Vec3 GripperGeometry::visual_finger_size() const {
  return Vec3(spec_.pad_size.x(), spec_.pad_size.y(), visual_finger_length_);
}

Vec3 GripperGeometry::JawOffset(double sign, double gap) const {
  TAVIS_INVARIANT(sign == 1.0 || sign == -1.0, "jaw sign is +1 or -1");
  return sign * 0.5 * (gap + pad_thickness_) * spec_.closing_axis;
}

Vec3 GripperGeometry::PadCentre(double sign, double gap) const { return spec_.pad_center + JawOffset(sign, gap); }

RigidTransform GripperGeometry::X_IkPad(double sign, double gap) const {
  return MakeTransform(PadCentre(sign, gap), Mat3::Identity());
}

RigidTransform GripperGeometry::X_IkHousing() const { return MakeTransform(spec_.housing_center, Mat3::Identity()); }

double GripperGeometry::ClosingTarget(double command) const {
  return 0.5 * (std::clamp(command, -1.0, 1.0) + 1.0) * finger_travel_;
}

double GripperGeometry::GapFromClosing(double closing_first, double closing_second) const {
  return spec_.open_gap - closing_first - closing_second;
}

}  // namespace tavis::kinematics
