#include "render/batch_renderer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "kinematics/cpu_clock.h"
#include "render/internal/embree_device.h"
#include "render/internal/env_scenes.h"
#include "render/internal/flush_denormals.h"
#include "render/internal/lighting_model.h"
#include "render/internal/shadow_casters.h"
#include "render/internal/shape_library.h"
#include "render/internal/tile_tracer.h"

namespace tavis::render {

using internal::CameraFrame;
using internal::CameraRaster;
using internal::EnvView;
using internal::ImageView;
using internal::kTileSize;
using internal::TileCounts;
using internal::TileRect;

namespace {

bool IsFinitePose(const RigidTransform& X) { return X.matrix().topRows<3>().allFinite(); }

CameraRaster RasterOf(const CameraSpec& camera) {
  const CameraIntrinsics k = IntrinsicsOf(camera);
  CameraRaster raster;
  raster.width = camera.width;
  raster.height = camera.height;
  raster.inv_fx = static_cast<float>(1.0 / k.fx);  // square pixels: fy = fx
  raster.cx = static_cast<float>(k.cx);
  raster.cy = static_cast<float>(k.cy);
  raster.near_m = static_cast<float>(camera.near_m);
  raster.far_m = static_cast<float>(camera.far_m);
  return raster;
}

CameraFrame FrameOf(const RigidTransform& X_WC) {
  CameraFrame frame;
  frame.origin = X_WC.translation().cast<float>();
  frame.forward = X_WC.linear().col(0).cast<float>();
  frame.left = X_WC.linear().col(1).cast<float>();
  frame.up = X_WC.linear().col(2).cast<float>();
  return frame;
}

int TilesAcross(int pixels) { return (pixels + kTileSize - 1) / kTileSize; }

void RequireSize(const char* array, std::size_t size, std::size_t expected, const char* shape, bool optional) {
  if (size == expected || (optional && size == 0)) return;
  std::ostringstream message;
  message << "RenderInputs." << array << " has " << size << " elements, expected " << expected << " (" << shape << ")"
          << (optional ? " or none" : "");
  throw std::invalid_argument(message.str());
}

std::string EnvItem(const char* array, std::size_t index, std::size_t per_env, const char* item) {
  return std::string("RenderInputs.") + array + "[env " + std::to_string(index / per_env) + "][" + item + " " +
         std::to_string(index % per_env) + "]";
}

void RequireFlags(const char* array, const ArrayRef<uint8_t>& flags, std::size_t per_env, const char* item) {
  for (std::size_t i = 0; i < flags.size; ++i) {
    if (flags[i] > 1) {
      throw std::invalid_argument(EnvItem(array, i, per_env, item) + " = " + std::to_string(flags[i]) +
                                  " must be 0 or 1");
    }
  }
}

void RequireRigid(const char* array, const ArrayRef<RigidTransform>& poses, std::size_t per_env, const char* item) {
  for (std::size_t i = 0; i < poses.size; ++i) {
    const RigidTransform& X = poses[i];
    if (!IsFinitePose(X)) throw std::invalid_argument(EnvItem(array, i, per_env, item) + " is not finite");
    const double error = (X.linear().transpose() * X.linear() - Mat3::Identity()).cwiseAbs().maxCoeff();
    if (error > 1e-4) {
      throw std::invalid_argument(EnvItem(array, i, per_env, item) + " rotation is not orthonormal (error " +
                                  std::to_string(error) + ")");
    }
  }
}

}  // namespace

struct BatchRenderer::Impl {
  Impl(const SceneLayout& layout_in, int num_envs_in, const RenderOptions& options_in)
      : layout(layout_in),
        num_envs(num_envs_in),
        options(options_in),
        device(internal::SharedEmbreeDevice()),
        shapes(device, layout.instances),
        env_scenes(device, shapes, num_envs, n_instances()),
        lighting(layout.lighting),
        packet_width(internal::PreferredPacketWidth(device)) {
    for (const CameraSpec& camera : layout.cameras) {
      rasters.push_back(RasterOf(camera));
      tiles_x.push_back(TilesAcross(camera.width));
      tiles_per_camera.push_back(static_cast<int64_t>(TilesAcross(camera.width)) * TilesAcross(camera.height));
    }
    const std::size_t env_cameras = static_cast<std::size_t>(num_envs) * layout.cameras.size();
    camera_frames.resize(env_cameras);
    camera_active.assign(env_cameras, 0);
    rendered_cameras.assign(layout.cameras.size(), 0);
    rendered_tile_start.assign(layout.cameras.size() + 1, 0);
    flat_shades.assign(static_cast<std::size_t>(num_envs),
                       internal::FlatShades(shapes.surfaces().data(), n_instances()));
    if (lighting.shadows() && !options.trace_every_shadow_ray)
      casters.assign(static_cast<std::size_t>(num_envs), {lighting.to_light(), n_instances()});
    if (!options.trace_every_primary_ray)
      bounds.assign(static_cast<std::size_t>(num_envs), internal::InstanceBounds(n_instances()));
  }

  int n_instances() const { return static_cast<int>(layout.instances.size()); }
  int n_cameras() const { return static_cast<int>(layout.cameras.size()); }

  void CheckShapes(const RenderInputs& inputs, const ImageBatch* images) const;
  // `shading`: the tick is shaded (not the primary-only baseline), so the shadow casters are binned.
  void PrepareTick(const RenderInputs& inputs, bool shading);
  // Marks env `env`'s rendered cameras active (enabled, finite pose) and commits its scene if
  // any is; touches only the env's rows. `rendered(c)` says whether camera c is drawn this call.
  template <typename Rendered>
  void PrepareEnv(int env, const RenderInputs& inputs, const Rendered& rendered, bool shading);
  // One tile of one env's camera: shaded, or cleared where the camera is not active.
  TileCounts ShadeOrClear(int env, int camera, const TileRect& rect, const RenderInputs& inputs,
                          const internal::Shading& shading, ImageBatch* images) const;
  template <typename TileFunction>
  RenderStats ForEachTile(const TileFunction& trace_tile) const;
  // Tile `tile` of camera `camera`, counted along rows of tiles from the top left.
  TileRect TileOf(int camera, int tile) const {
    const CameraRaster& raster = rasters[static_cast<std::size_t>(camera)];
    const int across = tiles_x[static_cast<std::size_t>(camera)];
    TileRect rect;
    rect.x0 = (tile % across) * kTileSize;
    rect.y0 = (tile / across) * kTileSize;
    rect.x1 = std::min(rect.x0 + kTileSize, raster.width);
    rect.y1 = std::min(rect.y0 + kTileSize, raster.height);
    return rect;
  }

  EnvView ViewOf(int env, const RenderInputs& inputs) const {
    EnvView view;
    view.scene = env_scenes.scene(env);
    view.frames = env_scenes.frames(env);
    view.surfaces = shapes.surfaces().data();
    view.flat = &flat_shades[static_cast<std::size_t>(env)];
    if (!casters.empty()) view.casters = &casters[static_cast<std::size_t>(env)];
    if (!bounds.empty()) view.bounds = &bounds[static_cast<std::size_t>(env)];
    if (!inputs.instance_rgb.empty()) {
      view.rgb_override = inputs.instance_rgb.data + static_cast<std::size_t>(env) * layout.instances.size();
    }
    if (!inputs.instance_texture.empty()) {
      view.textures = inputs.instance_texture.data + static_cast<std::size_t>(env) * layout.instances.size();
    }
    return view;
  }

  SceneLayout layout;
  int num_envs;
  RenderOptions options;
  RTCDevice device;
  internal::ShapeLibrary shapes;
  internal::EnvScenes env_scenes;
  internal::LightingModel lighting;
  internal::SrgbEncoder encoder;
  int packet_width;
  std::vector<CameraRaster> rasters;              // [camera]
  std::vector<int> tiles_x;                       // [camera]
  std::vector<int64_t> tiles_per_camera;          // [camera]
  std::vector<internal::FlatShades> flat_shades;  // [env]
  std::vector<internal::ShadowCasters> casters;   // [env], when the light casts shadows
  std::vector<internal::InstanceBounds> bounds;   // [env], unless every primary ray is traced

  // Per-tick state, sized once here so that Render does not allocate.
  std::vector<CameraFrame> camera_frames;    // [env][camera]
  std::vector<uint8_t> camera_active;        // [env][camera]: rendered, enabled and with a finite pose
  std::vector<int> rendered_cameras;         // the first n_rendered entries are this tick's cameras
  std::vector<int64_t> rendered_tile_start;  // prefix sums of their tile counts
  int n_rendered = 0;
};

void BatchRenderer::Impl::CheckShapes(const RenderInputs& inputs, const ImageBatch* images) const {
  const std::size_t envs = static_cast<std::size_t>(num_envs);
  const std::size_t instances = envs * layout.instances.size();
  const std::size_t cameras = envs * layout.cameras.size();
  RequireSize("X_WI", inputs.X_WI.size, instances, "num_envs x n_instances", false);
  RequireSize("instance_visible", inputs.instance_visible.size, instances, "num_envs x n_instances", true);
  RequireSize("instance_rgb", inputs.instance_rgb.size, instances, "num_envs x n_instances", true);
  RequireSize("instance_texture", inputs.instance_texture.size, instances, "num_envs x n_instances", true);
  RequireSize("X_WC", inputs.X_WC.size, cameras, "num_envs x n_cameras", false);
  RequireSize("camera_enabled", inputs.camera_enabled.size, cameras, "num_envs x n_cameras", true);
  RequireSize("render_camera", inputs.render_camera.size, layout.cameras.size(), "n_cameras", true);
  if (images == nullptr) return;
  bool matches = images->num_envs() == num_envs && images->n_cameras() == n_cameras() &&
                 images->has_depth() == options.with_depth && images->has_object_id() == options.with_object_id;
  for (int c = 0; matches && c < n_cameras(); ++c) {
    const CameraSpec& camera = layout.cameras[static_cast<std::size_t>(c)];
    matches = images->width(c) == camera.width && images->height(c) == camera.height;
  }
  if (!matches) {
    throw std::invalid_argument(
        "BatchRenderer::Render: the ImageBatch does not match this renderer's envs, cameras "
        "and options; create it with MakeImageBatch()");
  }
}

void BatchRenderer::Impl::PrepareTick(const RenderInputs& inputs, bool shading) {
  n_rendered = 0;
  for (int c = 0; c < n_cameras(); ++c) {
    if (!inputs.render_camera.empty() && inputs.render_camera[static_cast<std::size_t>(c)] == 0) continue;
    rendered_tile_start[static_cast<std::size_t>(n_rendered) + 1] =
        rendered_tile_start[static_cast<std::size_t>(n_rendered)] + tiles_per_camera[static_cast<std::size_t>(c)];
    rendered_cameras[static_cast<std::size_t>(n_rendered)] = c;
    ++n_rendered;
  }
  tbb::parallel_for(0, num_envs, [&](int env) {
    const internal::FlushDenormalsScope flush_denormals;
    PrepareEnv(
        env, inputs,
        [&](int camera) {
          for (int r = 0; r < n_rendered; ++r) {
            if (rendered_cameras[static_cast<std::size_t>(r)] == camera) return true;
          }
          return false;
        },
        shading);
  });
}

template <typename Rendered>
void BatchRenderer::Impl::PrepareEnv(int env, const RenderInputs& inputs, const Rendered& rendered, bool shading) {
  bool any_active = false;
  for (int camera = 0; camera < n_cameras(); ++camera) {
    if (!rendered(camera)) continue;
    const std::size_t index = static_cast<std::size_t>(env) * layout.cameras.size() + static_cast<std::size_t>(camera);
    const bool enabled = inputs.camera_enabled.empty() || inputs.camera_enabled[index] != 0;
    const bool active = enabled && IsFinitePose(inputs.X_WC[index]);
    camera_active[index] = active ? 1 : 0;
    if (active) camera_frames[index] = FrameOf(inputs.X_WC[index]);
    any_active = any_active || active;
  }
  if (!any_active) return;
  env_scenes.Update(env, inputs);
  // Both passes skip the tiles of sky, so that the primary-only baseline stays the primary rays'
  // cost in the shaded pass.
  if (!bounds.empty()) {
    bounds[static_cast<std::size_t>(env)].Build(env_scenes.frames(env), shapes.surfaces().data(),
                                                env_scenes.enabled(env));
  }
  if (!shading) return;
  const Eigen::Vector3f* rgb_override =
      inputs.instance_rgb.empty() ? nullptr
                                  : inputs.instance_rgb.data + static_cast<std::size_t>(env) * layout.instances.size();
  const ProceduralTexture* textures =
      inputs.instance_texture.empty()
          ? nullptr
          : inputs.instance_texture.data + static_cast<std::size_t>(env) * layout.instances.size();
  flat_shades[static_cast<std::size_t>(env)].Build(env_scenes.frames(env), rgb_override, textures, lighting, encoder);
  if (!casters.empty()) {
    casters[static_cast<std::size_t>(env)].Build(env_scenes.frames(env), shapes.surfaces().data(),
                                                 env_scenes.enabled(env));
  }
}

TileCounts BatchRenderer::Impl::ShadeOrClear(int env, int camera, const TileRect& rect, const RenderInputs& inputs,
                                             const internal::Shading& shading, ImageBatch* images) const {
  ImageView image;
  image.rgb = images->rgb(env, camera);
  image.depth = images->depth(env, camera);
  image.object_id = images->object_id(env, camera);
  image.width = images->width(camera);
  const std::size_t index = static_cast<std::size_t>(env) * layout.cameras.size() + static_cast<std::size_t>(camera);
  if (camera_active[index] == 0) {
    internal::ClearTile(rect, image);
    return TileCounts{};
  }
  return internal::ShadeTile(packet_width, ViewOf(env, inputs), rasters[static_cast<std::size_t>(camera)],
                             camera_frames[index], rect, shading, image);
}

template <typename TileFunction>
RenderStats BatchRenderer::Impl::ForEachTile(const TileFunction& trace_tile) const {
  const int64_t tiles_per_env = rendered_tile_start[static_cast<std::size_t>(n_rendered)];
  std::atomic<int64_t> primary_rays{0};
  std::atomic<int64_t> shadow_rays{0};
  std::atomic<int64_t> primary_hits{0};
  std::atomic<int64_t> sky_tiles{0};
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, tiles_per_env * num_envs),
                    [&](const tbb::blocked_range<int64_t>& items) {
                      const internal::FlushDenormalsScope flush_denormals;
                      TileCounts sum;
                      for (int64_t item = items.begin(); item != items.end(); ++item) {
                        const int env = static_cast<int>(item / tiles_per_env);
                        const int64_t env_tile = item % tiles_per_env;
                        int r = 0;
                        while (rendered_tile_start[static_cast<std::size_t>(r) + 1] <= env_tile) ++r;
                        const int camera = rendered_cameras[static_cast<std::size_t>(r)];
                        const int tile = static_cast<int>(env_tile - rendered_tile_start[static_cast<std::size_t>(r)]);
                        sum += trace_tile(env, camera, TileOf(camera, tile));
                      }
                      primary_rays += sum.primary_rays;
                      shadow_rays += sum.shadow_rays;
                      primary_hits += sum.primary_hits;
                      sky_tiles += sum.sky_tiles;
                    });
  return RenderStats{primary_rays.load(), shadow_rays.load(), primary_hits.load(), sky_tiles.load()};
}

BatchRenderer::BatchRenderer(const SceneLayout& layout, int num_envs, const RenderOptions& options) {
  if (num_envs <= 0)
    throw std::invalid_argument("BatchRenderer: num_envs = " + std::to_string(num_envs) + " must be positive");
  ValidateSceneLayout(layout);
  impl_ = std::make_unique<Impl>(layout, num_envs, options);
}

BatchRenderer::~BatchRenderer() = default;

const SceneLayout& BatchRenderer::layout() const { return impl_->layout; }
int BatchRenderer::num_envs() const { return impl_->num_envs; }
int BatchRenderer::n_instances() const { return impl_->n_instances(); }
int BatchRenderer::n_cameras() const { return impl_->n_cameras(); }
int BatchRenderer::n_unique_shapes() const { return impl_->shapes.n_shapes(); }

ImageBatch BatchRenderer::MakeImageBatch() const {
  return ImageBatch(impl_->layout.cameras, impl_->num_envs, impl_->options);
}

void BatchRenderer::Validate(const RenderInputs& inputs) const {
  impl_->CheckShapes(inputs, nullptr);
  const std::size_t n_instances = impl_->layout.instances.size();
  const std::size_t n_cameras = impl_->layout.cameras.size();
  RequireRigid("X_WI", inputs.X_WI, n_instances, "instance");
  RequireRigid("X_WC", inputs.X_WC, n_cameras, "camera");
  RequireFlags("instance_visible", inputs.instance_visible, n_instances, "instance");
  RequireFlags("camera_enabled", inputs.camera_enabled, n_cameras, "camera");
  RequireFlags("render_camera", inputs.render_camera, n_cameras, "camera");
  for (std::size_t i = 0; i < inputs.instance_rgb.size; ++i) {
    const Eigen::Vector3f& rgb = inputs.instance_rgb[i];
    if (!rgb.allFinite() || (rgb.array() < 0.0f).any() || (rgb.array() > 1.0f).any()) {
      std::ostringstream value;
      value << "(" << rgb.x() << ", " << rgb.y() << ", " << rgb.z() << ")";
      throw std::invalid_argument(EnvItem("instance_rgb", i, n_instances, "instance") + " = " + value.str() +
                                  " must be in [0, 1]");
    }
  }
  for (std::size_t i = 0; i < inputs.instance_texture.size; ++i) {
    ValidateProceduralTexture(inputs.instance_texture[i], EnvItem("instance_texture", i, n_instances, "instance"));
  }
}

RenderStats BatchRenderer::Render(const RenderInputs& inputs, ImageBatch* images) {
  Impl& impl = *impl_;
  impl.CheckShapes(inputs, images);
  impl.PrepareTick(inputs, true);
  const internal::Shading shading{&impl.lighting, &impl.encoder};
  return impl.ForEachTile([&](int env, int camera, const TileRect& rect) {
    return impl.ShadeOrClear(env, camera, rect, inputs, shading, images);
  });
}

RenderStats BatchRenderer::RenderEnv(int env, const RenderInputs& inputs, ImageBatch* images) {
  Impl& impl = *impl_;
  if (env < 0 || env >= impl.num_envs) {
    throw std::invalid_argument("BatchRenderer::RenderEnv: env " + std::to_string(env) + " out of range (" +
                                std::to_string(impl.num_envs) + " envs)");
  }
  impl.CheckShapes(inputs, images);
  const internal::FlushDenormalsScope flush_denormals;
  const auto rendered = [&](int camera) {
    return inputs.render_camera.empty() || inputs.render_camera[static_cast<std::size_t>(camera)] != 0;
  };
  impl.PrepareEnv(env, inputs, rendered, true);
  const internal::Shading shading{&impl.lighting, &impl.encoder};
  // The same tiles as Render's, as tasks over the env's rendered cameras one after the other.
  // While the caller's other envs keep every thread busy, this thread runs them all; at a cell's
  // tail, when threads have no env left to step, they take some. A tile's bytes do not depend on
  // the thread that shades it, and the counts are sums of integers.
  std::vector<int> cameras;
  std::vector<int64_t> tile_start{0};  // prefix sums of the rendered cameras' tile counts
  for (int camera = 0; camera < impl.n_cameras(); ++camera) {
    if (!rendered(camera)) continue;
    cameras.push_back(camera);
    tile_start.push_back(tile_start.back() + impl.tiles_per_camera[static_cast<std::size_t>(camera)]);
  }
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<int64_t> helper_cpu_ns{0};
  const auto shade_tiles = [&](const tbb::blocked_range<int64_t>& items, TileCounts counts) {
    const internal::FlushDenormalsScope flush_tile_denormals;
    // Only a helper's chunks are timed: the caller's CPU is on its own thread's clock.
    const bool helper = std::this_thread::get_id() != caller;
    const int64_t cpu_start = helper ? kinematics::ThreadCpuNanoseconds() : 0;
    std::size_t r = 0;
    for (int64_t item = items.begin(); item != items.end(); ++item) {
      while (tile_start[r + 1] <= item) ++r;
      const int tile = static_cast<int>(item - tile_start[r]);
      counts += impl.ShadeOrClear(env, cameras[r], impl.TileOf(cameras[r], tile), inputs, shading, images);
    }
    if (helper) helper_cpu_ns += kinematics::ThreadCpuNanoseconds() - cpu_start;
    return counts;
  };
  const auto add = [](TileCounts a, const TileCounts& b) {
    a += b;
    return a;
  };
  // Isolated: while this thread waits for its tiles it runs only tiles of this call, never
  // another slot's episode loop (which would hold this env's render until that loop ended).
  const TileCounts sum = tbb::this_task_arena::isolate([&] {
    return tbb::parallel_reduce(tbb::blocked_range<int64_t>(0, tile_start.back()), TileCounts{}, shade_tiles, add);
  });
  return RenderStats{sum.primary_rays, sum.shadow_rays, sum.primary_hits, sum.sky_tiles, helper_cpu_ns.load()};
}

RenderStats BatchRenderer::CastPrimaryRaysOnly(const RenderInputs& inputs) {
  Impl& impl = *impl_;
  impl.CheckShapes(inputs, nullptr);
  impl.PrepareTick(inputs, false);
  return impl.ForEachTile([&](int env, int camera, const TileRect& rect) {
    const std::size_t index =
        static_cast<std::size_t>(env) * impl.layout.cameras.size() + static_cast<std::size_t>(camera);
    if (impl.camera_active[index] == 0) return TileCounts{};
    return internal::CastPrimaryTile(impl.packet_width, impl.ViewOf(env, inputs),
                                     impl.rasters[static_cast<std::size_t>(camera)], impl.camera_frames[index], rect);
  });
}

}  // namespace tavis::render
