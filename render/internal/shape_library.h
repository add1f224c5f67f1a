// One committed Embree scene (BVH) per distinct shape of a layout, plus each instance's surface
// model. Built once; shared by every env.
#pragma once

#include <vector>

#include "render/internal/embree_device.h"
#include "render/internal/surface_shading.h"
#include "render/scene_layout.h"

namespace tavis::render::internal {

class ShapeLibrary {
 public:
  ShapeLibrary(RTCDevice device, const std::vector<InstanceSpec>& instances);

  int n_shapes() const { return static_cast<int>(shape_scenes_.size()); }
  RTCScene scene_of_instance(int instance) const {
    return shape_scenes_[static_cast<std::size_t>(shape_of_instance_[static_cast<std::size_t>(instance)])].get();
  }
  const std::vector<SurfaceModel>& surfaces() const { return surfaces_; }

 private:
  std::vector<ScenePtr> shape_scenes_;
  std::vector<int> shape_of_instance_;
  std::vector<SurfaceModel> surfaces_;  // per instance
};

}  // namespace tavis::render::internal
