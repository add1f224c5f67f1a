// Output images of one render call for every env x camera, allocated once from the declared shapes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/camera.h"

namespace tavis::render {

// Which optional channels are produced next to RGB.
struct RenderOptions {
  bool with_depth = false;
  bool with_object_id = false;
  // Trace every shadow ray with Embree instead of deciding most of them with exact tests
  // (render/internal/shadow_casters.h): slower, the same images; the reference for tests.
  bool trace_every_shadow_ray = false;
  // Trace every tile's primary rays with Embree instead of writing the tiles that provably see
  // only sky as background (render/internal/instance_bounds.h): the tests' reference.
  bool trace_every_primary_ray = false;
};

// Layout: env-major, then camera, then row-major pixels. RGB is height x width x 3 uint8 (sRGB).
// Depth is float metres along the optical axis (IsaacLab's "distance_to_image_plane"), 0 where no
// surface lies between the clipping planes. Object id is the InstanceSpec::object_id of the
// visible surface, -1 for background (floor, table, robot, nothing hit).
class ImageBatch {
 public:
  ImageBatch(const std::vector<CameraSpec>& cameras, int num_envs, const RenderOptions& options);

  int num_envs() const { return num_envs_; }
  int n_cameras() const { return static_cast<int>(widths_.size()); }
  int width(int camera) const { return widths_[static_cast<std::size_t>(camera)]; }
  int height(int camera) const { return heights_[static_cast<std::size_t>(camera)]; }
  bool has_depth() const { return !depth_.empty(); }
  bool has_object_id() const { return !object_id_.empty(); }

  uint8_t* rgb(int env, int camera) { return rgb_.data() + 3 * PixelOffset(env, camera); }
  const uint8_t* rgb(int env, int camera) const { return rgb_.data() + 3 * PixelOffset(env, camera); }
  // nullptr when the channel was not requested.
  float* depth(int env, int camera) { return has_depth() ? depth_.data() + PixelOffset(env, camera) : nullptr; }
  const float* depth(int env, int camera) const {
    return has_depth() ? depth_.data() + PixelOffset(env, camera) : nullptr;
  }
  int32_t* object_id(int env, int camera) {
    return has_object_id() ? object_id_.data() + PixelOffset(env, camera) : nullptr;
  }
  const int32_t* object_id(int env, int camera) const {
    return has_object_id() ? object_id_.data() + PixelOffset(env, camera) : nullptr;
  }

 private:
  std::size_t PixelOffset(int env, int camera) const {
    return static_cast<std::size_t>(env) * pixels_per_env_ + camera_pixel_offset_[static_cast<std::size_t>(camera)];
  }

  int num_envs_ = 0;
  std::vector<int> widths_;
  std::vector<int> heights_;
  std::vector<std::size_t> camera_pixel_offset_;
  std::size_t pixels_per_env_ = 0;
  std::vector<uint8_t> rgb_;
  std::vector<float> depth_;
  std::vector<int32_t> object_id_;
};

}  // namespace tavis::render
