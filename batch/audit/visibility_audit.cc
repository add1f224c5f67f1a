#include "batch/audit/visibility_audit.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <utility>

#include <tbb/parallel_for.h>

#include "batch/builtin_policies.h"
#include "batch/episode_driver.h"
#include "batch/scene/scene_plan.h"
#include "batch/scene_render.h"
#include "batch/vec_env.h"
#include "kinematics/forward_kinematics.h"
#include "render/batch_renderer.h"
#include "scenarios/registry.h"

namespace tavis::batch::audit {
namespace {

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
      X_WI_[first + object[env]] = MakeTransform(
          Vec3(pose[0], pose[1], pose[2]), Quat(pose[3], pose[4], pose[5], pose[6]).normalized().toRotationMatrix());
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
      X_WC_[env * num_cameras() + c] =
          mount < 0 ? render::FixedCameraPose() : X_WB * kinematics::CameraPose(robot_, mount, X_BL);
    }
  }

  const kinematics::RobotModel& robot_;
  int num_envs_ = 0;
  SceneRender scene_;
  std::unique_ptr<render::BatchRenderer> alone_;
  std::unique_ptr<render::ImageBatch> alone_images_;
  std::vector<int> camera_mount_;     // [camera]: robot camera index, -1 for the fixed camera
  std::vector<RigidTransform> X_BL_;  // [env][link]
  std::vector<RigidTransform> X_WI_;  // [env][object]
  std::vector<uint8_t> visible_;      // [env][object]
  std::vector<RigidTransform> X_WC_;  // [env][camera]
  std::vector<uint8_t> enabled_;      // [env][camera]
  std::vector<uint8_t> render_env_;   // [env]
};

// Episodes in which the object reaches kVisibleFraction in the camera; `moment` gives an
// episode's fractions, or null when they were never measured.
template <typename Moment>
int CountVisible(const AuditResult& result, int object, int camera, Moment moment) {
  return static_cast<int>(
      std::count_if(result.episodes.begin(), result.episodes.end(), [&](const EpisodeAudit& episode) {
        const CameraFractions* fractions = moment(episode.objects[static_cast<std::size_t>(object)]);
        return fractions != nullptr && (*fractions)[static_cast<std::size_t>(camera)] >= kVisibleFraction;
      }));
}

// Samples each audited object's visibility at the episode's reset and at the expert's first
// settled fixation of it; an episode is complete once every audited object has been sampled.
class AuditSink : public EpisodeSink {
 public:
  AuditSink(const VecEnv& vec_env, const ExpertPolicy& policy, const AuditConfig& config, AuditResult& result)
      : expert_(policy.expert()),
        meter_(vec_env.model(), vec_env.scenario().black_cameras, vec_env.num_envs(), config.image_width,
               config.image_height),
        result_(result) {
    const int slots = vec_env.num_envs();
    for (const std::string& cue : vec_env.scenario().cue_objects)
      cue_index_.push_back(vec_env.model().ObjectIndex(cue));
    num_audited_ = 1 + static_cast<int>(cue_index_.size());
    measured_.assign(static_cast<std::size_t>(slots), -1);
    fractions_.assign(static_cast<std::size_t>(slots * meter_.num_cameras()), 0.0);
    fresh_.assign(static_cast<std::size_t>(slots), 0);
    pending_.assign(static_cast<std::size_t>(slots), 0);
    fixating_.assign(static_cast<std::size_t>(num_audited_), std::vector<uint8_t>(static_cast<std::size_t>(slots), 0));
  }

  void EpisodeStarted(const VecEnv&, int slot) override {
    fresh_[slot] = 1;
    pending_[slot] = (1u << num_audited_) - 1u;
  }

  void TickStarting(const VecEnv& vec_env) override {
    for (int audited = 0; audited < num_audited_; ++audited) Sample(vec_env.state(), audited, fresh_, false);
    std::fill(fresh_.begin(), fresh_.end(), 0);
  }

  // The gaze is read after the expert has acted and the world has moved: the fixation is the
  // first tick whose state the expert reports its gaze settled on the object in.
  void Stepped(const VecEnv& vec_env) override {
    const engine::BatchState& state = vec_env.state();
    tbb::parallel_for(0, vec_env.num_envs(), [&](int slot) {
      const scenarios::Expert::Gaze gaze = state.running(slot) ? expert_.gaze(state, slot) : scenarios::Expert::Gaze{};
      for (int audited = 0; audited < num_audited_; ++audited) {
        fixating_[audited][slot] =
            (pending_[slot] >> audited & 1u) && gaze.settled && gaze.object == ObjectOf(state, audited, slot);
      }
    });
    for (int audited = 0; audited < num_audited_; ++audited) {
      Sample(state, audited, fixating_[audited], true);
      for (int slot = 0; slot < vec_env.num_envs(); ++slot) {
        if (fixating_[audited][slot]) pending_[slot] &= ~(1u << audited);
      }
    }
  }

  bool EpisodeComplete(const VecEnv&, int slot) const override { return pending_[slot] == 0; }

 private:
  int ObjectOf(const engine::BatchState& state, int audited, int slot) const {
    return audited == 0 ? state.target(slot) : cue_index_[static_cast<std::size_t>(audited - 1)];
  }

  // Measures audited object `audited` in the flagged slots, at reset or at its fixation.
  void Sample(const engine::BatchState& state, int audited, const std::vector<uint8_t>& flags, bool at_fixation) {
    if (std::find(flags.begin(), flags.end(), 1) == flags.end()) return;
    const int slots = state.num_envs;
    for (int slot = 0; slot < slots; ++slot) measured_[slot] = flags[slot] ? ObjectOf(state, audited, slot) : -1;
    meter_.Measure(state, measured_, fractions_);
    for (int slot = 0; slot < slots; ++slot) {
      if (!flags[slot]) continue;
      ObjectAudit& audit = result_.episodes[static_cast<std::size_t>(state.episode[slot])].objects[audited];
      const auto first = fractions_.begin() + slot * meter_.num_cameras();
      const CameraFractions seen(first, first + meter_.num_cameras());
      if (!at_fixation) {
        audit.at_reset = seen;
        continue;
      }
      audit.at_fixation = seen;
      audit.fixation_tick = state.control_step[slot];
    }
  }

  const scenarios::Expert& expert_;
  VisibilityMeter meter_;
  AuditResult& result_;
  std::vector<int> cue_index_;  // object index of each audited cue
  int num_audited_ = 1;
  std::vector<int> measured_;                   // [slot] object measured, -1: none
  std::vector<double> fractions_;               // [slot][camera]
  std::vector<uint8_t> fresh_;                  // [slot] dealt, not yet measured at reset
  std::vector<uint32_t> pending_;               // [slot] audited objects still to fixate, as bits
  std::vector<std::vector<uint8_t>> fixating_;  // [audited][slot] fixated on this tick
};

}  // namespace

int AuditResult::VisibleAtReset(int object, int camera) const {
  return CountVisible(*this, object, camera, [](const ObjectAudit& audit) { return &audit.at_reset; });
}

int AuditResult::VisibleAtFixation(int object, int camera) const {
  return CountVisible(*this, object, camera,
                      [](const ObjectAudit& audit) { return audit.at_fixation ? &*audit.at_fixation : nullptr; });
}

int AuditResult::Fixated(int object) const {
  return static_cast<int>(std::count_if(episodes.begin(), episodes.end(), [&](const EpisodeAudit& episode) {
    return episode.objects[static_cast<std::size_t>(object)].at_fixation.has_value();
  }));
}

AuditResult RunVisibilityAudit(const AuditConfig& config, const ProgressCallback& progress) {
  if (config.episodes < 1)
    throw std::invalid_argument("episodes must be at least 1, got " + std::to_string(config.episodes));
  if (config.envs < 1) throw std::invalid_argument("envs must be at least 1, got " + std::to_string(config.envs));
  const scene::SceneSpec& spec = config.scene;
  if (scenarios::FindScenario(spec.task).make_expert == nullptr)
    throw std::invalid_argument("task '" + spec.task + "' has no scripted expert to audit");
  scene::ScenePlan plan = scene::PlanScene(spec);
  const scenarios::ScenarioDef& scenario = *plan.scenario;
  const auto start = std::chrono::steady_clock::now();

  const int slots = std::min(config.envs, config.episodes);
  VecEnv vec_env(std::move(plan.model), scenario, spec.split, slots, spec.seed);
  ExpertPolicy expert(scenario, vec_env.model(), slots, spec.expert_mode);

  AuditResult result;
  result.config = config;
  result.cameras = SceneCameraNames();
  result.objects = {"target"};
  result.objects.insert(result.objects.end(), scenario.cue_objects.begin(), scenario.cue_objects.end());
  result.episodes.resize(static_cast<std::size_t>(config.episodes));
  for (std::size_t i = 0; i < result.episodes.size(); ++i) {
    result.episodes[i].episode = static_cast<int64_t>(i);
    result.episodes[i].objects.resize(result.objects.size());
  }
  AuditSink sink(vec_env, expert, config, result);
  EpisodeDriver driver(vec_env, expert, config.episodes);
  driver.AddSink(sink);
  driver.SetProgress(progress);
  driver.Run();
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace tavis::batch::audit
