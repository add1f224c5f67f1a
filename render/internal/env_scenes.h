// One top-level Embree scene per env: an instance of the shared shape BVH for every InstanceSpec,
// moved to the tick's pose, and the same poses in float for shading.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "render/internal/embree_device.h"
#include "render/internal/shape_library.h"
#include "render/render_inputs.h"

namespace tavis::render::internal {

// X_WI as a column-major 3x4 float matrix [R | t], the layout Embree reads.
struct InstanceFrame {
  float xfm[12];

  Eigen::Vector3f ToLocal(const Eigen::Vector3f& p_W) const {
    const Eigen::Vector3f d(p_W.x() - xfm[9], p_W.y() - xfm[10], p_W.z() - xfm[11]);
    return {xfm[0] * d.x() + xfm[1] * d.y() + xfm[2] * d.z(), xfm[3] * d.x() + xfm[4] * d.y() + xfm[5] * d.z(),
            xfm[6] * d.x() + xfm[7] * d.y() + xfm[8] * d.z()};
  }
  // ToLocal for K points given as arrays (x, y, z)[k]: local[axis][k], the same floats per lane.
  template <int K>
  void ToLocalLanes(const float* x, const float* y, const float* z, float (*local)[K]) const {
    for (int k = 0; k < K; ++k) {
      const float dx = x[k] - xfm[9], dy = y[k] - xfm[10], dz = z[k] - xfm[11];
      local[0][k] = xfm[0] * dx + xfm[1] * dy + xfm[2] * dz;
      local[1][k] = xfm[3] * dx + xfm[4] * dy + xfm[5] * dz;
      local[2][k] = xfm[6] * dx + xfm[7] * dy + xfm[8] * dz;
    }
  }
  Eigen::Vector3f RotateToWorld(const Eigen::Vector3f& v) const {
    return {xfm[0] * v.x() + xfm[3] * v.y() + xfm[6] * v.z(), xfm[1] * v.x() + xfm[4] * v.y() + xfm[7] * v.z(),
            xfm[2] * v.x() + xfm[5] * v.y() + xfm[8] * v.z()};
  }
  // RotateToWorld for K vectors given as arrays v[axis][k]: world[axis][k], the same floats per lane.
  template <int K>
  void RotateToWorldLanes(const float (*v)[K], float (*world)[K]) const {
    for (int axis = 0; axis < 3; ++axis) {
      for (int k = 0; k < K; ++k) {
        world[axis][k] = xfm[axis] * v[0][k] + xfm[3 + axis] * v[1][k] + xfm[6 + axis] * v[2][k];
      }
    }
  }
};

class EnvScenes {
 public:
  EnvScenes(RTCDevice device, const ShapeLibrary& shapes, int num_envs, int n_instances);

  // Sets env `env`'s instance poses and visibility from the inputs and commits its scene.
  // Hidden instances and instances with a non-finite pose are left out of the scene.
  void Update(int env, const RenderInputs& inputs);

  RTCScene scene(int env) const { return scenes_[static_cast<std::size_t>(env)].get(); }
  const InstanceFrame* frames(int env) const {
    return frames_.data() + static_cast<std::size_t>(env) * static_cast<std::size_t>(n_instances_);
  }
  // 1 where the instance is in env `env`'s scene at its last Update (visible, finite pose).
  const uint8_t* enabled(int env) const {
    return enabled_.data() + static_cast<std::size_t>(env) * static_cast<std::size_t>(n_instances_);
  }

 private:
  int n_instances_;
  std::vector<ScenePtr> scenes_;
  std::vector<GeometryPtr> instances_;  // [env][instance]
  std::vector<InstanceFrame> frames_;   // [env][instance]
  std::vector<uint8_t> enabled_;        // [env][instance], mirrors Embree's enable state
};

}  // namespace tavis::render::internal
