// Batch rendering throughput on a representative TAVIS tabletop: floor, table, a 30-primitive
// torso with two arms and grippers, six objects, and the four cameras. Poses change slightly per
// env and per iteration, so every iteration rebuilds and commits each env's instance scene.
//
// Each benchmark reports, for the full renderer (shading + shadow rays):
//   env_steps_per_s   envs rendered per second (all requested cameras of one env = one env-step)
//   rays_per_s        primary + shadow rays per second
// and, measured in the same run with timing paused, the bare primary-ray loop over the same
// scenes (no shading, no shadows, no image writes):
//   primary_only_env_steps_per_s, primary_only_rays_per_s, shading_ratio (full / primary-only time).
//
// The *Textured variants draw the same scenes with the appearance axis's procedural textures
// (render/procedural_texture.h) on the floor (value noise), the table and its legs (wood) and the
// six objects (checker), to measure what textures cost against the untextured benchmark.
//
// Run: tavis_render_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// Set TAVIS_RENDER_BENCH_CONTACT_SHEET=/path/sheet.png to also write env 0's four 640x480 views
// (TAVIS_RENDER_BENCH_TEXTURED_CONTACT_SHEET: the same views textured). Set
// TAVIS_RENDER_BENCH_IMAGE_HASH=1 to print a hash of every image of every env of the first two
// iterations (RGB, depth and object ids), so that two builds can be shown to draw the same pixels.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "render/batch_renderer.h"
#include "render/image_io.h"
#include "render/palette.h"

namespace tavis::render {
namespace {

constexpr int kEnvs = 16;
constexpr int kThreads = 2;
constexpr double kPi = 3.14159265358979323846;

RigidTransform At(const Vec3& p, const Mat3& R = Mat3::Identity()) { return MakeTransform(p, R); }

struct BenchScene {
  SceneLayout layout;
  std::vector<RigidTransform> X_WI;  // one env's nominal poses
  std::vector<int> jitter_scale;     // per instance: 0 static, 1 robot link, 2 object
  std::vector<std::string> looks;    // per instance: its palette name
  RigidTransform X_W_left_hand;
  RigidTransform X_W_right_hand;

  void Add(const ShapeGeometry& shape, const std::string& look, int32_t object_id, const RigidTransform& X,
           int jitter) {
    layout.instances.push_back({shape, PaletteAppearance(look), object_id});
    X_WI.push_back(X);
    jitter_scale.push_back(jitter);
    looks.push_back(look);
  }
  // A capsule link between two points.
  void AddLink(const Vec3& a, const Vec3& b, double radius, const std::string& look = "robot_link") {
    const Mat3 R = Quat::FromTwoVectors(Vec3::UnitZ(), b - a).toRotationMatrix();
    Add(MakeCapsule(radius, (b - a).norm()), look, kBackgroundObjectId, At(0.5 * (a + b), R), 1);
  }
};

// GR1T2's hand orientation at its rest pose (reference §6.1 teleop rest quaternion).
Mat3 RestHandRotation(double side) {
  return QuatFromWxyz(0.6401, -side * 0.00045, -0.7682, -side * 0.00857).normalized().toRotationMatrix();
}

// Reference §6.1 wrist-camera mount on the hand link.
RigidTransform WristCameraPose(const RigidTransform& X_W_hand) {
  return X_W_hand *
         At(Vec3(0.15, 0.0, 0.05), QuatFromWxyz(0.4617486, 0.0, 0.8870108, 0.0).normalized().toRotationMatrix());
}

BenchScene MakeBenchScene(int width, int height) {
  BenchScene scene;
  scene.Add(MakePlane(), "floor", kBackgroundObjectId, RigidTransform::Identity(), 0);
  scene.Add(MakeBox(Vec3(0.9, 1.2, 0.04)), "table", kBackgroundObjectId, At(Vec3(0.6, -0.1, 0.98)), 0);
  for (const double x : {0.2, 1.0}) {
    for (const double y : {-0.65, 0.45})
      scene.Add(MakeBox(Vec3(0.05, 0.05, 0.96)), "table", kBackgroundObjectId, At(Vec3(x, y, 0.48)), 0);
  }
  // Torso, neck, head.
  scene.Add(MakeBox(Vec3(0.18, 0.3, 0.42)), "robot_link", kBackgroundObjectId, At(Vec3(-0.06, 0.0, 1.15)), 0);
  scene.AddLink(Vec3(-0.04, 0.0, 1.36), Vec3(-0.04, 0.0, 1.42), 0.04);
  scene.Add(MakeSphere(0.09), "robot_link", kBackgroundObjectId, At(Vec3(-0.02, 0.0, 1.5)), 0);
  scene.Add(MakeCylinder(0.1, 0.12), "robot_link", kBackgroundObjectId, At(Vec3(-0.05, 0.0, 0.9)), 0);
  // Arms: shoulder, upper arm, elbow, forearm, wrist, hand, gripper (13 primitives each).
  for (const double side : {1.0, -1.0}) {
    const Vec3 shoulder(-0.03, 0.2 * side, 1.3);
    const Vec3 elbow(0.02, 0.26 * side, 1.06);
    const Vec3 wrist(0.22, 0.21 * side, 1.16);
    const RigidTransform X_W_hand = At(Vec3(0.3, 0.2 * side, 1.23), RestHandRotation(side));
    (side > 0 ? scene.X_W_left_hand : scene.X_W_right_hand) = X_W_hand;
    scene.Add(MakeSphere(0.055), "robot_link", kBackgroundObjectId, At(shoulder), 1);
    scene.AddLink(shoulder, shoulder + Vec3(0.0, 0.05 * side, -0.05), 0.045);
    scene.AddLink(shoulder + Vec3(0.0, 0.05 * side, -0.05), elbow, 0.04);
    scene.Add(MakeSphere(0.045), "robot_link", kBackgroundObjectId, At(elbow), 1);
    scene.AddLink(elbow, wrist, 0.035);
    scene.Add(MakeSphere(0.035), "robot_link", kBackgroundObjectId, At(wrist), 1);
    const Vec3 hand = X_W_hand.translation();
    scene.AddLink(wrist, hand, 0.03);
    // Gripper along the hand's approach axis (-z of the hand frame).
    auto in_hand = [&](const Vec3& p) { return X_W_hand * p; };
    const Mat3& R = X_W_hand.linear();
    scene.Add(MakeCylinder(0.035, 0.03), "robot_link", kBackgroundObjectId, At(in_hand(Vec3(0, 0, -0.01)), R), 1);
    scene.Add(MakeBox(Vec3(0.06, 0.09, 0.05)), "gripper", kBackgroundObjectId, At(in_hand(Vec3(0, 0, -0.05)), R), 1);
    for (const double finger : {1.0, -1.0}) {
      scene.Add(MakeBox(Vec3(0.02, 0.012, 0.06)), "gripper", kBackgroundObjectId,
                At(in_hand(Vec3(0, finger * 0.035, -0.105)), R), 1);
      scene.Add(MakeBox(Vec3(0.022, 0.006, 0.025)), "robot_link", kBackgroundObjectId,
                At(in_hand(Vec3(0, finger * 0.026, -0.125)), R), 1);
    }
  }
  // Objects at 0.75 x YCB size (reference §2.3) and the red cube.
  scene.Add(MakeCylinder(0.0248, 0.0758), "soup_can", 0, At(Vec3(0.32, 0.22, 1.0379)), 2);
  scene.Add(MakeBox(Vec3(0.0375, 0.0728, 0.0615)), "meat_can", 1, At(Vec3(0.45, 0.12, 1.0308)), 2);
  scene.Add(MakeCylinder(0.0319, 0.0248), "tuna_fish_can", 2, At(Vec3(0.38, 0.0, 1.0124)), 2);
  scene.Add(MakeBox(Vec3(0.021, 0.0638, 0.0548)), "gelatin_box", 3, At(Vec3(0.48, -0.12, 1.0274)), 2);
  scene.Add(MakeBox(Vec3(0.0263, 0.0825, 0.0668)), "pudding_box", 4, At(Vec3(0.34, -0.24, 1.0334)), 2);
  scene.Add(MakeBox(Vec3::Constant(0.055)), "red_cube", 5, At(Vec3(0.42, -0.02, 1.0275)), 2);

  scene.layout.cameras = {HeadCameraSpec(width, height), FixedCameraSpec(width, height),
                          WristCameraSpec("left_wrist", width, height), WristCameraSpec("right_wrist", width, height)};
  return scene;
}

// Per-tick inputs: the nominal poses moved by a small deterministic per-env, per-tick offset.
class BenchInputs {
 public:
  explicit BenchInputs(const BenchScene& scene)
      : scene_(scene), X_WI_(scene.X_WI.size() * kEnvs), X_WC_(scene.layout.cameras.size() * kEnvs) {}

  const RenderInputs& Update(int64_t tick) {
    const std::size_t n_instances = scene_.X_WI.size();
    for (int env = 0; env < kEnvs; ++env) {
      const double phase = 0.37 * static_cast<double>(tick) + 1.3 * env;
      const Vec3 object_shift(0.01 * std::sin(phase), 0.01 * std::cos(1.7 * phase), 0.0);
      const Vec3 link_shift(0.005 * std::cos(phase), 0.005 * std::sin(phase), 0.003 * std::sin(2.0 * phase));
      for (std::size_t i = 0; i < n_instances; ++i) {
        RigidTransform X = scene_.X_WI[i];
        const int jitter = scene_.jitter_scale[i];
        if (jitter == 1) X.pretranslate(link_shift);
        if (jitter == 2) X.pretranslate(object_shift).rotate(Eigen::AngleAxisd(0.2 * std::sin(phase), Vec3::UnitZ()));
        X_WI_[static_cast<std::size_t>(env) * n_instances + i] = X;
      }
      const Mat3 head =
          Eigen::AngleAxisd((45.0 + 3.0 * std::sin(phase)) * kPi / 180.0, Vec3::UnitY()).toRotationMatrix();
      RigidTransform* cameras = &X_WC_[static_cast<std::size_t>(env) * 4];
      cameras[0] = At(Vec3(0.105, 0.0, 1.454), head);
      cameras[1] = FixedCameraPose();
      cameras[2] = WristCameraPose(RigidTransform(scene_.X_W_left_hand).pretranslate(link_shift));
      cameras[3] = WristCameraPose(RigidTransform(scene_.X_W_right_hand).pretranslate(link_shift));
    }
    inputs_.X_WI = X_WI_;
    inputs_.X_WC = X_WC_;
    return inputs_;
  }

  void RenderOnly(const std::vector<uint8_t>& cameras) {
    render_camera_ = cameras;
    inputs_.render_camera = render_camera_;
  }

  // Textures on the floor, the table and the objects of every env (the Textured variants).
  void TextureFloorTableAndObjects() {
    textures_.clear();
    for (int env = 0; env < kEnvs; ++env) {
      for (std::size_t i = 0; i < scene_.looks.size(); ++i) textures_.push_back(BenchTexture(scene_, i));
    }
    inputs_.instance_texture = textures_;
  }

 private:
  static ProceduralTexture BenchTexture(const BenchScene& scene, std::size_t instance) {
    engine::SurfaceTexture texture;
    const std::string& look = scene.looks[instance];
    if (look == "floor") {
      texture.pattern = engine::TexturePattern::kNoise;
      texture.scale_m = 0.25;
      texture.colour_a = Eigen::Vector3f(0.10f, 0.12f, 0.10f);
      texture.colour_b = Eigen::Vector3f(0.35f, 0.30f, 0.22f);
    } else if (look == "table") {
      texture.pattern = engine::TexturePattern::kWood;
      texture.scale_m = 0.012;
      texture.turbulence = 1.2;
      texture.colour_a = Eigen::Vector3f(0.55f, 0.34f, 0.16f);
      texture.colour_b = Eigen::Vector3f(0.30f, 0.16f, 0.06f);
    } else if (scene.layout.instances[instance].object_id >= 0) {
      texture.pattern = engine::TexturePattern::kChecker;
      texture.scale_m = 0.01;
      texture.angle_deg = 30.0;
      texture.colour_a = Eigen::Vector3f(0.85f, 0.85f, 0.85f);
      texture.colour_b = Eigen::Vector3f(0.10f, 0.30f, 0.60f);
    }
    return MakeProceduralTexture(texture);
  }

  const BenchScene& scene_;
  std::vector<RigidTransform> X_WI_;
  std::vector<RigidTransform> X_WC_;
  std::vector<uint8_t> render_camera_;
  std::vector<ProceduralTexture> textures_;  // [env][instance], empty when untextured
  RenderInputs inputs_;
};

// TAVIS_RENDER_BENCH_CONTACT_SHEET (untextured) or TAVIS_RENDER_BENCH_TEXTURED_CONTACT_SHEET.
void WriteContactSheetIfRequested(const BenchScene& scene, BatchRenderer* renderer, BenchInputs* inputs,
                                  bool textured) {
  const char* path =
      std::getenv(textured ? "TAVIS_RENDER_BENCH_TEXTURED_CONTACT_SHEET" : "TAVIS_RENDER_BENCH_CONTACT_SHEET");
  if (path == nullptr) return;
  ImageBatch images = renderer->MakeImageBatch();
  renderer->Render(inputs->Update(0), &images);
  std::vector<LabelledImage> views;
  for (int c = 0; c < images.n_cameras(); ++c) {
    views.push_back(
        {scene.layout.cameras[static_cast<std::size_t>(c)].name, images.height(c), images.width(c), images.rgb(0, c)});
  }
  WritePng(path, MakeContactSheet(views));
}

// FNV-1a over bytes, continued from `hash`.
uint64_t HashBytes(const void* data, std::size_t size, uint64_t hash) {
  const auto* bytes = static_cast<const uint8_t*>(data);
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 0x100000001b3ull;
  return hash;
}

// With TAVIS_RENDER_BENCH_IMAGE_HASH set: one line per iteration with the hash of all its images.
void PrintImageHashIfRequested(const char* benchmark, const ImageBatch& images, int64_t tick) {
  if (std::getenv("TAVIS_RENDER_BENCH_IMAGE_HASH") == nullptr || tick >= 2) return;
  uint64_t hash = 0xcbf29ce484222325ull;
  for (int env = 0; env < images.num_envs(); ++env) {
    for (int c = 0; c < images.n_cameras(); ++c) {
      const std::size_t pixels = static_cast<std::size_t>(images.width(c)) * static_cast<std::size_t>(images.height(c));
      hash = HashBytes(images.rgb(env, c), 3 * pixels, hash);
      if (images.has_depth()) hash = HashBytes(images.depth(env, c), sizeof(float) * pixels, hash);
      if (images.has_object_id()) hash = HashBytes(images.object_id(env, c), sizeof(int32_t) * pixels, hash);
    }
  }
  std::printf("image hash %s tick %lld: %016llx\n", benchmark, static_cast<long long>(tick),
              static_cast<unsigned long long>(hash));
}

void RunRenderBenchmark(benchmark::State& state, const char* name, int resolution_width, int resolution_height,
                        const std::vector<uint8_t>& cameras, bool textured = false) {
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, kThreads);
  const BenchScene scene = MakeBenchScene(resolution_width, resolution_height);
  BatchRenderer renderer(scene.layout, kEnvs);
  ImageBatch images = renderer.MakeImageBatch();
  BenchInputs inputs(scene);
  if (textured) inputs.TextureFloorTableAndObjects();
  if (resolution_width == 640 && cameras.size() == 4) WriteContactSheetIfRequested(scene, &renderer, &inputs, textured);
  inputs.RenderOnly(cameras);

  int64_t tick = 0;
  int64_t rays = 0;
  int64_t primary_only_rays = 0;
  double full_seconds = 0.0;
  double primary_only_seconds = 0.0;
  using Clock = std::chrono::steady_clock;
  for (auto _ : state) {
    const auto full_start = Clock::now();
    const RenderStats stats = renderer.Render(inputs.Update(tick), &images);
    full_seconds += std::chrono::duration<double>(Clock::now() - full_start).count();
    benchmark::DoNotOptimize(images.rgb(0, 0));
    PrintImageHashIfRequested(name, images, tick);
    rays += stats.primary_rays + stats.shadow_rays;

    state.PauseTiming();
    const auto primary_start = Clock::now();
    const RenderStats primary = renderer.CastPrimaryRaysOnly(inputs.Update(tick));
    primary_only_seconds += std::chrono::duration<double>(Clock::now() - primary_start).count();
    primary_only_rays += primary.primary_rays;
    benchmark::DoNotOptimize(primary.primary_hits);
    state.ResumeTiming();
    ++tick;
  }
  const double iterations = static_cast<double>(state.iterations());
  state.counters["env_steps_per_s"] = benchmark::Counter(kEnvs * iterations, benchmark::Counter::kIsRate);
  state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
  state.counters["primary_only_env_steps_per_s"] = kEnvs * iterations / primary_only_seconds;
  state.counters["primary_only_rays_per_s"] = static_cast<double>(primary_only_rays) / primary_only_seconds;
  state.counters["shading_ratio"] = full_seconds / primary_only_seconds;
}

// (a) all four cameras at 640x480.
void BM_FourCameras640x480(benchmark::State& state) { RunRenderBenchmark(state, "640x480", 640, 480, {1, 1, 1, 1}); }
// (b) head and both wrists at 224x224 (the policy's cameras in head mode).
void BM_HeadAndWrists224x224(benchmark::State& state) { RunRenderBenchmark(state, "224x224", 224, 224, {1, 0, 1, 1}); }

// (c), (d) the same with textures on the floor, the table and the objects.
void BM_FourCameras640x480Textured(benchmark::State& state) {
  RunRenderBenchmark(state, "640x480 textured", 640, 480, {1, 1, 1, 1}, true);
}
void BM_HeadAndWrists224x224Textured(benchmark::State& state) {
  RunRenderBenchmark(state, "224x224 textured", 224, 224, {1, 0, 1, 1}, true);
}

BENCHMARK(BM_FourCameras640x480)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_HeadAndWrists224x224)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_FourCameras640x480Textured)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_HeadAndWrists224x224Textured)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

}  // namespace
}  // namespace tavis::render
