// MuJoCo's OpenGL renderer (mjr_*) drawing the scene our SceneRender draws: one mocap body per
// render instance (same shapes, colours from the same palette, posed from the same instance
// poses), the same cameras (pinhole, same field of view) and the same distant light, with its
// shadow map. OpenGL comes from Mesa's OSMesa (llvmpipe, software). MuJoCo and GL types stay in
// the .cc file.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/scene_layout.h"

namespace tavis::peer {

class MujocoRenderer {
 public:
  // `layout` is SceneRender::layout(); all its cameras are rendered.
  MujocoRenderer(const render::SceneLayout& layout, bool shadows);
  ~MujocoRenderer();
  MujocoRenderer(const MujocoRenderer&) = delete;
  MujocoRenderer& operator=(const MujocoRenderer&) = delete;

  // Renders every camera of one env from its instance and camera poses; image(c) holds camera
  // c's RGB afterwards (top row first, like ours). Instances with visible[i] == 0 are not drawn.
  void Render(const RigidTransform* X_WI, const RigidTransform* X_WC, const uint8_t* visible);
  const std::vector<uint8_t>& image(int camera) const;
  std::string mjcf() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tavis::peer
