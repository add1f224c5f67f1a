// Side-by-side peer benchmark: our engine and renderer against MuJoCo 2.2 (Debian) on the same
// GR1T2 clutter-pick-cube scene, in one run.
//
// 1. Records `--envs` scripted-expert episodes with our engine (joint targets after IK and gripper
//    commands per 60 Hz control tick, `--ticks` ticks, holding the last command after an episode
//    ends).
// 2. Physics: replays those commands in both engines over the batch of envs on `--threads`
//    threads (one world per env; 180 Hz steps, 3 per control tick). Ours is engine::PhysicsWorld,
//    the code path VecEnv steps; MuJoCo's model is built from the same WorldModel
//    (bench/peer/mujoco_physics.cc), stepped with its default (dense) and sparse Jacobians.
// 3. Rendering: the states of our replay at `--frames` sample ticks, rendered by our SceneRender
//    (4 cameras at 640x480, then head and wrists at 224x224, shadows on) and by MuJoCo's OpenGL
//    renderer through OSMesa posed from exactly the same instance and camera poses, with and
//    without its shadow map. Env 0's images of the last frame go to --out as PNG contact sheets.
// Rounds alternate the engines (the machine may be loaded); the table gives medians and ratios.
//
// Run: bench/peer/run.sh (installs MuJoCo and OSMesa, builds with -DTAVIS_BUILD_PEER_BENCH=ON).
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "batch/scene_render.h"
#include "bench/peer/expert_trajectories.h"
#include "bench/peer/mujoco_physics.h"
#include "bench/peer/mujoco_renderer.h"
#include "engine/physics_world.h"
#include "render/image_batch.h"
#include "render/image_io.h"

namespace tavis::peer {
namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  int envs = 16;
  int ticks = 600;
  int threads = 2;
  int rounds = 3;
  int frames = 8;
  std::string out = "peer_results";
  std::string config_dir = TAVIS_CONFIG_DIR;
};

int PositiveInt(const std::string& flag, const char* text) {
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || value <= 0 || value > 1000000) {
    throw std::invalid_argument(flag + " = '" + text + "' must be a positive integer");
  }
  return static_cast<int>(value);
}

Options ParseOptions(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) throw std::invalid_argument(flag + " needs a value");
    const char* value = argv[++i];
    if (flag == "--envs")
      options.envs = PositiveInt(flag, value);
    else if (flag == "--ticks")
      options.ticks = PositiveInt(flag, value);
    else if (flag == "--threads")
      options.threads = PositiveInt(flag, value);
    else if (flag == "--rounds")
      options.rounds = PositiveInt(flag, value);
    else if (flag == "--frames")
      options.frames = PositiveInt(flag, value);
    else if (flag == "--out")
      options.out = value;
    else if (flag == "--config-dir")
      options.config_dir = value;
    else
      throw std::invalid_argument("unknown option '" + flag +
                                  "' (known: --envs --ticks --threads --rounds --frames --out --config-dir)");
  }
  return options;
}

double Seconds(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

int CubeIndex(const engine::WorldModel& model) {
  for (int o = 0; o < model.num_objects(); ++o) {
    if (model.objects[static_cast<std::size_t>(o)].name.find("cube") != std::string::npos) return o;
  }
  return 0;
}

// Our physics: one PhysicsWorld per env, replaying the recorded commands; returns seconds and
// fills the final cube heights. `states` (optional) receives the BatchState rows at the sample
// ticks for rendering.
double RunOurPhysics(const ExpertTrajectories& trajectories, std::vector<std::unique_ptr<engine::PhysicsWorld>>& worlds,
                     std::vector<double>* cube_z, std::vector<engine::BatchState>* samples, int frames) {
  const engine::WorldModel& model = trajectories.model;
  const int envs = static_cast<int>(trajectories.episodes.size());
  const int nj = model.robot.num_joints();
  const int no = model.num_objects();
  const int substeps = model.physics.substeps_per_control();
  const int cube = CubeIndex(model);
  const auto start = Clock::now();
  tbb::parallel_for(0, envs, [&](int env) {
    const EpisodeTrajectory& episode = trajectories.episodes[static_cast<std::size_t>(env)];
    engine::PhysicsWorld& world = *worlds[static_cast<std::size_t>(env)];
    world.ResetRobot(episode.q0.data());
    for (int o = 0; o < no; ++o) {
      const double* pose = &episode.object_pose0[static_cast<std::size_t>(o) * engine::kObjectPoseSize];
      world.SetObject(o, Vec3(pose[0], pose[1], pose[2]), Quat(pose[3], pose[4], pose[5], pose[6]),
                      episode.object_enabled[static_cast<std::size_t>(o)] != 0);
    }
    std::vector<double> q(episode.q0);
    std::vector<double> object_pose(static_cast<std::size_t>(no) * engine::kObjectPoseSize);
    std::vector<double> object_velocity(static_cast<std::size_t>(no) * engine::kObjectVelocitySize);
    double gap[2] = {0.0, 0.0};
    for (int tick = 0; tick < trajectories.ticks; ++tick) {
      const std::size_t row = static_cast<std::size_t>(tick);
      world.Step(&episode.q_target[row * static_cast<std::size_t>(nj)],
                 {episode.gripper_command[2 * row], episode.gripper_command[2 * row + 1]}, substeps);
      world.ReadState(q.data(), gap, object_pose.data(), object_velocity.data());
      const int every = std::max(1, trajectories.ticks / frames);
      if (samples != nullptr && (tick + 1) % every == 0 && (tick + 1) / every <= frames) {
        engine::BatchState& state = (*samples)[static_cast<std::size_t>((tick + 1) / every - 1)];
        std::copy(q.begin(), q.end(), state.q_row(env));
        // The neck is not simulated: it holds the episode's recorded target.
        for (int j : model.robot.neck_joints) {
          state.q_row(env)[j] = episode.q_target[row * static_cast<std::size_t>(nj) + static_cast<std::size_t>(j)];
        }
        std::copy(gap, gap + 2, state.gripper_gap_row(env));
        std::copy(object_pose.begin(), object_pose.end(), state.object_pose_row(env, 0));
        for (int o = 0; o < no; ++o) {
          state.object_enabled[static_cast<std::size_t>(env * no + o)] =
              episode.object_enabled[static_cast<std::size_t>(o)];
        }
      }
    }
    (*cube_z)[static_cast<std::size_t>(env)] =
        object_pose[static_cast<std::size_t>(cube) * engine::kObjectPoseSize + 2];
  });
  return Seconds(start);
}

double RunMujocoPhysics(const ExpertTrajectories& trajectories, MujocoPhysics& physics, std::vector<double>* cube_z) {
  const int envs = static_cast<int>(trajectories.episodes.size());
  const int cube = CubeIndex(trajectories.model);
  const auto start = Clock::now();
  tbb::parallel_for(0, envs, [&](int env) {
    const EpisodeTrajectory& episode = trajectories.episodes[static_cast<std::size_t>(env)];
    physics.Reset(env, episode);
    for (int tick = 0; tick < trajectories.ticks; ++tick) physics.StepTick(env, episode, tick);
    double xyz[3];
    physics.ObjectPosition(env, cube, xyz);
    (*cube_z)[static_cast<std::size_t>(env)] = xyz[2];
  });
  return Seconds(start);
}

struct RenderConfig {
  std::string name;
  std::vector<std::string> cameras;
  int width = 0;
  int height = 0;
};

struct Row {
  std::string what;
  std::string unit;
  double ours = 0.0;
  double mujoco = 0.0;
  std::string mujoco_setting;
};

void WriteSheet(const std::string& path, const std::vector<std::string>& names, const std::vector<const uint8_t*>& rgb,
                int width, int height) {
  std::vector<render::LabelledImage> views;
  for (std::size_t c = 0; c < names.size(); ++c) views.push_back({names[c], height, width, rgb[c]});
  render::WritePng(path, render::MakeContactSheet(views));
}

std::vector<Row> RunRendering(const Options& options, const engine::WorldModel& model,
                              const std::vector<engine::BatchState>& samples, const RenderConfig& config) {
  batch::CameraSettings settings;
  settings.cameras = config.cameras;
  settings.width = config.width;
  settings.height = config.height;
  batch::SceneRender ours(model, options.envs, settings);
  MujocoRenderer mujoco_shadows(ours.layout(), true);
  MujocoRenderer mujoco_plain(ours.layout(), false);
  std::ofstream(options.out + "/mujoco_render_" + config.name + ".xml") << mujoco_shadows.mjcf();
  const std::vector<uint8_t> all(static_cast<std::size_t>(options.envs), 1);
  const int n_cameras = static_cast<int>(config.cameras.size());
  std::vector<RigidTransform> X_WI(ours.layout().instances.size() * static_cast<std::size_t>(options.envs));
  std::vector<RigidTransform> X_WC(config.cameras.size() * static_cast<std::size_t>(options.envs));
  // SceneRender's instance order: floor, static parts, objects, robot; only objects can be hidden.
  const std::size_t n_instances = ours.layout().instances.size();
  const std::size_t first_object = 1 + model.static_parts.size();
  std::vector<uint8_t> visible(n_instances * static_cast<std::size_t>(options.envs), 1);
  std::vector<double> ours_rates, shadow_rates, plain_rates;
  for (int round = 0; round < options.rounds; ++round) {
    double ours_s = 0.0, shadow_s = 0.0, plain_s = 0.0;
    for (const engine::BatchState& state : samples) {
      auto start = Clock::now();
      ours.Render(state, all.data());
      ours_s += Seconds(start);
      for (int env = 0; env < options.envs; ++env) {
        std::copy(ours.instance_poses(env), ours.instance_poses(env) + ours.layout().instances.size(),
                  X_WI.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(env) * n_instances));
        std::copy(ours.camera_poses(env), ours.camera_poses(env) + n_cameras, X_WC.begin() + env * n_cameras);
        for (int o = 0; o < model.num_objects(); ++o) {
          visible[static_cast<std::size_t>(env) * n_instances + first_object + static_cast<std::size_t>(o)] =
              state.object_enabled[static_cast<std::size_t>(env * model.num_objects() + o)];
        }
      }
      for (MujocoRenderer* renderer : {&mujoco_shadows, &mujoco_plain}) {
        start = Clock::now();
        for (int env = 0; env < options.envs; ++env) {
          renderer->Render(&X_WI[static_cast<std::size_t>(env) * n_instances],
                           &X_WC[static_cast<std::size_t>(env * n_cameras)],
                           &visible[static_cast<std::size_t>(env) * n_instances]);
        }
        (renderer == &mujoco_shadows ? shadow_s : plain_s) += Seconds(start);
      }
    }
    const double env_steps = static_cast<double>(samples.size()) * options.envs;
    ours_rates.push_back(env_steps / ours_s);
    shadow_rates.push_back(env_steps / shadow_s);
    plain_rates.push_back(env_steps / plain_s);
  }
  // Env 0 of the last frame: MuJoCo's renderer still holds env options.envs-1, so render env 0 again.
  mujoco_shadows.Render(&X_WI[0], &X_WC[0], &visible[0]);
  std::vector<const uint8_t*> ours_rgb, mujoco_rgb;
  for (int c = 0; c < n_cameras; ++c) {
    ours_rgb.push_back(ours.images().rgb(0, c));
    mujoco_rgb.push_back(mujoco_shadows.image(c).data());
  }
  WriteSheet(options.out + "/ours_" + config.name + ".png", config.cameras, ours_rgb, config.width, config.height);
  WriteSheet(options.out + "/mujoco_" + config.name + ".png", config.cameras, mujoco_rgb, config.width, config.height);
  const std::string what =
      std::to_string(n_cameras) + " x " + std::to_string(config.width) + "x" + std::to_string(config.height);
  return {{what + ", shadows", "env-steps/s", Median(ours_rates), Median(shadow_rates), "OSMesa llvmpipe, shadow map"},
          {what + ", ours shadows vs MuJoCo none", "env-steps/s", Median(ours_rates), Median(plain_rates),
           "OSMesa llvmpipe, no shadows"}};
}

int Main(int argc, char** argv) {
  const Options options = ParseOptions(argc, argv);
  std::filesystem::create_directories(options.out);
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                    static_cast<std::size_t>(options.threads));

  auto start = Clock::now();
  const ExpertTrajectories trajectories =
      RecordExpertTrajectories(options.config_dir, "clutter-pick-cube", "gr1t2", options.envs, options.ticks);
  int successes = 0;
  for (const EpisodeTrajectory& e : trajectories.episodes) successes += e.success ? 1 : 0;
  std::printf("recorded %d expert episodes x %d ticks in %.1f s (%d successes)\n", options.envs, options.ticks,
              Seconds(start), successes);
  const engine::WorldModel& model = trajectories.model;
  std::ofstream(options.out + "/mujoco_physics.xml") << PhysicsMjcf(model, false);

  std::vector<std::unique_ptr<engine::PhysicsWorld>> worlds;
  for (int e = 0; e < options.envs; ++e) worlds.push_back(std::make_unique<engine::PhysicsWorld>(model));
  MujocoPhysics mujoco_dense(model, options.envs, false);
  MujocoPhysics mujoco_sparse(model, options.envs, true);
  std::vector<engine::BatchState> samples(static_cast<std::size_t>(options.frames));
  for (engine::BatchState& s : samples) {
    s.Allocate(options.envs, model.robot.num_joints(), model.num_objects());
    std::fill(s.object_rgb.begin(), s.object_rgb.end(), -1.0f);
  }
  std::vector<double> ours_z(static_cast<std::size_t>(options.envs)), dense_z(ours_z), sparse_z(ours_z);
  std::vector<double> ours_rate, dense_rate, sparse_rate;
  const double ticks = static_cast<double>(options.envs) * options.ticks;
  for (int round = 0; round < options.rounds; ++round) {
    ours_rate.push_back(ticks /
                        RunOurPhysics(trajectories, worlds, &ours_z, round == 0 ? &samples : nullptr, options.frames));
    dense_rate.push_back(ticks / RunMujocoPhysics(trajectories, mujoco_dense, &dense_z));
    sparse_rate.push_back(ticks / RunMujocoPhysics(trajectories, mujoco_sparse, &sparse_z));
    std::printf("physics round %d: ours %.0f, MuJoCo dense %.0f, sparse %.0f control ticks/s\n", round,
                ours_rate.back(), dense_rate.back(), sparse_rate.back());
  }
  auto lifted = [](const std::vector<double>& z) {
    int n = 0;
    for (double v : z) n += v > 1.1 ? 1 : 0;  // cube above the table top (about 1.03 m at rest)
    return n;
  };
  std::printf("cube lifted at the end (z > 1.1 m): ours %d/%d, MuJoCo dense %d, sparse %d\n", lifted(ours_z),
              options.envs, lifted(dense_z), lifted(sparse_z));

  std::vector<Row> rows = {{"physics, " + std::to_string(options.envs) + " envs", "control ticks/s", Median(ours_rate),
                            Median(dense_rate), "default (dense Jacobian)"},
                           {"physics, " + std::to_string(options.envs) + " envs", "control ticks/s", Median(ours_rate),
                            Median(sparse_rate), "jacobian=\"sparse\""}};
  for (const RenderConfig& config :
       {RenderConfig{"4cam_640x480", {"head", "fixed", "left_wrist", "right_wrist"}, 640, 480},
        RenderConfig{"3cam_224x224", {"head", "left_wrist", "right_wrist"}, 224, 224}}) {
    for (const Row& row : RunRendering(options, model, samples, config)) rows.push_back(row);
  }

  std::ostringstream table;
  table << "| measure | unit | ours | MuJoCo 2.2.2 | ours / MuJoCo | MuJoCo setting |\n|---|---|---|---|---|---|\n";
  for (const Row& row : rows) {
    char line[512];
    std::snprintf(line, sizeof(line), "| %s | %s | %.1f | %.1f | %.2fx | %s |\n", row.what.c_str(), row.unit.c_str(),
                  row.ours, row.mujoco, row.ours / row.mujoco, row.mujoco_setting.c_str());
    table << line;
  }
  std::printf("\n%s\n(%d threads, medians of %d rounds; images and MJCF in %s)\n", table.str().c_str(), options.threads,
              options.rounds, options.out.c_str());
  std::ofstream(options.out + "/peer_table.md") << table.str();
  return 0;
}

}  // namespace
}  // namespace tavis::peer

int main(int argc, char** argv) {
  try {
    return tavis::peer::Main(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "tavis_peer_bench: %s\n", error.what());
    return 1;
  }
}
