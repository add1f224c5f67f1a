// The parallel gripper's derived geometry, computed once from its GripperSpec: where the housing,
// the pads and the visual fingers sit in the IK link frame at a given gap, and how finger slider
// positions map to the gap. The physics builds, the renderer draws and the planners' clearance
// checks test this one description, so the three cannot drift apart.
#pragma once

#include <array>

#include "kinematics/pose.h"
#include "kinematics/robot_model.h"

namespace tavis::kinematics {

// The two jaws, by the side of the pad centre they sit on along the closing axis.
inline constexpr std::array<double, 2> kJawSigns = {1.0, -1.0};

class GripperGeometry {
 public:
  explicit GripperGeometry(const GripperSpec& spec);

  const GripperSpec& spec() const { return spec_; }
  // m, a pad's extent along the closing axis.
  double pad_thickness() const { return pad_thickness_; }
  // m, how far each finger moves from open to closed.
  double finger_travel() const { return finger_travel_; }
  // m, z of the housing's bottom face in the IK link frame (the grippers approach along -z).
  double housing_bottom() const { return housing_bottom_; }
  // m, length of the visual-only finger from the housing's bottom face down to its pad's centre
  // (the physics has no finger link there); not positive when the pads touch the housing.
  double visual_finger_length() const { return visual_finger_length_; }
  Vec3 visual_finger_size() const;
  // The visual finger's centre in the IK link frame with the jaws closed on the centre line.
  const Vec3& visual_finger_centre() const { return visual_finger_centre_; }

  // Displacement of jaw `sign` (kJawSigns) from the centre line along the closing axis when the
  // pads' inner faces are `gap` apart.
  Vec3 JawOffset(double sign, double gap) const;
  // Centre of pad `sign` in the IK link frame at inner-face gap `gap`.
  Vec3 PadCentre(double sign, double gap) const;
  RigidTransform X_IkPad(double sign, double gap) const;
  RigidTransform X_IkHousing() const;

  // Each finger's closing position (0 open, finger_travel() closed) for a gripper command in
  // [-1 open, 1 closed]; commands outside are clamped.
  double ClosingTarget(double command) const;
  // Inner-face gap given both fingers' closing positions.
  double GapFromClosing(double closing_first, double closing_second) const;

 private:
  GripperSpec spec_;
  double pad_thickness_ = 0.0;
  double finger_travel_ = 0.0;
  double housing_bottom_ = 0.0;
  double visual_finger_length_ = 0.0;
  Vec3 visual_finger_centre_ = Vec3::Zero();
};

}  // namespace tavis::kinematics
