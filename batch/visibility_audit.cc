#include "batch/visibility_audit.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "batch/scene_render.h"
#include "batch/vec_env.h"
#include "configs/robot_config.h"
#include "kinematics/forward_kinematics.h"
#include "render/batch_renderer.h"
#include "scenarios/registry.h"

namespace tavis::batch {
namespace {

// The cues a task's information sits in besides the target, by model name.
std::vector<std::string> AuditedCues(const std::string& task) {
  if (task == "conditional-pick") return {"cue_card"};
  if (task == "wait-then-act") return {"signal_light"};
  return {};
}

// Counts, per env and camera, the pixels of one object in the full scene and in a scene holding
// that object alone. The full scene is the policy's (SceneRender, black cameras blocked); the
// lone object is drawn by a second renderer whose layout keeps only the full scene's objects,
// with every object but the measured one hidden.
class VisibilityMeter {
 public:
  VisibilityMeter(const engine::WorldModel& model, const std::vector<std::string>& black_cameras, int num_envs,
                  int width, int height)
      : robot_(model.robot), num_envs_(num_envs), scene_(model, num_envs, IdCameras(width, height)) {
    for (const std::string& name : black_cameras) {
      for (int env = 0; env < num_envs; ++env) scene_.SetCameraEnabled(env, scene_.CameraIndex(name), false);
    }
    render::SceneLayout alone;
    alone.cameras = scene_.layout().cameras;
    for (const render::InstanceSpec& instance : scene_.layout().instances) {
      if (instance.object_id != render::kBackgroundObjectId) alone.instances.push_back(instance);  // id = index
    }
    alone.lighting.shadows = false;  // only the ids are read
    render::RenderOptions options;
    options.with_object_id = true;
    alone_ = std::make_unique<render::BatchRenderer>(alone, num_envs, options);
    alone_images_ = std::make_unique<render::ImageBatch>(alone_->MakeImageBatch());
    for (const std::string& name : scene_.settings().cameras) {
      const auto mount = std::find_if(robot_.cameras.begin(), robot_.cameras.end(),
                                      [&](const kinematics::CameraMount& camera) { return camera.name == name; });
      camera_mount_.push_back(mount == robot_.cameras.end() ? -1 : static_cast<int>(mount - robot_.cameras.begin()));
    }
    const std::size_t envs = static_cast<std::size_t>(num_envs);
    X_BL_.resize(envs * static_cast<std::size_t>(robot_.num_links()));
    X_WI_.assign(envs * alone.instances.size(), RigidTransform::Identity());
    visible_.assign(envs * alone.instances.size(), 0);
    X_WC_.assign(envs * camera_mount_.size(), RigidTransform::Identity());
    enabled_.assign(envs * camera_mount_.size(), 0);
    render_env_.assign(envs, 0);
  }

  int num_cameras() const { return scene_.num_cameras(); }

  // For every env with object[env] >= 0: the fraction of that object's own pixels visible in each
  // camera, written to fractions[env * num_cameras() + camera] (0 where it has none).
  void Measure(const engine::BatchState& state, const std::vector<int>& object, std::vector<double>& fractions) {
    for (int env = 0; env < num_envs_; ++env) render_env_[env] = object[env] >= 0 ? 1 : 0;
    scene_.Render(state, render_env_.data());
    const int objects = state.num_objects;
    const int cameras = num_cameras();
    tbb::parallel_for(0, num_envs_, [&](int env) {
      const std::size_t first = static_cast<std::size_t>(env) * static_cast<std::size_t>(objects);
      for (int i = 0; i < objects; ++i) visible_[first + i] = i == object[env] && state.object_enabled_at(env, i);
      for (int c = 0; c < cameras; ++c) enabled_[env * cameras + c] = object[env] >= 0 && scene_.camera_enabled(env, c);
      if (object[env] < 0) return;
      const double* pose = state.object_pose_row(env, object[env]);
      X_WI_[first + object[env]] = MakeTransform(Vec3(pose[0], pose[1], pose[2]),
                                                 Quat(pose[3], pose[4], pose[5], pose[6]).normalized().toRotationMatrix());
      PlaceCameras(state, env);
    });
    render::RenderInputs inputs;
    inputs.X_WI = X_WI_;
    inputs.instance_visible = visible_;
    inputs.X_WC = X_WC_;
    inputs.camera_enabled = enabled_;
    alone_->Render(inputs, alone_images_.get());
    tbb::parallel_for(0, num_envs_, [&](int env) {
      if (object[env] < 0) return;
      for (int c = 0; c < cameras; ++c) {
        const int64_t seen = CountPixels(scene_.images(), env, c, object[env]);
        const int64_t own = CountPixels(*alone_images_, env, c, object[env]);
        fractions[env * cameras + c] = own > 0 ? static_cast<double>(seen) / static_cast<double>(own) : 0.0;
      }
    });
  }

 private:
  static CameraSettings IdCameras(int width, int height) {
    CameraSettings settings;
    settings.cameras = SceneCameraNames();
    settings.width = width;
    settings.height = height;
    settings.with_object_id = true;
    return settings;
  }

  static int64_t CountPixels(const render::ImageBatch& images, int env, int camera, int object) {
    const int32_t* ids = images.object_id(env, camera);
    return std::count(ids, ids + static_cast<std::ptrdiff_t>(images.width(camera)) * images.height(camera), object);
  }

  // The cameras' world poses as SceneRender places them: robot mounts by forward kinematics of
  // the measured joints from the base at root_world, the fixed camera at its own pose.
  void PlaceCameras(const engine::BatchState& state, int env) {
    RigidTransform* X_BL = &X_BL_[static_cast<std::size_t>(env) * static_cast<std::size_t>(robot_.num_links())];
    kinematics::ComputeLinkPoses(robot_, state.q_row(env), X_BL);
    const RigidTransform X_WB = MakeTransform(robot_.root_world, Mat3::Identity());
    for (int c = 0; c < num_cameras(); ++c) {
      const int mount = camera_mount_[static_cast<std::size_t>(c)];
      X_WC_[env * num_cameras() + c] = mount < 0 ? render::FixedCameraPose() : X_WB * kinematics::CameraPose(robot_, mount, X_BL);
    }
  }

  const kinematics::RobotModel& robot_;
  int num_envs_ = 0;
  SceneRender scene_;
  std::unique_ptr<render::BatchRenderer> alone_;
  std::unique_ptr<render::ImageBatch> alone_images_;
  std::vector<int> camera_mount_;  // [camera]: robot camera index, -1 for the fixed camera
  std::vector<RigidTransform> X_BL_;   // [env][link]
  std::vector<RigidTransform> X_WI_;   // [env][object]
  std::vector<uint8_t> visible_;       // [env][object]
  std::vector<RigidTransform> X_WC_;   // [env][camera]
  std::vector<uint8_t> enabled_;       // [env][camera]
  std::vector<uint8_t> render_env_;    // [env]
};

// Episodes in which the object reaches kVisibleFraction in the camera; `moment` gives an
// episode's fractions, or null when they were never measured.
template <typename Moment>
int CountVisible(const AuditResult& result, int object, int camera, Moment moment) {
  return static_cast<int>(std::count_if(result.episodes.begin(), result.episodes.end(), [&](const EpisodeAudit& episode) {
    const CameraFractions* fractions = moment(episode.objects[static_cast<std::size_t>(object)]);
    return fractions != nullptr && (*fractions)[static_cast<std::size_t>(camera)] >= kVisibleFraction;
  }));
}

}  // namespace

int AuditResult::VisibleAtReset(int object, int camera) const {
  return CountVisible(*this, object, camera, [](const ObjectAudit& audit) { return &audit.at_reset; });
}

int AuditResult::VisibleAtFixation(int object, int camera) const {
  return CountVisible(*this, object, camera, [](const ObjectAudit& audit) {
    return audit.at_fixation ? &*audit.at_fixation : nullptr;
  });
}

int AuditResult::Fixated(int object) const {
  return static_cast<int>(std::count_if(episodes.begin(), episodes.end(), [&](const EpisodeAudit& episode) {
    return episode.objects[static_cast<std::size_t>(object)].at_fixation.has_value();
  }));
}

AuditResult RunVisibilityAudit(const AuditConfig& config, const ProgressCallback& progress) {
  if (config.episodes < 1) throw std::invalid_argument("--episodes must be at least 1, got " + std::to_string(config.episodes));
  if (config.envs < 1) throw std::invalid_argument("--envs must be at least 1, got " + std::to_string(config.envs));
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario(config.task);
  if (scenario.make_expert == nullptr) throw std::invalid_argument("task '" + config.task + "' has no scripted expert to audit");
  const kinematics::RobotModel robot = configs::LoadRobotModel(configs::RobotConfigPath(config.config_dir, config.robot));
  const auto start = std::chrono::steady_clock::now();

  const int slots = std::min(config.envs, config.episodes);
  VecEnv env(BuildWorldModel(robot, scenario), scenario, config.split, slots, config.seed);
  std::unique_ptr<scenarios::Expert> expert = scenario.make_expert(env.model(), slots);
  VisibilityMeter meter(env.model(), scenario.black_cameras, slots, config.image_width, config.image_height);
  const engine::BatchState& state = env.state();

  AuditResult result;
  result.config = config;
  result.cameras = SceneCameraNames();
  result.objects = {"target"};
  std::vector<int> cue_index;
  for (const std::string& cue : AuditedCues(config.task)) {
    result.objects.push_back(cue);
    cue_index.push_back(env.model().ObjectIndex(cue));
  }
  const int num_audited = static_cast<int>(result.objects.size());
  result.episodes.resize(static_cast<std::size_t>(config.episodes));
  for (std::size_t i = 0; i < result.episodes.size(); ++i) {
    result.episodes[i].episode = static_cast<int64_t>(i);
    result.episodes[i].objects.resize(static_cast<std::size_t>(num_audited));
  }
  auto object_of = [&](int audited, int slot) {
    return audited == 0 ? state.target(slot) : cue_index[audited - 1];
  };

  // Measures audited object `audited` in the flagged slots, at reset or at its fixation.
  std::vector<int> measured(static_cast<std::size_t>(slots));
  std::vector<double> fractions(static_cast<std::size_t>(slots * meter.num_cameras()));
  auto sample = [&](int audited, const std::vector<uint8_t>& flags, bool at_fixation) {
    if (std::find(flags.begin(), flags.end(), 1) == flags.end()) return;
    for (int slot = 0; slot < slots; ++slot) measured[slot] = flags[slot] ? object_of(audited, slot) : -1;
    meter.Measure(state, measured, fractions);
    for (int slot = 0; slot < slots; ++slot) {
      if (!flags[slot]) continue;
      ObjectAudit& audit = result.episodes[static_cast<std::size_t>(state.episode[slot])].objects[audited];
      const auto first = fractions.begin() + slot * meter.num_cameras();
      const CameraFractions seen(first, first + meter.num_cameras());
      if (!at_fixation) {
        audit.at_reset = seen;
        continue;
      }
      audit.at_fixation = seen;
      audit.fixation_tick = state.control_step[slot];
    }
  };

  EpisodeDealer dealer(config.episodes);
  std::vector<uint8_t> fresh(static_cast<std::size_t>(slots), 0);  // dealt, not yet measured at reset
  std::vector<uint32_t> pending(static_cast<std::size_t>(slots), 0);  // audited objects still to fixate, as bits
  auto start_episode = [&](int slot) {
    if (!dealer.Deal(env, slot)) return;
    expert->Reset(env.model(), state, slot);
    fresh[slot] = 1;
    pending[slot] = (1u << num_audited) - 1u;
  };
  for (int slot = 0; slot < slots; ++slot) start_episode(slot);

  std::vector<kinematics::Action> actions(static_cast<std::size_t>(slots));
  std::vector<std::vector<uint8_t>> fixating(static_cast<std::size_t>(num_audited), std::vector<uint8_t>(slots, 0));
  int finished = 0;
  auto running = [&](int slot) { return state.episode[slot] >= 0 && state.end[slot] == engine::EpisodeEnd::kRunning; };
  while (finished < config.episodes) {
    for (int audited = 0; audited < num_audited; ++audited) sample(audited, fresh, false);
    std::fill(fresh.begin(), fresh.end(), 0);
    tbb::parallel_for(0, slots, [&](int slot) {
      if (running(slot)) expert->Act(env.model(), state, slot, actions[slot]);
    });
    env.Step(actions);
    // The gaze is read after the expert has acted and the world has moved: the fixation is the
    // first tick whose state the expert reports its gaze settled on the object in.
    tbb::parallel_for(0, slots, [&](int slot) {
      const scenarios::Expert::Gaze gaze = running(slot) ? expert->gaze(state, slot) : scenarios::Expert::Gaze{};
      for (int audited = 0; audited < num_audited; ++audited) {
        fixating[audited][slot] = (pending[slot] >> audited & 1u) && gaze.settled && gaze.object == object_of(audited, slot);
      }
    });
    for (int audited = 0; audited < num_audited; ++audited) {
      sample(audited, fixating[audited], true);
      for (int slot = 0; slot < slots; ++slot) {
        if (fixating[audited][slot]) pending[slot] &= ~(1u << audited);
      }
    }
    // Serial, in slot order: an episode is done once every audited object has been sampled or it
    // has ended; its slot is refilled deterministically.
    for (int slot = 0; slot < slots; ++slot) {
      if (state.episode[slot] < 0 || (running(slot) && pending[slot] != 0)) continue;
      ++finished;
      if (progress) progress(finished, config.episodes);
      start_episode(slot);
    }
  }
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace tavis::batch
