#include "render/image_batch.h"

#include <stdexcept>
#include <string>

namespace tavis::render {

ImageBatch::ImageBatch(const std::vector<CameraSpec>& cameras, int num_envs, const RenderOptions& options)
    : num_envs_(num_envs) {
  if (num_envs <= 0)
    throw std::invalid_argument("ImageBatch: num_envs = " + std::to_string(num_envs) + " must be positive");
  for (const CameraSpec& camera : cameras) {
    ValidateCamera(camera);
    widths_.push_back(camera.width);
    heights_.push_back(camera.height);
    camera_pixel_offset_.push_back(pixels_per_env_);
    pixels_per_env_ += static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height);
  }
  const std::size_t pixels = pixels_per_env_ * static_cast<std::size_t>(num_envs);
  rgb_.assign(3 * pixels, 0);
  if (options.with_depth) depth_.assign(pixels, 0.0f);
  if (options.with_object_id) object_id_.assign(pixels, -1);
}

}  // namespace tavis::render
