// The batched env as the Python module steps it (docs/python.md): Gymnasium's VectorEnv
// semantics on the lock-step episode loop (LockStepTicker, the episode driver's). One step holds
// the caller's actions for a fixed number of control ticks; episodes that end are recorded
// (cell::EpisodeRecorder, the loop's sink, as `tavis eval` records them) and, with autoreset,
// their slots start the next episode at once (Gymnasium's SAME_STEP); without it they stay ended
// until reset. Episode i has the randomness of (seed, i) whichever slot runs it, so a
// rollout's records equal those of the evaluation cell with the same seed. Nothing here knows
// Python: module.cc wraps the buffers as numpy views.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/task_arena.h>

#include "batch/camera_protocol.h"
#include "batch/cell/episode_recorder.h"
#include "batch/cell/evaluation_cell.h"
#include "batch/episode_slots.h"
#include "batch/lock_step_ticker.h"
#include "batch/policy.h"
#include "batch/scene/scene_spec.h"
#include "batch/vec_env.h"

namespace tavis::batch::gym {

// The most envs one GymVecEnv runs, as the cell setting envs allows.
constexpr int kMaxGymEnvs = 4096;
// The largest episode index a reset may start: far from int64's end, so that the episodes dealt
// after it (autoreset counts on from it) never overflow.
constexpr int64_t kMaxEpisode = (int64_t{1} << 62) - 1;

struct GymVecEnvConfig {
  // The task, robot, split, seed, perturbation levels and config dir (scene::PlanScene plans it,
  // as every front end plans its scene).
  scene::SceneSpec scene;
  int num_envs = 1;
  std::string camera = "head";  // the camera protocol: head or fixed
  // The cameras observed, from SceneCameraNames(); under the fixed protocol "head" means the
  // fixed camera (ProtocolCameras).
  std::vector<std::string> cameras = {"head", "left_wrist", "right_wrist"};
  int image_width = 224;
  int image_height = 224;
  int threads = 0;                 // 0: all cores
  int control_ticks_per_step = 0;  // 0: the policy rate's (3 control ticks, 20 Hz)
  bool autoreset = true;
};

// Why the env could not be made: an unknown name (KeyError in Python) or a bad value (ValueError).
struct UnknownName : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// The env's buffers would not fit in this machine's memory (MemoryError in Python).
struct OutOfMemory : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The env is in use by another thread (RuntimeError in Python): Python releases the GIL while an
// env works, and ODE aborts when one world is stepped from two threads at once.
struct EnvBusy : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class GymVecEnv {
 public:
  // Throws UnknownName naming an unknown task, robot or camera, std::invalid_argument for a bad
  // value (a size, a count above kMaxGymEnvs, cameras with steps off the policy ticks, a
  // perturbation that is not AXIS:LEVEL of a known axis and level), OutOfMemory if the images
  // alone would exceed the machine's memory.
  explicit GymVecEnv(const GymVecEnvConfig& config);

  // Holds the env for one caller until destroyed; throws EnvBusy naming `what` while another
  // caller holds it. Every use from Python holds it, so a second thread gets an error, not a crash.
  class Exclusive {
   public:
    Exclusive(const GymVecEnv& env, const char* what);
    ~Exclusive() { busy_.store(false); }
    Exclusive(const Exclusive&) = delete;
    Exclusive& operator=(const Exclusive&) = delete;

   private:
    std::atomic<bool>& busy_;
  };
  bool busy() const { return busy_.load(); }

  int num_envs() const { return vec_env_.num_envs(); }
  int state_size() const { return slots_.proprioception().state_size(); }
  int control_ticks_per_step() const { return ticks_per_step_; }
  // Steps before an episode times out.
  int max_episode_steps() const;
  const GymVecEnvConfig& config() const { return config_; }
  const std::vector<std::string>& camera_names() const { return cameras_; }  // as rendered (protocol applied)

  // Starts episodes in the envs with mask[env] != 0: episodes[env] when it is >= 0, else the next
  // episode index not dealt yet (in env order). Throws std::invalid_argument for wrong sizes or an
  // episode above kMaxEpisode.
  void Reset(const std::vector<uint8_t>& mask, const std::vector<int64_t>& episodes);
  // One step: actions (num_envs x 19, row-major) held for control_ticks_per_step() ticks by the
  // running envs (other rows are ignored). Throws std::invalid_argument, before anything moves,
  // naming the env and entry of a non-finite action of a running env, or if no env was reset.
  void Step(const double* actions);

  // This step's outputs, per env.
  const std::vector<float>& rewards() const { return rewards_; }
  const std::vector<uint8_t>& terminated() const { return terminated_; }
  const std::vector<uint8_t>& truncated() const { return truncated_; }
  // The envs whose episode ended in this step, with its end, episode and final observation.state.
  const std::vector<uint8_t>& ended() const { return ended_; }
  const std::vector<engine::EpisodeEnd>& ended_how() const { return ended_how_; }
  const std::vector<int64_t>& ended_episode() const { return ended_episode_; }
  const std::vector<float>& final_state() const { return final_state_; }  // (num_envs x state_size)
  bool running(int env) const { return vec_env_.state().running(env); }
  int64_t episode(int env) const { return vec_env_.state().episode[env]; }
  const char* prompt(int env) const { return slots_.prompt(env) != nullptr ? slots_.prompt(env) : ""; }

  // Buffers the numpy views show; allocated once, overwritten by every step and reset.
  const float* agent_pos() const { return slots_.proprioception().state(0); }
  const render::ImageBatch* images() const { return vec_env_.images(); }
  // With cameras and autoreset: the images of each env whose episode ended in this step, drawn at
  // its final state before the slot restarted (other envs' entries are stale); null until an
  // episode has ended.
  const render::ImageBatch* final_images() const { return final_images_.get(); }

  // A built-in policy (MakeBuiltinPolicy) acting on this env, reset with its episodes. Throws
  // std::invalid_argument if it acts at another rate than the env steps.
  std::shared_ptr<Policy> MakePolicy(const std::string& name, const std::string& actions_file);
  // The policy's actions for the running envs at the current state (num_envs x 19, row-major;
  // the other rows are zero). An env's episode the policy has given up on (Policy::GaveUp: the
  // expert out of grasp attempts) ends as gave_up after the next step's first tick, as the
  // episode driver ends it.
  void Act(Policy& policy, double* actions);
  // The hold policy's actions (num_envs x 19, row-major; zero rows for envs not running): each
  // running env's arms at their pose when its episode started, head still, grippers open. A
  // valid action to step with whatever the policy rate; it does not count as a policy acting.
  void NeutralActions(double* actions);

  // The records of the episodes that have ended, by episode index (a restarted episode's latest).
  const std::map<int64_t, cell::EpisodeRecord>& records() const { return records_; }
  // Writes episodes first .. first + count - 1 as `tavis eval` writes a cell (episodes.jsonl,
  // summary.json) for `policy`, under the rules of tavis's output folders (WriteResultsFolder:
  // locked, and a folder holding results replaced only with `overwrite`). Throws
  // std::invalid_argument naming an episode not ended yet, or the folder and why it is refused.
  void WriteResults(const std::string& out_dir, const std::string& policy, int64_t first, int64_t count,
                    bool overwrite) const;

 private:
  // Starts `starts_` (the loop resets the policies and tells the recorder), then renders and
  // updates the observation, and reports an episode that ended in its warm-up.
  void StartEpisodes();
  // Reports the episodes that have ended since last told: rewards, ends, final observation.state.
  void CollectEnded();
  void UpdateObservation();
  // Renders the envs whose episode ended in this step into final_images_.
  void KeepFinalImages();
  void ActInto(Policy& policy, double* actions);

  GymVecEnvConfig config_;
  const scenarios::ScenarioDef& scenario_;
  CameraProtocol protocol_;
  tbb::task_arena arena_;
  VecEnv vec_env_;
  int ticks_per_step_ = 0;
  std::vector<std::string> cameras_;
  EpisodeSlots slots_;  // the prompts and the observation, the protocol, the recorder as the sink
  LockStepTicker ticker_;
  std::unique_ptr<cell::EpisodeRecorder> recorder_;
  std::map<int64_t, cell::EpisodeRecord> records_;
  std::vector<std::shared_ptr<Policy>> policies_;  // reset with the episodes (the ticker's)
  std::shared_ptr<Policy> hold_;                   // NeutralActions' policy
  mutable std::atomic<bool> busy_{false};
  std::unique_ptr<render::ImageBatch> final_images_;
  int64_t next_episode_ = 0;
  bool was_reset_ = false;
  double busy_s_ = 0.0;  // time spent resetting and stepping, for the summary's wall_s
  // Per-env buffers, sized once.
  std::vector<EpisodeStart> starts_;
  std::vector<uint8_t> all_envs_;
  ActionBatch actions_;
  Policy* acted_ = nullptr;  // the policy whose actions were asked for since the last step
  std::vector<float> rewards_;
  std::vector<uint8_t> terminated_;
  std::vector<uint8_t> truncated_;
  std::vector<uint8_t> ended_;
  std::vector<engine::EpisodeEnd> ended_how_;
  std::vector<int64_t> ended_episode_;
  std::vector<float> final_state_;
};

}  // namespace tavis::batch::gym
