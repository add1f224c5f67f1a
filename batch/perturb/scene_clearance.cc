#include "batch/perturb/scene_clearance.h"

#include <cmath>

#include "kinematics/forward_kinematics.h"
#include "kinematics/robot_buffers.h"
#include "scenarios/expert/arm_clearance.h"

namespace tavis::batch::perturb {
namespace {

// Resting contact is not overlap: a box's bottom is lifted this far before it is compared with
// the static parts, so the surface it stands on does not count.
constexpr double kRestingContact = 0.002;  // m

// A box as tall as any scene, standing where `box` stands: compares footprints only.
scenarios::expert::OrientedBox Column(scenarios::expert::OrientedBox box) {
  constexpr double kTall = 100.0;  // m
  box.X.translation().z() = 0.0;
  box.half_size.z() = kTall;
  return box;
}

}  // namespace

scenarios::expert::OrientedBox UprightBox(const Shape& shape, double x, double y, double surface_z, double yaw) {
  const Vec3 half = BoundingHalfSize(shape);
  return {MakeTransform(Vec3(x, y, surface_z + half.z()), QuatFromYaw(yaw).toRotationMatrix()), half};
}

bool PointInZone(const Vec3& point, const scenarios::SupportZone& zone) {
  const double c = std::cos(zone.yaw);
  const double s = std::sin(zone.yaw);
  const double dx = point.x() - zone.centre.x();
  const double dy = point.y() - zone.centre.y();
  // The point in the zone's own frame.
  const double local_x = c * dx + s * dy;
  const double local_y = -s * dx + c * dy;
  return std::abs(local_x) <= zone.half_x && std::abs(local_y) <= zone.half_y;
}

bool FootprintInZone(const scenarios::expert::OrientedBox& box, const scenarios::SupportZone& zone) {
  for (const double sx : {-1.0, 1.0}) {
    for (const double sy : {-1.0, 1.0}) {
      for (const double sz : {-1.0, 1.0}) {
        const Vec3 corner = box.X * Vec3(sx, sy, sz).cwiseProduct(box.half_size);
        if (!PointInZone(corner, zone)) return false;
      }
    }
  }
  return true;
}

bool ClearOfObjects(const engine::WorldModel& model, const engine::BatchState& state, int env,
                    const scenarios::expert::OrientedBox& box, int skip, double margin, double fixed_margin) {
  for (int object = 0; object < model.num_objects(); ++object) {
    if (object == skip || !state.object_enabled_at(env, object)) continue;
    const bool fixed = model.objects[static_cast<std::size_t>(object)].motion == engine::ObjectMotion::kKinematic;
    if (scenarios::expert::BoxesOverlap(box, scenarios::expert::ObjectBox(model, state, env, object),
                                        fixed ? fixed_margin : margin))
      return false;
  }
  return true;
}

bool ClearOfObjectsLandingOn(const engine::WorldModel& model, const engine::BatchState& state, int env,
                             const scenarios::expert::OrientedBox& box, double surface_z, int skip, double margin) {
  const scenarios::expert::OrientedBox column = Column(box);
  for (int object = 0; object < model.num_objects(); ++object) {
    if (object == skip || !state.object_enabled_at(env, object)) continue;
    const scenarios::expert::OrientedBox other = scenarios::expert::ObjectBox(model, state, env, object);
    const double reach_down = (other.X.linear().transpose() * Vec3::UnitZ()).cwiseAbs().dot(other.half_size);
    const double bottom = other.X.translation().z() - reach_down;
    const double top = other.X.translation().z() + reach_down;
    if (top < surface_z) continue;  // below the surface
    if (bottom > surface_z + kRestingContact) {
      // What lies between it and the surface: a static part there holds it up instead.
      scenarios::expert::OrientedBox fall = Column(other);
      fall.half_size.z() = 0.5 * (bottom - surface_z) - kRestingContact;
      fall.X.translation().z() = 0.5 * (bottom + surface_z);
      if (!ClearOfStaticParts(model, fall)) continue;
    }
    if (scenarios::expert::BoxesOverlap(column, Column(other), margin)) return false;
  }
  return true;
}

bool ClearOfRobot(const engine::WorldModel& model, const engine::BatchState& state, int env,
                  const scenarios::expert::OrientedBox& box, double margin) {
  const kinematics::RobotModel& robot = model.robot;
  LinkPoses X_BL;
  kinematics::ComputeLinkPoses(robot, state.q_row(env), X_BL.data());
  const RigidTransform X_WB = MakeTransform(robot.root_world, Mat3::Identity());
  auto link_pose = [&](int link) {
    return link == kinematics::kBaseLink ? X_WB : X_WB * X_BL[static_cast<std::size_t>(link)];
  };
  for (const kinematics::LinkShape& shape : robot.shapes) {
    const scenarios::expert::OrientedBox link{link_pose(shape.link) * shape.X_LS, BoundingHalfSize(shape.shape)};
    if (scenarios::expert::BoxesOverlap(box, link, margin)) return false;
  }
  for (const kinematics::Side side : kinematics::kSides) {
    const RigidTransform X_W_ik = link_pose(robot.arm(side).ik_link);
    const double gap = state.gripper_gap_row(env)[kinematics::Index(side)];
    for (const scenarios::expert::OrientedBox& part : scenarios::expert::OpenHandBoxes(robot.gripper, X_W_ik, gap)) {
      if (scenarios::expert::BoxesOverlap(box, part, margin)) return false;
    }
  }
  return true;
}

bool ClearOfStaticParts(const engine::WorldModel& model, const scenarios::expert::OrientedBox& box) {
  scenarios::expert::OrientedBox raised = box;
  raised.X.translation().z() += 0.5 * kRestingContact;
  raised.half_size.z() -= 0.5 * kRestingContact;
  for (const engine::StaticPart& part : model.static_parts) {
    if (!part.collides) continue;
    if (scenarios::expert::BoxesOverlap(raised, {part.X_WS, BoundingHalfSize(part.shape)}, 0.0)) return false;
  }
  return true;
}

}  // namespace tavis::batch::perturb
