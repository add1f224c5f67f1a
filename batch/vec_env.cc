#include "batch/vec_env.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "batch/init_pose_warmup.h"
#include "batch/perturb/distractor_placement.h"
#include "batch/perturb/prompt_paraphrase.h"
#include "batch/perturb/target_move.h"
#include "batch/usable_threads.h"
#include "kinematics/action_check.h"
#include "kinematics/cpu_clock.h"
#include "kinematics/inverse_kinematics.h"
#include "kinematics/robot_buffers.h"

namespace tavis::batch {
namespace {

using kinematics::Side;

// A scene perturbation level needs the task to say where its objects may go (scenario.h).
void CheckTaskTakesEpisodePerturbation(const engine::EpisodePerturbation& perturbation,
                                       const scenarios::ScenarioDef& scenario) {
  if (perturbation.adds_distractors() && scenario.distractor_zones == nullptr) {
    throw std::invalid_argument("task '" + scenario.name +
                                "' declares no distractor zones: it cannot take a distractors level");
  }
  if (perturbation.moves_target() && scenario.target_zones == nullptr) {
    throw std::invalid_argument("task '" + scenario.name +
                                "' declares no target zones: it cannot take a runtime level");
  }
  if (perturbation.paraphrases_prompt() && perturbation.language.paraphrases.count(scenario.name) == 0) {
    throw std::invalid_argument("the language level has no paraphrases for task '" + scenario.name + "'");
  }
}

}  // namespace

const char* ToString(Stage stage) {
  switch (stage) {
    case Stage::kApplyActions: return "apply_actions";
    case Stage::kStepPhysics: return "step_physics";
    case Stage::kServoNeck: return "servo_neck";
    case Stage::kUpdateTask: return "update_task";
    case Stage::kEndEpisodes: return "end_episodes";
    case Stage::kRender: return "render";
    case Stage::kReset: return "reset";
  }
  return "unknown";
}

engine::WorldModel BuildWorldModel(const kinematics::RobotModel& robot, const scenarios::ScenarioDef& scenario) {
  engine::WorldModel model;
  model.robot = robot;
  scenario.layout(model);
  return model;
}

VecEnv::VecEnv(engine::WorldModel model, const scenarios::ScenarioDef& scenario, scenarios::Split split, int num_envs,
               uint64_t seed)
    : model_(std::move(model)), scenario_(scenario), split_(split), seed_(seed) {
  if (model_.robot.num_links() > kMaxRobotLinks || model_.robot.num_joints() > kMaxRobotJoints) {
    throw std::invalid_argument("robot '" + model_.robot.name + "' has " + std::to_string(model_.robot.num_links()) +
                                " links and " + std::to_string(model_.robot.num_joints()) +
                                " joints; the simulator supports at most " + std::to_string(kMaxRobotLinks) + " and " +
                                std::to_string(kMaxRobotJoints));
  }
  if (num_envs < 1)
    throw std::invalid_argument("the number of envs must be at least 1, got " + std::to_string(num_envs));
  CheckTaskTakesEpisodePerturbation(model_.episode_perturbation, scenario_);
  state_.Allocate(num_envs, model_.robot.num_joints(), model_.num_objects());
  worlds_.resize(num_envs);
  tbb::parallel_for(0, num_envs, [&](int env) { worlds_[env] = std::make_unique<engine::PhysicsWorld>(model_); });
  physics_sane_.assign(num_envs, 1);
  render_env_.assign(num_envs, 0);
  warmup_actions_.assign(num_envs, kinematics::Action{});
  prompts_.assign(num_envs, std::string());
}

VecEnv::~VecEnv() {
  // ODE worlds must be destroyed on threads where ODE is initialised; parallel like creation.
  tbb::parallel_for(0, num_envs(), [&](int env) { worlds_[env].reset(); });
}

template <typename Body>
void VecEnv::Timed(Stage stage, Body&& body) {
  if (!stage_timing_) {
    body();
    return;
  }
  // A control tick's stages run on one thread: their CPU time. Reset starts parallel work: its
  // wall time (render calls are timed by TimedRender).
  if (stage != Stage::kReset) {
    const int64_t start = kinematics::ThreadCpuNanoseconds();
    body();
    stage_nanoseconds_[static_cast<int>(stage)] += kinematics::ThreadCpuNanoseconds() - start;
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  body();
  const auto elapsed = std::chrono::steady_clock::now() - start;
  stage_nanoseconds_[static_cast<int>(stage)] += std::chrono::duration_cast<std::chrono::nanoseconds>(elapsed).count();
}

template <typename Body>
void VecEnv::TimedRender(int env, Body&& body) {
  if (!stage_timing_) {
    body();
    return;
  }
  const bool batch = env < 0;
  // The wall interval encloses the CPU one, so that the CPU time never exceeds the time held.
  const auto start = std::chrono::steady_clock::now();
  const int64_t cpu_start = batch ? kinematics::ProcessCpuNanoseconds() : kinematics::ThreadCpuNanoseconds();
  // A single env's call returns the CPU that idle threads spent on its tiles, off this thread's
  // clock; they were held for it too. A whole batch's call is on the process's clock.
  int64_t helpers = 0;
  if constexpr (std::is_void_v<std::invoke_result_t<Body>>) {
    body();
  } else {
    helpers = body();
  }
  const int64_t cpu =
      (batch ? kinematics::ProcessCpuNanoseconds() : kinematics::ThreadCpuNanoseconds()) - cpu_start + helpers;
  const int64_t wall =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count();
  stage_nanoseconds_[static_cast<int>(Stage::kRender)] += wall + helpers;
  render_cpu_nanoseconds_ += cpu;
  render_held_nanoseconds_ += batch ? wall * UsableThreads() : wall + helpers;
  if (!batch) env_nanoseconds_[env] += cpu;
}

VecEnv::RenderTimes VecEnv::render_times() const {
  return {1e-9 * static_cast<double>(render_cpu_nanoseconds_.load()),
          1e-9 * static_cast<double>(render_held_nanoseconds_.load())};
}

void VecEnv::EnableStageTiming(bool enabled) {
  stage_timing_ = enabled;
  for (auto& nanoseconds : stage_nanoseconds_) nanoseconds = 0;
  render_cpu_nanoseconds_ = 0;
  render_held_nanoseconds_ = 0;
  env_nanoseconds_.assign(num_envs(), 0);
}

double VecEnv::TakeEnvSeconds(int env) {
  if (!stage_timing_) return 0.0;
  const double seconds = 1e-9 * static_cast<double>(env_nanoseconds_[env]);
  env_nanoseconds_[env] = 0;
  return seconds;
}

std::array<double, kNumStages> VecEnv::stage_seconds() const {
  std::array<double, kNumStages> seconds{};
  for (int i = 0; i < kNumStages; ++i) seconds[i] = 1e-9 * static_cast<double>(stage_nanoseconds_[i].load());
  return seconds;
}

void VecEnv::Reset(const std::vector<EpisodeStart>& starts) {
  Timed(Stage::kReset,
        [&] { tbb::parallel_for(0, static_cast<int>(starts.size()), [&](int i) { TimedResetOne(starts[i]); }); });
}

void VecEnv::ResetEnv(int env, int64_t episode) {
  Timed(Stage::kReset, [&] { TimedResetOne({env, episode}); });
}

void VecEnv::TimedResetOne(const EpisodeStart& start) {
  const int64_t begin = stage_timing_ ? kinematics::ThreadCpuNanoseconds() : 0;
  ResetOne(start);
  if (stage_timing_) env_nanoseconds_[start.env] += kinematics::ThreadCpuNanoseconds() - begin;
}

void VecEnv::ResetOne(const EpisodeStart& start) {
  const int env = start.env;
  const kinematics::RobotModel& robot = model_.robot;
  state_.episode[env] = start.episode;
  state_.end[env] = engine::EpisodeEnd::kRunning;
  state_.control_step[env] = 0;
  state_.task_rng[env] =
      engine::RandomStream(seed_, engine::RandomStreamId::kTask, static_cast<uint64_t>(start.episode));
  state_.invalid_action[env] = engine::InvalidAction();
  state_.images_current[env] = 0;
  const std::vector<double> q_default = robot.DefaultPositions();
  std::copy(q_default.begin(), q_default.end(), state_.q_row(env));
  std::copy(q_default.begin(), q_default.end(), state_.q_target_row(env));
  // Grippers commanded open, as in a fresh batch (engine/batch_state.cc): the stage check reads
  // the command at the first tick, which must not see what the slot's previous episode left.
  std::fill_n(state_.gripper_command_row(env), engine::kGrippersPerEnv, -1.0);
  state_.task[env] = engine::TaskVars();
  state_.task_state[env] = engine::TaskStateBlock();
  std::fill_n(state_.object_rgb_row(env, 0), 3 * model_.num_objects(), -1.0f);
  scenario_.reset(model_, split_, state_, env);
  perturb::PlaceDistractors(model_, scenario_, state_, env);
  prompts_[env] = perturb::EpisodePrompt(model_, scenario_, state_, env);

  engine::PhysicsWorld& world = *worlds_[env];
  world.ResetRobot(state_.q_row(env));
  for (int object = 0; object < model_.num_objects(); ++object) {
    world.SetObject(object, state_.ObjectPosition(env, object), state_.ObjectOrientation(env, object),
                    state_.object_enabled_at(env, object) != 0);
  }
  world.ReadState(state_.q_row(env), state_.gripper_gap_row(env), state_.object_pose_row(env, 0),
                  state_.object_velocity_row(env, 0));

  if (split_ == scenarios::Split::kOodInitPose) {
    engine::RandomStream rng(seed_, engine::RandomStreamId::kInitPose, static_cast<uint64_t>(start.episode));
    warmup_actions_[env] = InitPoseWarmupAction(robot, rng);
    const int ticks = kInitPoseWarmupPolicySteps * model_.physics.controls_per_policy();
    for (int tick = 0; tick < ticks && state_.running(env); ++tick) ControlTick({env, env + 1}, warmup_actions_);
  }
  state_.policy_start_tick[env] = state_.control_step[env];
}

void VecEnv::EndInvalid(int env, engine::InvalidAction fault) {
  TAVIS_INVARIANT(state_.running(env), "only a running episode ends invalid_action");
  state_.invalid_action[env] = std::move(fault);
  state_.end[env] = engine::EpisodeEnd::kInvalidAction;
}

void VecEnv::EndEarly(int env, engine::EpisodeEnd why) {
  TAVIS_INVARIANT(state_.running(env), "only a running episode is ended early");
  TAVIS_INVARIANT(why == engine::EpisodeEnd::kStopped || why == engine::EpisodeEnd::kGaveUp,
                  "an episode ends early as stopped or gave_up");
  state_.end[env] = why;
}

void VecEnv::Step(const std::vector<kinematics::Action>& actions) {
  TAVIS_INVARIANT(static_cast<int>(actions.size()) == num_envs(), "one action per env slot");
  tbb::parallel_for(tbb::blocked_range<int>(0, num_envs(), 1), [&](const tbb::blocked_range<int>& range) {
    if (!stage_timing_) {
      ControlTick({range.begin(), range.end()}, actions);
      return;
    }
    for (int env = range.begin(); env < range.end(); ++env) TimedControlTick(env, actions);
  });
}

void VecEnv::StepEnv(int env, const std::vector<kinematics::Action>& actions) {
  TAVIS_INVARIANT(static_cast<int>(actions.size()) == num_envs(), "one action per env slot");
  TimedControlTick(env, actions);
}

void VecEnv::TimedControlTick(int env, const std::vector<kinematics::Action>& actions) {
  if (!stage_timing_) {
    ControlTick({env, env + 1}, actions);
    return;
  }
  const int64_t start = kinematics::ThreadCpuNanoseconds();
  ControlTick({env, env + 1}, actions);
  env_nanoseconds_[env] += kinematics::ThreadCpuNanoseconds() - start;
}

void VecEnv::ControlTick(EnvRange envs, const std::vector<kinematics::Action>& actions) {
  Timed(Stage::kApplyActions, [&] { ApplyActions(envs, actions); });
  Timed(Stage::kStepPhysics, [&] { StepPhysics(envs); });
  Timed(Stage::kServoNeck, [&] { ServoNeck(envs); });
  Timed(Stage::kUpdateTask, [&] { UpdateTask(envs); });
  Timed(Stage::kEndEpisodes, [&] { EndEpisodes(envs); });
}

void VecEnv::ApplyActions(EnvRange envs, const std::vector<kinematics::Action>& actions) {
  const kinematics::RobotModel& robot = model_.robot;
  LinkPoses X_BL;  // the step allocates nothing
  for (int env = envs.begin; env < envs.end; ++env) {
    if (!state_.running(env)) continue;
    const kinematics::Action& action = actions[env];
    // An unusable action ends the episode; the hot loop never throws.
    const kinematics::ActionDefect defect = kinematics::FindActionDefect(action);
    if (defect.found()) {
      EndInvalid(env, {defect.entry, action[defect.entry], defect.reason});
      continue;
    }
    const double* q = state_.q_row(env);
    double* q_target = state_.q_target_row(env);
    kinematics::ComputeLinkPoses(robot, q, X_BL.data());
    for (Side side : kinematics::kSides) {
      const int i = kinematics::Index(side);
      const int p = kinematics::action::kArmPosition[i];
      const int r = kinematics::action::kArmQuaternion[i];
      const kinematics::PoseTarget target{robot.CanonicalToBase(Vec3(action[p], action[p + 1], action[p + 2])),
                                          Quat(action[r], action[r + 1], action[r + 2], action[r + 3])};
      const auto arm_targets = kinematics::IkStep(robot, side, q, X_BL.data(), target);
      if (!std::all_of(arm_targets.begin(), arm_targets.end(), [](double value) { return std::isfinite(value); })) {
        EndInvalid(env, {p, action[p], "IK gave a non-finite joint target for this arm's target"});
        break;
      }
      for (int k = 0; k < kinematics::kArmDof; ++k) q_target[robot.arm(side).joints[k]] = arm_targets[k];
      state_.gripper_command_row(env)[i] = std::clamp(action[kinematics::action::kGripper[i]], -1.0, 1.0);
    }
    if (!state_.running(env)) continue;
    for (int k = 0; k < kinematics::kNeckDof; ++k) {
      const kinematics::Joint& joint = robot.joints[robot.neck_joints[k]];
      q_target[robot.neck_joints[k]] = std::clamp(action[kinematics::action::kNeck[k]], joint.lower, joint.upper);
    }
  }
}

void VecEnv::StepPhysics(EnvRange envs) {
  for (int env = envs.begin; env < envs.end; ++env) {
    if (!state_.running(env)) continue;
    engine::PhysicsWorld& world = *worlds_[env];
    const double* command = state_.gripper_command_row(env);
    const std::array<double, engine::kGrippersPerEnv> gripper = {command[0], command[1]};
    physics_sane_[env] = world.Step(state_.q_target_row(env), gripper, model_.physics.substeps_per_control());
    world.ReadState(state_.q_row(env), state_.gripper_gap_row(env), state_.object_pose_row(env, 0),
                    state_.object_velocity_row(env, 0));
  }
}

// The neck only carries the head, so it is servoed kinematically: first order toward its
// target at the actuator gain, bounded by the velocity limit.
void VecEnv::ServoNeck(EnvRange envs) {
  const kinematics::RobotModel& robot = model_.robot;
  const double dt = 1.0 / model_.physics.control_hz;
  const double blend = 1.0 - std::exp(-robot.neck_actuator.position_gain * dt);
  const double max_move = robot.neck_actuator.velocity_limit * dt;
  for (int env = envs.begin; env < envs.end; ++env) {
    if (!state_.running(env)) continue;
    double* q = state_.q_row(env);
    const double* q_target = state_.q_target_row(env);
    for (int joint : robot.neck_joints)
      q[joint] += std::clamp(blend * (q_target[joint] - q[joint]), -max_move, max_move);
  }
}

void VecEnv::UpdateTask(EnvRange envs) {
  for (int env = envs.begin; env < envs.end; ++env) {
    if (!state_.running(env)) continue;
    state_.control_step[env] += 1;
    if (scenario_.update != nullptr) scenario_.update(model_, state_, env);
    perturb::MoveTargetNearHand(model_, scenario_, state_, env, *worlds_[env]);
    state_.images_current[env] = 0;
  }
}

void VecEnv::EndEpisodes(EnvRange envs) {
  for (int env = envs.begin; env < envs.end; ++env) {
    if (!state_.running(env)) continue;
    if (!physics_sane_[env]) {
      state_.end[env] = engine::EpisodeEnd::kPhysicsBlowUp;
    } else if (scenario_.Succeeded(state_, env)) {
      state_.end[env] = engine::EpisodeEnd::kSuccess;
    } else if (state_.control_step[env] >= model_.physics.max_control_steps()) {
      state_.end[env] = engine::EpisodeEnd::kTimeOut;
    }
  }
}

void VecEnv::EnableCameras(const CameraSettings& settings) {
  renderer_ = std::make_unique<SceneRender>(model_, num_envs(), settings);
  // The task's black cameras (blocked-clutter-pick-cube's head, reference 4.8) give all-zero
  // images; the reference renders them and then replaces the image, here no ray is traced.
  for (const std::string& name : scenario_.black_cameras) {
    const int camera = renderer_->CameraIndex(name);
    if (camera < 0) continue;
    for (int env = 0; env < num_envs(); ++env) renderer_->SetCameraEnabled(env, camera, false);
  }
  std::fill(state_.images_current.begin(), state_.images_current.end(), 0);
}

void VecEnv::SetCameraBlocked(int env, int camera, bool blocked) {
  if (!renderer_) throw std::logic_error("VecEnv::SetCameraBlocked: cameras are not enabled (call EnableCameras)");
  renderer_->SetCameraEnabled(env, camera, !blocked);
  state_.images_current[env] = 0;
}

void VecEnv::BlockCameras(const std::vector<std::string>& names) {
  if (!renderer_) throw std::logic_error("VecEnv::BlockCameras: cameras are not enabled (call EnableCameras)");
  for (const std::string& name : names) {
    const int camera = renderer_->CameraIndex(name);
    if (camera < 0) continue;
    for (int env = 0; env < num_envs(); ++env) SetCameraBlocked(env, camera, true);
  }
}

const render::ImageBatch* VecEnv::images() const { return renderer_ ? &renderer_->images() : nullptr; }

void VecEnv::RenderPolicyTick() {
  if (!renderer_) return;
  const int ticks_per_policy_step = model_.physics.controls_per_policy();
  bool stale = false;
  int rendered_envs = 0;
  for (int env = 0; env < num_envs(); ++env) {
    const bool at_policy_tick = state_.running(env) && state_.control_step[env] % ticks_per_policy_step == 0;
    render_env_[env] = at_policy_tick ? 1 : 0;
    stale = stale || (at_policy_tick && state_.images_current[env] == 0);
    rendered_envs += at_policy_tick ? 1 : 0;
  }
  // One render call for all envs at their policy tick: the call clears the other envs' images,
  // so envs already current are drawn again rather than left out.
  if (!stale) return;
  TimedRender(-1, [&] { renderer_->Render(state_, render_env_.data()); });
  for (int env = 0; env < num_envs(); ++env) state_.images_current[env] = render_env_[env];
  rendered_images_ += static_cast<int64_t>(rendered_envs) * renderer_->num_cameras();
}

void VecEnv::RenderEnvPolicyTick(int env) {
  if (!renderer_ || !state_.running(env) || state_.images_current[env] != 0) return;
  if (state_.control_step[env] % model_.physics.controls_per_policy() != 0) return;
  TimedRender(env, [&] { return renderer_->RenderEnv(state_, env).helper_cpu_ns; });
  state_.images_current[env] = 1;
  rendered_images_ += renderer_->num_cameras();
}

void VecEnv::RenderFinal(const std::vector<uint8_t>& envs) {
  if (!renderer_) return;
  TimedRender(-1, [&] { renderer_->Render(state_, envs.data()); });
  int rendered_envs = 0;
  for (int env = 0; env < num_envs(); ++env) rendered_envs += envs[env] != 0 ? 1 : 0;
  std::fill(state_.images_current.begin(), state_.images_current.end(), 0);
  rendered_images_ += static_cast<int64_t>(rendered_envs) * renderer_->num_cameras();
}

}  // namespace tavis::batch
