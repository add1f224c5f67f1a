// An evaluation cell: (task, robot, split, camera protocol, seed, policy) x N episodes run over M parallel env
// slots. Episode i always gets the randomness of (seed, i), so a cell's records are identical
// for any thread count and any number of slots.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "batch/camera_protocol.h"
#include "batch/cell/episode_recorder.h"
#include "batch/cell_profile.h"
#include "batch/episode_driver.h"
#include "batch/remote/remote_policy.h"
#include "scenarios/expert/expert_mode.h"
#include "scenarios/split.h"

namespace tavis::batch::cell {

struct EvaluationCellConfig {
  std::string task = "clutter-pick-cube";
  std::string robot = "gr1t2";
  scenarios::Split split = scenarios::Split::kId;
  CameraProtocol camera = CameraProtocol::kHead;
  std::string policy = "expert";
  // For the scripted expert: how its head leads (gaze-first, or head-still for the fixed-camera
  // bias ablation); another policy must leave it gaze-first.
  scenarios::expert::ExpertMode expert_mode = scenarios::expert::ExpertMode::kGazeFirst;
  std::string actions_file;  // for the replay policy: a CSV, or a folder of episode_<i>.csv
  // For the expert: 60 (its action may change every control tick) or 20 (held for three ticks,
  // as a 20 Hz policy acts; each episode's actions are then saved at 20 Hz for --policy replay).
  int expert_hz = 60;
  // For the served policy "openpi": its policy servers (env slot i asks servers[i % size]) and
  // the chunk rows an env steps with before asking again (0: the whole chunk).
  std::vector<std::string> servers;
  int replan_steps = 0;
  // The request layout: a preset (remote::KeyPresetNames()) or a YAML file (observation_keys.h).
  std::string observation_keys = "tavis";
  // A LeRobot dataset whose meta/info.json gives the layout (keys, cameras, image size) when
  // observation_keys_given is false; when it is true (or an image size is given), a layout that
  // differs from the dataset's is reported (CellResult::layout_differences), not refused.
  std::string observation_dataset;
  bool observation_keys_given = false;
  // How requests travel (remote_policy.h); the records do not depend on it.
  remote::ServingMode serving = remote::ServingMode::kSerial;
  double server_ready_timeout_s = 60.0;  // per server, for its /healthz to answer before the cell starts
  double reply_timeout_s = 300.0;  // per request, for the reply (a server's first inference may compile its model)
  double max_reply_mb = 16.0;      // a longer reply ends its episode (remote::kDefaultMaxReplyBytes)
  int episodes = 96;
  // The cell's first episode index: it holds episodes episode_start .. episode_start + episodes - 1
  // (`tavis eval --episode I` runs episode I of the seed alone, the scene it has in a full cell).
  int64_t episode_start = 0;
  // Episodes before this one are not run (a resumed cell has their records already); in
  // [episode_start, episode_start + episodes] (at the end, nothing runs).
  int64_t first_episode = 0;
  int envs = 32;  // parallel env slots
  uint64_t seed = 0;
  std::string config_dir;  // holds robots/*.yaml
  // Cameras rendered on every policy tick even if the policy does not consume them (throughput
  // runs); the policy's own cameras() are always rendered. Names from SceneCameraNames().
  std::vector<std::string> render_cameras;
  // The size of the policy's images; 0 x 0: the policy's own (a served policy's observation
  // keys, 224 x 224 for the presets; the reference's 640 x 480 otherwise).
  int image_width = 0;
  int image_height = 0;
  // Keep every control tick's commanded action in the records (tests compare them); otherwise a
  // cell's memory does not grow with its episodes.
  bool keep_actions = false;
  // Time every stage and episode (CellResult::profile; `tavis eval --profile`).
  bool profile = false;
  // Perturbation levels, "AXIS:LEVEL" each, at most one per axis (batch/perturbation_catalog.h,
  // docs/perturbations.md); empty: the base scene. Episode i keeps its base scene under every one.
  std::vector<std::string> perturbations;
};

struct CellResult {
  EvaluationCellConfig config;  // as run: the image size resolved
  int render_width = 0;         // the cameras' rendered size (letterboxed into the image size)
  int render_height = 0;
  std::vector<EpisodeRecord> episodes;  // the episodes run, ordered by episode index
  int successes = 0;
  int envs = 0;  // the env slots that ran (at most the episodes to run)
  double wall_s = 0.0;
  int64_t control_ticks = 0;                  // env control ticks simulated, for throughput
  double galt_fps = 0.0;                      // rate of the action samples GALT was computed on
  double galt_policy_rate_fps = 0.0;          // 0 when the policy acts at the policy rate
  std::vector<std::string> rendered_cameras;  // the policy's cameras, then the extra render_cameras
  int64_t rendered_images = 0;                // env-camera images rendered
  // A served policy's requests; its episodes' actions are kept for --policy replay
  // (EpisodeRecord::replay_actions).
  std::optional<remote::RequestTimings> requests;
  std::vector<remote::Value> server_metadata;  // each server's metadata message
  std::string observation_keys_source;         // the request layout's preset, file or dataset
  // How the served layout differs from observation_dataset's (empty: it does not, or none given).
  std::vector<std::string> layout_differences;
  std::optional<CellProfile> profile;  // with config.profile
  bool per_slot = false;               // run on the driver's per-slot schedule (RunsPerSlot)
};

// Policy names a cell accepts, for --help texts and errors: the built-in ones and "openpi".
std::string CellPolicyNames();

// Throws std::invalid_argument / configs::ConfigError for bad settings, and std::runtime_error
// naming the server when a served policy's server is unreachable or fails. An unusable action
// ends only its episode (invalid_action, recorded with the entry and the reason).
// Checks every setting (task, robot file, policy, cameras, sizes, the served policy's keys)
// without running anything; throws as RunEvaluationCell does for bad settings.
void CheckEvaluationCell(const EvaluationCellConfig& config);

// What a cell's recorder keeps for a policy acting every `hold_ticks` control ticks: GALT at that
// rate (and at the 20 Hz policy rate for a faster policy) under the head protocol, the served
// policy's actions for replay, every action with config.keep_actions.
RecordSettings RecordSettingsFor(const EvaluationCellConfig& config, int hold_ticks,
                                 const engine::PhysicsSettings& physics, bool served);

// How a served cell's layout differs from its observation_dataset's, one line each (empty when it
// does not or no dataset is named). Throws as CheckEvaluationCell does.
std::vector<std::string> ServedLayoutDifferences(const EvaluationCellConfig& config);

// True if the cell's episodes run on the episode driver's per-slot schedule: a built-in policy
// (each env decided on its own; its cameras, rendered or not, are drawn per slot), unless a sink
// the caller adds needs the common tick (episode videos). Such a cell keeps every thread busy
// until its last episodes.
bool RunsPerSlot(const EvaluationCellConfig& config);

// The --envs a cell gets when none is given: 32, and for a served policy (lock-step, a batch per
// request) 6 per thread when that is more (96 on 16 threads), so that each tick's wait for the
// slowest env and the server is shared by more envs.
int DefaultEnvs(const std::string& policy, int threads);

// Called with each episode's record as soon as it and every earlier episode have ended.
using RecordCallback = std::function<void(const EpisodeRecord&)>;

// Further sinks a caller plugs into the cell's driver beside its recorder (episode videos, a
// rollout dataset), made once the env exists; `policy_cameras` are the cameras the policy sees
// under the camera protocol (empty for one that takes no images). The sinks watch; what they do
// must not change the records.
using CellSinks =
    std::function<std::vector<EpisodeSink*>(const VecEnv& vec_env, const std::vector<std::string>& policy_cameras)>;

CellResult RunEvaluationCell(const EvaluationCellConfig& config, const ProgressCallback& progress = nullptr,
                             const RecordCallback& on_record = nullptr, const CellSinks& sinks = nullptr);

}  // namespace tavis::batch::cell
