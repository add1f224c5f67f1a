// Batched Embree ray tracer: renders every camera of every env of a SceneLayout in one call.
//
// Per call: each env's instance scene is updated from the poses and committed once, then rays are
// traced over (env x camera x 16x16-pixel tile) work items with TBB, in packets of 16 rays
// (4x4 pixels; 8 rays, 4x2 pixels, on CPUs without AVX-512). Primary hits are shaded with a dome
// term plus one distant light whose visibility is a shadow-ray packet. Results do not depend on
// the number of threads.
#pragma once

#include <cstdint>
#include <memory>

#include "render/image_batch.h"
#include "render/render_inputs.h"
#include "render/scene_layout.h"

namespace tavis::render {

struct RenderStats {
  int64_t primary_rays = 0;
  int64_t shadow_rays = 0;
  int64_t primary_hits = 0;
  int64_t sky_tiles = 0;  // tiles written as background without tracing (none of their rays can hit)
  // RenderEnv: the CPU time that other threads spent on this call's tiles, which the calling
  // thread's own CPU clock does not see (0 for Render, whose work every thread shares).
  int64_t helper_cpu_ns = 0;
};

class BatchRenderer {
 public:
  // Validates the layout (std::invalid_argument on bad input) and builds one acceleration
  // structure per distinct shape and one instance scene per env.
  BatchRenderer(const SceneLayout& layout, int num_envs, const RenderOptions& options = {});
  ~BatchRenderer();
  BatchRenderer(const BatchRenderer&) = delete;
  BatchRenderer& operator=(const BatchRenderer&) = delete;

  const SceneLayout& layout() const;
  int num_envs() const;
  int n_instances() const;
  int n_cameras() const;
  // Distinct shapes among the instances, i.e. the number of shape BVHs built.
  int n_unique_shapes() const;

  // Output buffers of the right shapes for this renderer; allocate once, reuse every tick.
  ImageBatch MakeImageBatch() const;

  // Full check of the inputs: array sizes, finite poses, 0/1 flags, colours in [0, 1], textures.
  // Throws std::invalid_argument naming the array, index and value. Call it when binding buffers
  // or whenever the data comes from an untrusted source; Render does only the size checks.
  void Validate(const RenderInputs& inputs) const;

  // Renders the requested cameras of every env into `images` (from MakeImageBatch). Throws
  // std::invalid_argument only if array sizes or the image batch do not match the declared
  // shapes (a caller bug, caught on the first call); never throws on the data, never allocates.
  RenderStats Render(const RenderInputs& inputs, ImageBatch* images);
  // Renders the requested cameras of env `env` alone into its images; the other envs' images and
  // scenes are left as they are. Its tiles are tasks: the calling thread shades them unless idle
  // threads take some (at a cell's tail). Calls for distinct envs may run concurrently with each
  // other (not with Render): the per-env schedule of the episode driver renders each env at its
  // own policy ticks. Images are the same as Render's for that env.
  RenderStats RenderEnv(int env, const RenderInputs& inputs, ImageBatch* images);

  // Benchmark baseline: the same scene update and primary-ray packets as Render, with no
  // shading, no shadow rays and no image writes. Returns the ray and hit counts.
  RenderStats CastPrimaryRaysOnly(const RenderInputs& inputs);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tavis::render
