#include "scenarios/grasp_clearance.h"

#include <array>
#include <cmath>

namespace tavis::scenarios {
namespace {

struct Box {
  RigidTransform X_WB;
  Vec3 half_size;
};

// The object's collision volume as a box (spheres and capsules by their bounding boxes).
Box ObjectBox(const engine::WorldModel& model, const engine::BatchState& state, int env, int object) {
  const Shape& shape = model.objects[object].shape;
  Vec3 half = 0.5 * shape.size;
  if (shape.kind == ShapeKind::kCylinder) half = Vec3(shape.Radius(), shape.Radius(), 0.5 * shape.Length());
  if (shape.kind == ShapeKind::kCapsule) half = Vec3(shape.Radius(), shape.Radius(), 0.5 * shape.Length() + shape.Radius());
  if (shape.kind == ShapeKind::kSphere) half = Vec3::Constant(shape.Radius());
  return {MakeTransform(state.ObjectPosition(env, object), state.ObjectOrientation(env, object).toRotationMatrix()),
          half};
}

bool Inside(const Box& box, const Vec3& p_W, double margin) {
  const Vec3 p = box.X_WB.inverse() * p_W;
  return (p.cwiseAbs() - box.half_size).maxCoeff() < margin;
}

}  // namespace

double HalfExtentAlong(const engine::WorldModel& model, const engine::BatchState& state, int env, int object,
                       const Vec3& direction) {
  const Box box = ObjectBox(model, state, env, object);
  return (box.X_WB.linear().transpose() * direction).cwiseAbs().dot(box.half_size);
}

bool OpenHandClearsNeighbours(const engine::WorldModel& model, const engine::BatchState& state, int env, int target,
                              const RigidTransform& X_W_ik, double open_gap, double margin, HandParts parts) {
  const kinematics::GripperSpec& g = model.robot.gripper;
  const Vec3 pad_offset = (0.5 * open_gap + 0.5 * g.pad_size.dot(g.closing_axis)) * g.closing_axis;
  const std::array<Box, 3> hand = {
      Box{X_W_ik * MakeTransform(g.pad_center + pad_offset, Mat3::Identity()), 0.5 * g.pad_size},
      Box{X_W_ik * MakeTransform(g.pad_center - pad_offset, Mat3::Identity()), 0.5 * g.pad_size},
      Box{X_W_ik * MakeTransform(g.housing_center, Mat3::Identity()), 0.5 * g.housing_size},
  };
  const int num_parts = parts == HandParts::kPadsAndHousing ? 3 : 2;
  for (int object = 0; object < model.num_objects(); ++object) {
    if (object == target || !state.object_enabled_at(env, object)) continue;
    const Box obstacle = ObjectBox(model, state, env, object);
    for (int p = 0; p < num_parts; ++p) {
      const Box& part = hand[static_cast<size_t>(p)];
      for (int i = -1; i <= 1; ++i) {
        for (int j = -1; j <= 1; ++j) {
          for (int k = -1; k <= 1; ++k) {
            const Vec3 sample = part.X_WB * part.half_size.cwiseProduct(Vec3(i, j, k));
            if (Inside(obstacle, sample, margin)) return false;
          }
        }
      }
    }
  }
  return true;
}

}  // namespace tavis::scenarios
