// The pick expert's commanded hand poses as they move, one control tick at a time: along a
// straight joint-space segment (the controller follows it where it could not follow a straight
// hand line), or along a straight hand line at a speed, as a teleoperator moves the hand.
// Poses are the IK link's (canonical frame) at arm configurations, evaluated on a fixed joint
// vector: moving the hands allocates nothing.
#pragma once

#include <array>

#include "engine/world_model.h"
#include "kinematics/robot_buffers.h"
#include "kinematics/robot_model.h"

namespace tavis::scenarios::expert {

class HandMotion {
 public:
  // Holds both hands at their poses in configuration q (full joint vector); later poses take
  // the joints besides the arms' from q.
  void Reset(const kinematics::RobotModel& robot, const double* q);

  // The commanded IK-link pose (canonical frame) of `side`'s hand.
  const RigidTransform& command(kinematics::Side side) const { return command_[kinematics::Index(side)]; }

  // IK-link pose (canonical frame) of `side`'s arm at `joints`.
  RigidTransform PoseAt(const kinematics::RobotModel& robot, kinematics::Side side, const ArmJoints& joints);

  // Starts a straight joint-space segment of `side`'s arm, timed so that no joint moves faster
  // than joint_speed and the hand's start-to-end distance takes no less than at hand_speed.
  void StartSegment(const engine::WorldModel& model, kinematics::Side side, const ArmJoints& from, const ArmJoints& to,
                    double joint_speed, double hand_speed);
  // Advances the arm's segment by a control tick and commands its hand pose; true when it has ended.
  bool FollowSegment(const kinematics::RobotModel& robot, kinematics::Side side);

  // Moves `side`'s commanded hand a control tick straight toward the pose of arm configuration
  // `goal` at `speed` (m/s); true there.
  bool MoveToward(const engine::WorldModel& model, kinematics::Side side, const ArmJoints& goal, double speed);

 private:
  // A straight joint-space segment, traversed at a speed set by its length.
  struct Segment {
    ArmJoints from{};
    ArmJoints to{};
    double progress = 0.0;  // 0..1
    double rate = 0.0;      // progress per control tick
  };

  JointPositions q_{};  // where poses are evaluated: the arms' joints as last set, the rest as at Reset
  std::array<RigidTransform, 2> command_;
  std::array<Segment, 2> segments_;
};

}  // namespace tavis::scenarios::expert
