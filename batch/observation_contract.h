// The observation contract's names, declared once: what `tavis demos` writes into a dataset, what
// the Python env returns and what a served policy receives carry the same keys (the reference's
// LeRobot names, tavis-reference-spec 10.2: observation.images.OBS_HEAD, ...), so a policy
// trained on our datasets (or the reference's) finds its features when it is served. The shapes
// and the state layout are in docs/observation.md.
#pragma once

#include <string>

namespace tavis::batch::contract {

// The LeRobot feature key of a scene camera: head -> observation.images.OBS_HEAD, fixed ->
// observation.images.OBS_FIXED, left_wrist -> observation.images.OBS_WRIST_LEFT, right_wrist ->
// observation.images.OBS_WRIST_RIGHT. Throws std::invalid_argument for another name.
std::string CameraImageKey(const std::string& camera);
// The suffix alone (OBS_HEAD, ...): the Python env's `pixels` keys, as LeRobot's
// preprocess_observation turns `pixels/<name>` into observation.images.<name>.
std::string CameraImageName(const std::string& camera);
// The scene camera of a dataset image key (the inverse of CameraImageKey); empty when `key` is none.
std::string CameraOfImageKey(const std::string& key);

inline constexpr const char* kStateKey = "observation.state";
// The episode's instruction travels twice: openpi's transforms read "prompt", LeRobot's
// policies "task".
inline constexpr const char* kPromptKey = "prompt";
inline constexpr const char* kTaskKey = "task";

// What each served request carries besides the observation, so that a server can keep state per
// (env, episode) (observation history, action ensembling): the env slot, the episode's index in
// the cell, the 20 Hz policy step within the episode, and a flag on its first observation.
inline constexpr const char* kEnvIndexField = "env_index";
inline constexpr const char* kEpisodeIndexField = "episode_index";
inline constexpr const char* kStepField = "step";
inline constexpr const char* kIsFirstField = "is_first";
// In a batched request (one message for every env due at a policy tick): the number of envs, the
// length of every value's leading axis.
inline constexpr const char* kBatchSizeField = "batch_size";
// All of them: a top-level key every request carries besides the observation, which no image or
// state key may use (a key layout or a server's declared contract that did would be overwritten).
inline constexpr const char* kRequestFields[] = {kEnvIndexField, kEpisodeIndexField, kStepField, kIsFirstField,
                                                 kBatchSizeField};
// A server's metadata declares that it answers batched requests with this key set to true.
inline constexpr const char* kBatchedRequestsMetadata = "batched_requests";

// The image size a served policy receives by default: the reference's evaluation feeds every
// camera at 320x240 (its 640x480 view resized; pi0's own processor then pads to its size).
inline constexpr int kServedImageWidth = 320;
inline constexpr int kServedImageHeight = 240;

}  // namespace tavis::batch::contract
