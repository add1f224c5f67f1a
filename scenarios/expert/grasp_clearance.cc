#include "scenarios/expert/grasp_clearance.h"

#include <array>

#include "kinematics/gripper_geometry.h"

namespace tavis::scenarios::expert {
namespace {

bool Inside(const OrientedBox& box, const Vec3& p_W, double margin) {
  const Vec3 p = box.X.inverse() * p_W;
  return (p.cwiseAbs() - box.half_size).maxCoeff() < margin;
}

}  // namespace

OrientedBox ObjectBox(const engine::WorldModel& model, const engine::BatchState& state, int env, int object) {
  return {MakeTransform(state.ObjectPosition(env, object), state.ObjectOrientation(env, object).toRotationMatrix()),
          BoundingHalfSize(model.objects[object].shape)};
}

std::array<OrientedBox, 3> OpenHandBoxes(const kinematics::GripperSpec& gripper, const RigidTransform& X_ik,
                                         double open_gap) {
  const kinematics::GripperGeometry geometry(gripper);
  return {OrientedBox{X_ik * geometry.X_IkPad(kinematics::kJawSigns[0], open_gap), 0.5 * gripper.pad_size},
          OrientedBox{X_ik * geometry.X_IkPad(kinematics::kJawSigns[1], open_gap), 0.5 * gripper.pad_size},
          OrientedBox{X_ik * geometry.X_IkHousing(), 0.5 * gripper.housing_size}};
}

double HalfExtentAlong(const engine::WorldModel& model, const engine::BatchState& state, int env, int object,
                       const Vec3& direction) {
  const OrientedBox box = ObjectBox(model, state, env, object);
  return (box.X.linear().transpose() * direction).cwiseAbs().dot(box.half_size);
}

bool OpenHandClearsNeighbours(const engine::WorldModel& model, const engine::BatchState& state, int env, int target,
                              const RigidTransform& X_W_ik, double open_gap, double margin, HandParts parts) {
  const std::array<OrientedBox, 3> hand = OpenHandBoxes(model.robot.gripper, X_W_ik, open_gap);
  const int num_parts = parts == HandParts::kPadsAndHousing ? 3 : 2;
  for (int object = 0; object < model.num_objects(); ++object) {
    if (object == target || !state.object_enabled_at(env, object)) continue;
    const OrientedBox obstacle = ObjectBox(model, state, env, object);
    for (int p = 0; p < num_parts; ++p) {
      const OrientedBox& part = hand[static_cast<size_t>(p)];
      for (int i = -1; i <= 1; ++i) {
        for (int j = -1; j <= 1; ++j) {
          for (int k = -1; k <= 1; ++k) {
            const Vec3 sample = part.X * part.half_size.cwiseProduct(Vec3(i, j, k));
            if (Inside(obstacle, sample, margin)) return false;
          }
        }
      }
    }
  }
  return true;
}

}  // namespace tavis::scenarios::expert
