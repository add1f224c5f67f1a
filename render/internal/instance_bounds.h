// Proves, before tracing, that no primary ray of a tile can hit anything, so that a tile of sky
// is written as background without calling Embree. In the rendering cell 29% of the tiles see
// only sky, and Embree's packets that hit nothing were 8-11% of its render CPU (measured by
// tracing them twice).
//
// Per env and render this keeps the bounding box of every visible instance's shape, turned into
// the world and grown by a margin (the meshes lie inside their shapes), and every plane as an
// unbounded plane. A tile's rays lie inside the pyramid spanned by its four corner pixels' rays (a
// ray's direction is forward + a * left + b * up with a and b affine in the pixel's column and
// row, so its parameter is the depth along forward) between the near and far clipping depths.
// None of them can hit a box that lies entirely nearer than the near depth (the head inside which
// the head camera sits, the hand in front of a wrist camera) or farther than the far one, or
// outside one of the pyramid's four side planes, or whose face plane the origin lies beyond while
// all four corner rays run away from it; nor a plane that all four corner rays run away from. The
// test is conservative: the images are the same as with every ray traced.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "render/internal/env_scenes.h"
#include "render/internal/surface_shading.h"

namespace tavis::render::internal {

class InstanceBounds {
 public:
  InstanceBounds() = default;
  // Sizes every buffer for `n_instances` so that Build does not allocate.
  explicit InstanceBounds(int n_instances);

  // Takes the instances with visible[i] != 0 at their frames for this render.
  void Build(const InstanceFrame* frames, const SurfaceModel* surfaces, const uint8_t* visible);

  // A tile's rays: from `origin`, directions in the pyramid spanned by corner[0..3] (in order
  // around the tile), depths along the unit vector `forward` between near_m and far_m.
  struct Pyramid {
    Eigen::Vector3f origin;
    Eigen::Vector3f forward;
    float near_m;
    float far_m;
    Eigen::Vector3f corner[4];
  };

  // Whether no ray of the pyramid can hit a visible instance.
  bool MissesEverything(const Pyramid& pyramid) const;

 private:
  struct Box {
    Eigen::Vector3f centre;
    Eigen::Vector3f axes[3];  // the shape's local axes in the world
    Eigen::Vector3f half;     // half sizes along them, grown by the margin
  };
  struct Plane {
    Eigen::Vector3f normal;
    Eigen::Vector3f point;
  };
  // Whether no ray of the pyramid (its inward side-plane normals `normal`) can reach the box.
  static bool Misses(const Box& box, const Pyramid& pyramid, const Eigen::Vector3f* normal,
                     const float* normal_dot_origin);

  // Sized once (copies keep the size, not a reserved capacity); the first n_ are this render's.
  int n_boxes_ = 0;
  int n_planes_ = 0;
  std::vector<Box> boxes_;
  std::vector<Plane> planes_;
};

}  // namespace tavis::render::internal
