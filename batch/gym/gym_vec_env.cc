#include "batch/gym/gym_vec_env.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <unistd.h>

#include "batch/builtin_policies.h"
#include "batch/cell/cell_report.h"
#include "batch/gym/results_folder.h"
#include "batch/policy_kinds.h"
#include "batch/scene/scene_plan.h"
#include "configs/robot_config.h"
#include "scenarios/registry.h"

namespace tavis::batch::gym {
namespace {

// Runs `body` and rethrows an std::invalid_argument it throws as UnknownName (a name lookup).
template <typename Body>
auto AsUnknownName(Body&& body) -> decltype(body()) {
  try {
    return body();
  } catch (const UnknownName&) {
    throw;
  } catch (const std::invalid_argument& error) {
    throw UnknownName(error.what());
  }
}

// The machine's physical memory in bytes (0 if unknown).
double PhysicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page_size > 0 ? static_cast<double>(pages) * static_cast<double>(page_size) : 0.0;
}

// Refuses images that could never fit rather than letting the allocation fail, or succeed
// lazily under overcommit and take the process down when first touched.
void CheckImageMemory(const GymVecEnvConfig& config) {
  const double bytes = static_cast<double>(config.num_envs) * static_cast<double>(config.cameras.size()) *
                       static_cast<double>(config.image_width) * static_cast<double>(config.image_height) * 3.0;
  const double memory = PhysicalMemoryBytes();
  if (memory > 0.0 && bytes > memory) {
    constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
    char sizes[96];
    std::snprintf(sizes, sizeof(sizes), "need %.1f GiB; this machine has %.1f GiB", bytes / kGiB, memory / kGiB);
    throw OutOfMemory("the images of " + std::to_string(config.num_envs) + " envs x " +
                      std::to_string(config.cameras.size()) + " cameras at " + std::to_string(config.image_height) +
                      "x" + std::to_string(config.image_width) + " " + sizes);
  }
}

const GymVecEnvConfig& Checked(const GymVecEnvConfig& config) {
  if (config.num_envs < 1)
    throw std::invalid_argument("num_envs must be at least 1, got " + std::to_string(config.num_envs));
  if (config.num_envs > kMaxGymEnvs) {
    throw std::invalid_argument("num_envs must be at most " + std::to_string(kMaxGymEnvs) +
                                " (as an evaluation cell allows), got " + std::to_string(config.num_envs));
  }
  if (config.threads < 0)
    throw std::invalid_argument("threads must be >= 0 (0: all cores), got " + std::to_string(config.threads));
  if (config.control_ticks_per_step < 0) {
    throw std::invalid_argument("control_ticks_per_step must be >= 1 (0: the policy rate's), got " +
                                std::to_string(config.control_ticks_per_step));
  }
  const std::vector<std::string>& known = SceneCameraNames();
  for (const std::string& name : config.cameras) {
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      std::string names;
      for (const std::string& camera : known) names += (names.empty() ? "" : ", ") + camera;
      throw UnknownName("unknown camera '" + name + "' (known: " + names + ")");
    }
  }
  ValidateCameraSettings({config.cameras, config.image_width, config.image_height, false, false});
  CheckImageMemory(config);
  return config;
}

// The env's world, planned as every front end plans its scene; a robot with no file is an
// unknown name, a bad file or perturbation a bad value.
engine::WorldModel PlannedModel(const GymVecEnvConfig& config) {
  try {
    configs::RobotConfigPath(config.scene.config_dir, config.scene.robot);
  } catch (const std::exception& error) {
    throw UnknownName(error.what());
  }
  return scene::PlanScene(config.scene).model;
}

tbb::task_arena::constraints ArenaThreads(int threads) {
  return tbb::task_arena::constraints{}.set_max_concurrency(threads > 0 ? threads : tbb::task_arena::automatic);
}

}  // namespace

GymVecEnv::GymVecEnv(const GymVecEnvConfig& config)
    : config_(Checked(config)),
      scenario_(
          AsUnknownName([&]() -> const scenarios::ScenarioDef& { return scenarios::FindScenario(config.scene.task); })),
      protocol_(AsUnknownName([&] { return ParseCameraProtocol(config.camera); })),
      arena_(ArenaThreads(config.threads)),
      vec_env_(PlannedModel(config), scenario_, config.scene.split, config.num_envs, config.scene.seed),
      ticks_per_step_(config.control_ticks_per_step > 0 ? config.control_ticks_per_step
                                                        : vec_env_.model().physics.controls_per_policy()),
      cameras_(ProtocolCameras(config.cameras, protocol_)),
      slots_(vec_env_),
      ticker_(slots_) {
  const std::size_t n = static_cast<std::size_t>(num_envs());
  if (!cameras_.empty() && ticks_per_step_ % vec_env_.model().physics.controls_per_policy() != 0) {
    throw std::invalid_argument("control_ticks_per_step " + std::to_string(ticks_per_step_) +
                                " with cameras: images are rendered at policy ticks, so it must be a multiple of " +
                                std::to_string(vec_env_.model().physics.controls_per_policy()) +
                                " (or give cameras=[])");
  }
  slots_.SetCameraProtocol(protocol_);
  if (!cameras_.empty()) {
    vec_env_.EnableCameras({cameras_, config.image_width, config.image_height, false, false});
    vec_env_.BlockCameras(ProtocolBlackCameras(protocol_));
  }
  cell::EvaluationCellConfig cell;
  cell.camera = protocol_;
  cell::RecordSettings settings = cell::RecordSettingsFor(cell, ticks_per_step_, vec_env_.model().physics, false);
  settings.in_episode_order = false;
  recorder_ = std::make_unique<cell::EpisodeRecorder>(num_envs(), vec_env_.model().physics.max_control_steps(),
                                                      settings, 0, [this](cell::EpisodeRecord&& record) {
                                                        const int64_t episode = record.episode;
                                                        records_[episode] = std::move(record);
                                                      });
  slots_.AddSink(*recorder_);
  starts_.reserve(n);
  all_envs_.assign(n, 1);
  actions_.assign(n, kinematics::Action{});
  rewards_.assign(n, 0.0F);
  terminated_.assign(n, 0);
  truncated_.assign(n, 0);
  ended_.assign(n, 0);
  ended_how_.assign(n, engine::EpisodeEnd::kRunning);
  ended_episode_.assign(n, -1);
  final_state_.assign(n * static_cast<std::size_t>(state_size()), 0.0F);
  hold_ = MakeBuiltinPolicy(PolicyName(PolicyKind::kHold), scenario_, vec_env_.model(), num_envs(), "");
  policies_.push_back(hold_);
  ticker_.AddPolicy(*hold_);
}

GymVecEnv::Exclusive::Exclusive(const GymVecEnv& env, const char* what) : busy_(env.busy_) {
  if (busy_.exchange(true)) {
    throw EnvBusy(std::string(what) + ": the env is in use by another thread (one env is for one thread at a time)");
  }
}

int GymVecEnv::max_episode_steps() const {
  return (vec_env_.model().physics.max_control_steps() + ticks_per_step_ - 1) / ticks_per_step_;
}

void GymVecEnv::Reset(const std::vector<uint8_t>& mask, const std::vector<int64_t>& episodes) {
  const std::size_t n = static_cast<std::size_t>(num_envs());
  if (mask.size() != n || episodes.size() != n) {
    throw std::invalid_argument("reset needs one mask entry and one episode per env (" + std::to_string(n) + "), got " +
                                std::to_string(mask.size()) + " and " + std::to_string(episodes.size()));
  }
  if (std::none_of(mask.begin(), mask.end(), [](uint8_t m) { return m != 0; })) {
    throw std::invalid_argument("reset_mask selects no env");
  }
  for (std::size_t env = 0; env < n; ++env) {
    if (episodes[env] > kMaxEpisode) {
      throw std::invalid_argument("the episode of env " + std::to_string(env) + " must be an index from 0 to " +
                                  std::to_string(kMaxEpisode) + ", got " + std::to_string(episodes[env]));
    }
  }
  const auto start = std::chrono::steady_clock::now();
  std::fill(rewards_.begin(), rewards_.end(), 0.0F);
  std::fill(terminated_.begin(), terminated_.end(), 0);
  std::fill(truncated_.begin(), truncated_.end(), 0);
  std::fill(ended_.begin(), ended_.end(), 0);
  starts_.clear();
  for (int env = 0; env < num_envs(); ++env) {
    if (mask[env] == 0) continue;
    const int64_t episode = episodes[env] >= 0 ? episodes[env] : next_episode_;
    next_episode_ = std::max(next_episode_, episode + 1);
    starts_.push_back({env, episode});
  }
  arena_.execute([&] { StartEpisodes(); });
  was_reset_ = true;
  busy_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void GymVecEnv::StartEpisodes() {
  if (starts_.empty()) return;
  // The built-in policies' reset looks at the state only, so the images and observation.state
  // can come after it.
  ticker_.StartEpisodes(starts_);
  ticker_.RenderPolicyTick();
  UpdateObservation();
  // An ood-init-pose warm-up can end its episode.
  CollectEnded();
}

void GymVecEnv::UpdateObservation() { slots_.proprioception().Update(vec_env_.state(), all_envs_); }

void GymVecEnv::Step(const double* actions) {
  if (!was_reset_) throw std::invalid_argument("step before reset: call reset() first");
  const engine::BatchState& state = vec_env_.state();
  for (int env = 0; env < num_envs(); ++env) {
    if (!state.running(env)) continue;
    for (int entry = 0; entry < kinematics::action::kSize; ++entry) {
      const double value = actions[static_cast<std::size_t>(env) * kinematics::action::kSize + entry];
      if (!std::isfinite(value)) {
        throw std::invalid_argument("action of env " + std::to_string(env) + ", entry " + std::to_string(entry) +
                                    " is not finite (" + std::to_string(value) + ")");
      }
    }
  }
  const auto start = std::chrono::steady_clock::now();
  for (int env = 0; env < num_envs(); ++env) {
    std::copy_n(actions + static_cast<std::size_t>(env) * kinematics::action::kSize, kinematics::action::kSize,
                actions_[env].begin());
  }
  std::fill(rewards_.begin(), rewards_.end(), 0.0F);
  std::fill(terminated_.begin(), terminated_.end(), 0);
  std::fill(truncated_.begin(), truncated_.end(), 0);
  std::fill(ended_.begin(), ended_.end(), 0);
  arena_.execute([&] {
    // An env whose episode ends within the step stays ended for the step's other ticks.
    for (int tick = 0; tick < ticks_per_step_ && ticker_.RunningEnvs() > 0; ++tick) {
      ticker_.TickStarting();
      ticker_.Tick(actions_, acted_);
    }
    acted_ = nullptr;
    CollectEnded();
    if (config_.autoreset) {
      KeepFinalImages();
      // Every ended episode's slot, including one whose episode ended in an earlier reset's
      // warm-up (a warm-up that ends here reports in this step, over the previous episode's end).
      starts_.clear();
      for (int env = 0; env < num_envs(); ++env) {
        if (state.episode[env] >= 0 && !state.running(env)) starts_.push_back({env, next_episode_++});
      }
      StartEpisodes();
    }
    ticker_.RenderPolicyTick();
    UpdateObservation();
  });
  busy_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void GymVecEnv::CollectEnded() {
  const engine::BatchState& state = vec_env_.state();
  const std::size_t row = static_cast<std::size_t>(state_size());
  UpdateObservation();
  // An env already reported keeps its end until reset: the ticker tells of each end once.
  ticker_.CollectEnded([&](int env) {
    const engine::EpisodeEnd end = state.end[env];
    ended_[env] = 1;
    ended_how_[env] = end;
    ended_episode_[env] = state.episode[env];
    rewards_[env] = end == engine::EpisodeEnd::kSuccess ? 1.0F : 0.0F;
    truncated_[env] = end == engine::EpisodeEnd::kTimeOut ? 1 : 0;
    terminated_[env] = truncated_[env] == 0 ? 1 : 0;
    std::copy_n(slots_.proprioception().state(env), row, final_state_.begin() + static_cast<std::ptrdiff_t>(env * row));
  });
}

void GymVecEnv::KeepFinalImages() {
  if (vec_env_.images() == nullptr || std::none_of(ended_.begin(), ended_.end(), [](uint8_t e) { return e != 0; }))
    return;
  vec_env_.RenderFinal(ended_);
  const render::ImageBatch& images = *vec_env_.images();
  if (!final_images_) final_images_ = std::make_unique<render::ImageBatch>(images);
  // An env's images are one block, its cameras one after the other (ImageBatch is env-major).
  std::size_t env_bytes = 0;
  for (int camera = 0; camera < images.n_cameras(); ++camera) {
    env_bytes += 3 * static_cast<std::size_t>(images.width(camera)) * static_cast<std::size_t>(images.height(camera));
  }
  for (int env = 0; env < num_envs(); ++env) {
    if (ended_[env] != 0) std::copy_n(images.rgb(env, 0), env_bytes, final_images_->rgb(env, 0));
  }
}

std::shared_ptr<Policy> GymVecEnv::MakePolicy(const std::string& name, const std::string& actions_file) {
  AsUnknownName([&] { CheckBuiltinPolicyName(name); });
  std::shared_ptr<Policy> policy = MakeBuiltinPolicy(name, scenario_, vec_env_.model(), num_envs(), actions_file);
  if (policy->control_ticks_per_action() != ticks_per_step_) {
    throw std::invalid_argument(
        "policy '" + name + "' acts every " + std::to_string(policy->control_ticks_per_action()) +
        " control ticks but the env steps " + std::to_string(ticks_per_step_) +
        "; make the env with control_ticks_per_step=" + std::to_string(policy->control_ticks_per_action()));
  }
  if (!policy->cameras().empty()) throw std::invalid_argument("built-in policy '" + name + "' uses cameras");
  arena_.execute([&] {
    std::vector<uint8_t> running(static_cast<std::size_t>(num_envs()), 0);
    for (int env = 0; env < num_envs(); ++env) running[env] = vec_env_.state().running(env) ? 1 : 0;
    policy->Reset(slots_.observation(), running);
  });
  policies_.push_back(policy);
  ticker_.AddPolicy(*policy);
  return policy;
}

void GymVecEnv::Act(Policy& policy, double* actions) {
  const auto is_this = [&](const std::shared_ptr<Policy>& mine) { return mine.get() == &policy; };
  if (std::none_of(policies_.begin(), policies_.end(), is_this)) {
    throw std::invalid_argument("policy '" + policy.name() +
                                "' was made by another env (make it with this env's make_policy)");
  }
  ActInto(policy, actions);
  acted_ = &policy;
}

void GymVecEnv::NeutralActions(double* actions) {
  if (!was_reset_) throw std::invalid_argument("neutral actions before reset: call reset() first");
  ActInto(*hold_, actions);
}

void GymVecEnv::ActInto(Policy& policy, double* actions) {
  std::vector<uint8_t> acting(static_cast<std::size_t>(num_envs()), 0);
  ActionBatch chosen(static_cast<std::size_t>(num_envs()), kinematics::Action{});
  for (int env = 0; env < num_envs(); ++env) acting[env] = vec_env_.state().running(env) ? 1 : 0;
  arena_.execute([&] { policy.Act(slots_.observation(), acting, chosen); });
  for (int env = 0; env < num_envs(); ++env) {
    std::copy(chosen[env].begin(), chosen[env].end(),
              actions + static_cast<std::size_t>(env) * kinematics::action::kSize);
  }
}

void GymVecEnv::WriteResults(const std::string& out_dir, const std::string& policy, int64_t first, int64_t count,
                             bool overwrite) const {
  if (first < 0 || count < 1) {
    throw std::invalid_argument("episodes to write: first >= 0 and count >= 1, got first " + std::to_string(first) +
                                ", count " + std::to_string(count));
  }
  cell::CellResult result;
  cell::EvaluationCellConfig& cell = result.config;
  cell.task = config_.scene.task;
  cell.robot = config_.scene.robot;
  cell.split = config_.scene.split;
  cell.camera = protocol_;
  cell.policy = policy;
  cell.episodes = static_cast<int>(count);
  cell.envs = num_envs();
  cell.seed = config_.scene.seed;
  cell.perturbations = config_.scene.perturbations;
  cell.config_dir = config_.scene.config_dir;
  cell.image_width = config_.image_width;
  cell.image_height = config_.image_height;
  for (int64_t episode = first; episode < first + count; ++episode) {
    const auto record = records_.find(episode);
    if (record == records_.end()) {
      throw std::invalid_argument("episode " + std::to_string(episode) +
                                  " has not ended (episodes ended: " + std::to_string(records_.size()) + ")");
    }
    result.episodes.push_back(record->second);
    result.successes += record->second.success ? 1 : 0;
  }
  const cell::RecordSettings settings = cell::RecordSettingsFor(cell, ticks_per_step_, vec_env_.model().physics, false);
  result.galt_fps = settings.galt_fps;
  result.galt_policy_rate_fps = settings.policy_rate_fps;
  result.envs = num_envs();
  result.wall_s = busy_s_;
  result.control_ticks = ticker_.control_ticks();
  result.rendered_cameras = cameras_;
  result.render_width = config_.image_width;
  result.render_height = config_.image_height;
  result.rendered_images = vec_env_.rendered_images();
  cell::RunInfo info;
  info.threads = arena_.max_concurrency();
  WriteResultsFolder(result, info, out_dir, overwrite);
}

}  // namespace tavis::batch::gym
