// N envs of one task stepped together. A control tick is a short pipeline of named stages, each
// a function over a range of envs (ControlTick lists them); the envs are split into ranges run
// by tbb::parallel_for, and each range goes through all stages in turn while its rows are in
// cache. At policy ticks RenderPolicyTick adds the render stage. Episodes are keyed by their
// index: an episode's randomness comes from (seed, episode), so results do not depend on the
// thread count, on the number of env slots, or on which slot ran which episode.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "batch/scene_render.h"
#include "engine/batch_state.h"
#include "engine/physics_world.h"
#include "engine/world_model.h"
#include "kinematics/action.h"
#include "scenarios/scenario.h"

namespace tavis::batch {

// Builds the world of a task for a robot: the robot model plus the scenario's layout.
engine::WorldModel BuildWorldModel(const kinematics::RobotModel& robot, const scenarios::ScenarioDef& scenario);

// Envs [begin, end).
struct EnvRange {
  int begin = 0;
  int end = 0;
};

// An episode to start in a slot.
struct EpisodeStart {
  int env = 0;
  int64_t episode = 0;
};

// The stages of a control tick, then rendering, for timing.
enum class Stage { kApplyActions, kStepPhysics, kServoNeck, kUpdateTask, kEndEpisodes, kRender, kReset };
constexpr int kNumStages = 7;
const char* ToString(Stage stage);

class VecEnv {
 public:
  VecEnv(engine::WorldModel model, const scenarios::ScenarioDef& scenario, scenarios::Split split, int num_envs,
         uint64_t seed);
  ~VecEnv();
  VecEnv(const VecEnv&) = delete;
  VecEnv& operator=(const VecEnv&) = delete;

  int num_envs() const { return state_.num_envs; }
  const engine::WorldModel& model() const { return model_; }
  const engine::BatchState& state() const { return state_; }
  const scenarios::ScenarioDef& scenario() const { return scenario_; }
  scenarios::Split split() const { return split_; }
  // The instruction of the episode in slot `env`, fixed at its reset: the task's prompt, or under a
  // language perturbation level its paraphrase (prompt_paraphrase.h). Valid until the slot's next reset.
  const char* prompt(int env) const { return prompts_[static_cast<std::size_t>(env)].c_str(); }

  // Starts each listed episode in its slot, in parallel: default robot pose, the task's random
  // layout (and a distractors level's objects, distractor_placement.h), and under ood-init-pose the warm-up (its ticks
  // count toward the episode, as in the reference's InitPoseWrapper; the policy first sees its end). An episode can end
  // in its warm-up.
  void Reset(const std::vector<EpisodeStart>& starts);
  // The same for one slot on the calling thread. Like StepEnv, safe to call concurrently for
  // distinct envs.
  void ResetEnv(int env, int64_t episode);
  // Marks a slot idle: it is skipped by Step until reset again.
  void Release(int env) { state_.episode[env] = -1; }
  // Ends a running episode between ticks, for the driver: kStopped (a sink has what it needs;
  // no outcome) or kGaveUp (the policy has nothing left to try; a failure).
  void EndEarly(int env, engine::EpisodeEnd why);
  // Ends a running episode as invalid_action for `fault` (the step's own action check, or a
  // policy that could not produce an action for it, such as a malformed served reply).
  void EndInvalid(int env, engine::InvalidAction fault);

  // One control tick for every running env, with actions[env] (num_envs entries; idle and
  // ended envs' entries are ignored). Ends episodes on success, time-out, blow-up or an invalid
  // action (kinematics::FindActionDefect, or an IK result that is not finite).
  void Step(const std::vector<kinematics::Action>& actions);
  // One control tick of one env on the calling thread (nothing if it is not running). Calls for
  // distinct envs may run concurrently: a tick touches only its env's rows and world. The
  // episode driver uses it to run slots independently of each other.
  void StepEnv(int env, const std::vector<kinematics::Action>& actions);

  // Camera observations: builds the render scene once (images at settings.width x height, in
  // the order of settings.cameras); the scenario's black_cameras start blocked in every env.
  // Without it nothing is ever rendered.
  void EnableCameras(const CameraSettings& settings);
  // The scene renderer; null until EnableCameras.
  const SceneRender* renderer() const { return renderer_.get(); }
  // Blocks or unblocks one camera of one env: a blocked camera's image is all zero. `camera`
  // indexes settings.cameras. Requires EnableCameras.
  void SetCameraBlocked(int env, int camera, bool blocked);
  // Blocks the named cameras in every env (a camera protocol's blacked-out images,
  // ProtocolBlackCameras); a name that is not rendered is skipped. Requires EnableCameras.
  void BlockCameras(const std::vector<std::string>& names);

  // Stage: render. Renders every running env at a policy tick (control_step a multiple of
  // controls_per_policy) if any of them has images older than its state; without cameras it does
  // nothing. Afterwards images() holds the current images of exactly those envs.
  void RenderPolicyTick();
  // The same for env `env` alone, on the calling thread (the per-slot schedule): renders it if it
  // is running at a policy tick and its images are older than its state; the other envs' images
  // are left as they are. Calls for distinct envs may run concurrently (not with RenderPolicyTick).
  void RenderEnvPolicyTick(int env);
  // Renders exactly the envs flagged in `envs` (num_envs flags) at their current state, running or
  // not: the final observation of an episode that has just ended, before its slot restarts. The
  // other envs' images are cleared and marked stale, so the next RenderPolicyTick draws them.
  void RenderFinal(const std::vector<uint8_t>& envs);
  // The enabled cameras' images, or null without cameras.
  const render::ImageBatch* images() const;
  // Env-camera images rendered so far, for throughput counters and tests.
  int64_t rendered_images() const { return rendered_images_; }

  // ODE solver messages (degenerate contact sets) in the env's current episode.
  int solver_messages(int env) const { return worlds_[env]->solver_messages(); }

  // Per-stage time, summed over the env ranges (so it can exceed the elapsed time on several
  // threads): the CPU time of a control tick's stages, the wall time of reset and render calls
  // (which start parallel work; render calls of single envs, RenderEnvPolicyTick, are summed over
  // the threads that made them). Off by default; the counters start from zero when it is
  // switched on.
  void EnableStageTiming(bool enabled);
  std::array<double, kNumStages> stage_seconds() const;
  // With stage timing on, the render calls' share of the above, split by what the threads did:
  // `cpu` is the CPU time spent rendering (a batch render call: the process's CPU time during the
  // call, when nothing else runs; a single env's: its thread's), and `held` the thread time the
  // calls held (a batch call: its wall time x every thread; a single env's: its wall time on its
  // thread). held - cpu is the time the render calls' threads waited: for a batch call, threads
  // that ran out of tiles while the others finished; for a single env's, a busy machine's
  // preemption.
  struct RenderTimes {
    double cpu = 0.0;
    double held = 0.0;
  };
  RenderTimes render_times() const;
  // With stage timing on: the CPU time spent on the env (its resets, control ticks and, on the
  // per-slot schedule, its renders) since the last call, which returns it and starts again from
  // zero. Envs are then timed one by one.
  double TakeEnvSeconds(int env);

 private:
  // One control tick of the envs in `envs`, each with actions[env]: the stages in order.
  void ControlTick(EnvRange envs, const std::vector<kinematics::Action>& actions);
  // Stages. Each acts on the running envs of its range.
  void ApplyActions(EnvRange envs, const std::vector<kinematics::Action>& actions);  // validate, IK, targets
  void StepPhysics(EnvRange envs);  // ODE substeps toward the targets; reads the state back
  void ServoNeck(EnvRange envs);    // the neck follows its target kinematically
  void UpdateTask(EnvRange envs);   // the episode's clock, the task's own update, a runtime level's move
  void EndEpisodes(EnvRange envs);  // blow-up, success, time-out
  void ResetOne(const EpisodeStart& start);
  // ResetOne and ControlTick of one env, its CPU time added to the env's cost with stage timing.
  void TimedResetOne(const EpisodeStart& start);
  void TimedControlTick(int env, const std::vector<kinematics::Action>& actions);

  template <typename Body>
  void Timed(Stage stage, Body&& body);
  // A render call of the whole batch (all threads) or of `env` alone (its thread, and idle threads
  // for some of its tiles), timed for render_times() and, for a single env, added to the env's
  // cost. A single env's `body` returns the CPU time of the helping threads.
  template <typename Body>
  void TimedRender(int env, Body&& body);

  engine::WorldModel model_;
  const scenarios::ScenarioDef& scenario_;
  scenarios::Split split_;
  uint64_t seed_;
  engine::BatchState state_;
  std::vector<std::unique_ptr<engine::PhysicsWorld>> worlds_;
  std::unique_ptr<SceneRender> renderer_;
  // Per-tick scratch, sized once.
  std::vector<uint8_t> physics_sane_;               // (num_envs) this tick's physics stayed finite
  std::vector<uint8_t> render_env_;                 // (num_envs) this tick's render flags
  std::vector<kinematics::Action> warmup_actions_;  // (num_envs) ood-init-pose warm-up actions
  std::vector<std::string> prompts_;                // (num_envs) the running episode's instruction
  std::atomic<int64_t> rendered_images_{0};
  bool stage_timing_ = false;
  std::array<std::atomic<int64_t>, kNumStages> stage_nanoseconds_{};
  std::atomic<int64_t> render_cpu_nanoseconds_{0};
  std::atomic<int64_t> render_held_nanoseconds_{0};
  std::vector<int64_t> env_nanoseconds_;  // (num_envs) for TakeEnvSeconds
};

}  // namespace tavis::batch
