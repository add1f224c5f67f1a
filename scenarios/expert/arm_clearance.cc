#include "scenarios/expert/arm_clearance.h"

#include <algorithm>
#include <cmath>

#include "kinematics/forward_kinematics.h"

namespace tavis::scenarios::expert {
namespace {

// Two box edges whose directions' cross product is shorter than this (the sine of the angle
// between them) count as parallel: their separating axis is then one of the face axes.
constexpr double kParallelEdgesSine = 1e-9;
// Joint-space paths are checked at samples this far apart in the largest joint's motion: at a
// 0.6 m reach the hand moves about 3 cm between samples, less than its boxes are wide.
constexpr double kPathSampleStep = 0.05;  // rad

// True if link `link` moves with one of the arm's joints (it or an ancestor is an arm joint's child).
bool MovesWithArm(const kinematics::RobotModel& robot, kinematics::Side side, int link) {
  const auto& arm_joints = robot.arm(side).joints;
  for (int l = link; l != kinematics::kBaseLink; l = robot.links[static_cast<std::size_t>(l)].parent) {
    const int joint = robot.links[static_cast<std::size_t>(l)].joint;
    if (std::find(arm_joints.begin(), arm_joints.end(), joint) != arm_joints.end()) return true;
  }
  return false;
}

}  // namespace

bool BoxesOverlap(const OrientedBox& a, const OrientedBox& b, double margin) {
  const Mat3& A = a.X.linear();
  const Mat3& B = b.X.linear();
  const Vec3 ha = a.half_size + Vec3::Constant(margin);
  const Vec3& hb = b.half_size;
  const Vec3 d = b.X.translation() - a.X.translation();
  // Separated along `axis` if the projected centre distance exceeds the projected half extents.
  auto separated = [&](const Vec3& axis) {
    const double length = axis.norm();
    if (length < kParallelEdgesSine) return false;
    const Vec3 u = axis / length;
    const double ra = (A.transpose() * u).cwiseAbs().dot(ha);
    const double rb = (B.transpose() * u).cwiseAbs().dot(hb);
    return std::abs(d.dot(u)) > ra + rb;
  };
  for (int i = 0; i < 3; ++i) {
    if (separated(A.col(i)) || separated(B.col(i))) return false;
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (separated(A.col(i).cross(B.col(j)))) return false;
    }
  }
  return true;
}

ArmObstacles::ArmObstacles(const engine::WorldModel& model, const engine::BatchState& state, int env, double margin)
    : margin_(margin), root_world_(model.robot.root_world) {
  const Vec3 base = model.robot.root_world;
  auto in_base = [&](const RigidTransform& X_W) {
    RigidTransform X_B = X_W;
    X_B.translation() -= base;
    return X_B;
  };
  for (const engine::StaticPart& part : model.static_parts) {
    if (!part.collides) continue;
    (part.name == "table" ? link_only_ : obstacles_).push_back({in_base(part.X_WS), BoundingHalfSize(part.shape)});
  }
  for (int object = 0; object < model.num_objects(); ++object) {
    const engine::ObjectSpec& spec = model.objects[static_cast<std::size_t>(object)];
    if (spec.motion != engine::ObjectMotion::kKinematic || !spec.collides || !state.object_enabled_at(env, object)) {
      continue;
    }
    const RigidTransform X_WO =
        MakeTransform(state.ObjectPosition(env, object), state.ObjectOrientation(env, object).toRotationMatrix());
    obstacles_.push_back({in_base(X_WO), BoundingHalfSize(spec.shape)});
  }
}

bool ArmObstacles::ArmIsClear(const kinematics::RobotModel& robot, kinematics::Side side,
                              const RigidTransform* X_BL) const {
  auto clear_of = [&](const std::vector<OrientedBox>& obstacles, const OrientedBox& part) {
    return std::none_of(obstacles.begin(), obstacles.end(),
                        [&](const OrientedBox& obstacle) { return BoxesOverlap(part, obstacle, margin_); });
  };
  for (const kinematics::LinkShape& shape : robot.shapes) {
    if (shape.link == kinematics::kBaseLink || !MovesWithArm(robot, side, shape.link)) continue;
    const OrientedBox link{X_BL[static_cast<std::size_t>(shape.link)] * shape.X_LS, BoundingHalfSize(shape.shape)};
    if (!clear_of(obstacles_, link) || !clear_of(link_only_, link)) return false;
  }
  const RigidTransform& X_B_ik = X_BL[static_cast<std::size_t>(robot.arm(side).ik_link)];
  for (const OrientedBox& part : OpenHandBoxes(robot.gripper, X_B_ik, robot.gripper.open_gap)) {
    if (!clear_of(obstacles_, part)) return false;
  }
  return true;
}

bool ArmObstacles::BoxIsClear(const OrientedBox& box_world) const {
  OrientedBox box = box_world;
  box.X.translation() -= root_world_;
  return std::none_of(obstacles_.begin(), obstacles_.end(),
                      [&](const OrientedBox& obstacle) { return BoxesOverlap(box, obstacle, margin_); });
}

bool ArmObstacles::JointPathIsClear(const kinematics::RobotModel& robot, kinematics::Side side,
                                    const std::vector<double>& q_from, const std::vector<double>& q_to) const {
  if (obstacles_.empty() && link_only_.empty()) return true;
  double largest = 0.0;
  for (const int joint : robot.arm(side).joints) largest = std::max(largest, std::abs(q_to[joint] - q_from[joint]));
  const int samples = std::max(2, static_cast<int>(std::ceil(largest / kPathSampleStep)));
  std::vector<double> q = q_from;
  // Only the arm's joints move along the path: the other links' poses are computed once.
  std::vector<RigidTransform> X_BL(robot.links.size());
  kinematics::ComputeLinkPoses(robot, q.data(), X_BL.data());
  const std::vector<int> arm_links = kinematics::LinksMovedByArm(robot, side);
  for (int i = 1; i <= samples; ++i) {
    const double s = static_cast<double>(i) / samples;
    for (const int joint : robot.arm(side).joints) q[joint] = q_from[joint] + s * (q_to[joint] - q_from[joint]);
    kinematics::ComputeLinkPosesOf(robot, q.data(), arm_links, X_BL.data());
    if (!ArmIsClear(robot, side, X_BL.data())) return false;
  }
  return true;
}

}  // namespace tavis::scenarios::expert
