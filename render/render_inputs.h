// Per-tick inputs of BatchRenderer::Render: read-only views of the caller's structure-of-arrays
// buffers. Nothing is copied; the buffers must outlive the call.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "kinematics/pose.h"
#include "render/procedural_texture.h"

namespace tavis::render {

// A read-only (pointer, size) view; converts from std::vector. Empty means "not given".
template <typename T>
struct ArrayRef {
  const T* data = nullptr;
  std::size_t size = 0;

  ArrayRef() = default;
  ArrayRef(const T* data_in, std::size_t size_in) : data(data_in), size(size_in) {}
  template <typename Allocator>
  ArrayRef(const std::vector<T, Allocator>& v) : data(v.data()), size(v.size()) {}  // NOLINT: implicit view

  bool empty() const { return size == 0; }
  const T& operator[](std::size_t i) const { return data[i]; }
};

// Index order everywhere: [env][instance] or [env][camera], env-major.
struct RenderInputs {
  // World pose of every instance (n_envs x n_instances). A non-finite pose hides that instance
  // for this tick (Validate reports it).
  ArrayRef<RigidTransform> X_WI;
  // 1 = drawn, 0 = hidden (n_envs x n_instances). Empty: everything visible.
  ArrayRef<uint8_t> instance_visible;
  // Per-env colour replacing Appearance::rgb, e.g. a card or light whose colour is a task
  // variable (n_envs x n_instances, linear [0, 1]). Empty: the layout's colours.
  ArrayRef<Eigen::Vector3f> instance_rgb;
  // Per-env procedural texture replacing the colour (Appearance::rgb or instance_rgb) of a lit
  // instance's surface, evaluated per hit in the instance's frame (n_envs x n_instances;
  // TexturePattern::kNone keeps the colour; labels are drawn over it; emissive surfaces ignore
  // it). Empty: no textures, and the shading takes exactly its untextured path.
  ArrayRef<ProceduralTexture> instance_texture;
  // World pose of every camera (n_envs x n_cameras). A non-finite pose gives an all-zero image.
  ArrayRef<RigidTransform> X_WC;
  // 0 = this env's camera is blocked: its image is all zero and no ray is traced
  // (n_envs x n_cameras). Empty: all enabled.
  ArrayRef<uint8_t> camera_enabled;
  // 1 = render this camera this tick (n_cameras). Images of cameras not rendered keep their
  // previous contents. Empty: render all cameras.
  ArrayRef<uint8_t> render_camera;
};

}  // namespace tavis::render
