// How a served policy's request is laid out. openpi's served policies each read their own keys
// (policy-interfaces.md A1: LIBERO's "observation/image", ALOHA's nested "images"/"cam_high"
// channel-first), so the layout is a preset or a YAML file. The default preset `tavis` is the
// observation contract itself (batch/observation_contract.h: the dataset's keys
// observation.images.OBS_HEAD ..., observation.state, prompt and task, 320x240), built in so that
// it cannot drift from what `tavis demos` writes; `libero` and `aloha` are shipped YAML files
// (configs/policy_keys/<name>.yaml), and a user's file has the same schema. A dataset's
// meta/info.json can give the layout too (LoadDatasetKeys), so a policy is served exactly what it
// was trained on.
//
//   cameras:          camera -> key, for the cameras the policy receives (head, fixed,
//     head: KEY         left_wrist, right_wrist). A KEY is a string (a top-level key) or a list
//     fixed: KEY        of strings (a path into nested maps). `fixed` is the key of the fixed
//     ...               camera under the fixed protocol; without it the fixed camera travels
//                       under head's key.
//   state: KEY        observation.state (float32, docs/observation.md)
//   prompt: KEY       the episode's instruction (str)
//   task: KEY         optional: the instruction again under a second key (LeRobot reads "task")
//   image_layout: hwc | chw        uint8 H x W x 3, or 3 x H x W
//   image_width: W, image_height: H  the size the policy receives (--image-size overrides)
//   letterbox: bool   render at the cameras' 4:3 aspect fitted into W x H and pad with black,
//                     as openpi's clients do with resize_with_pad; otherwise render at W x H
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "batch/camera_protocol.h"
#include "batch/policy.h"
#include "batch/remote/msgpack_value.h"

namespace tavis::batch::remote {

using KeyPath = std::vector<std::string>;  // one entry: a top-level key; more: nested maps

enum class ImageLayout { kHwc, kChw };

struct ObservationKeys {
  std::string source;                                    // the preset's name or the file's path
  std::vector<std::pair<std::string, KeyPath>> cameras;  // in the order of batch::SceneCameraNames()
  KeyPath state;
  KeyPath prompt;
  KeyPath task;  // empty: the instruction travels under `prompt` only
  ImageLayout image_layout = ImageLayout::kHwc;
  int image_width = 320;
  int image_height = 240;
  bool letterbox = false;

  // The policy's cameras under the head protocol (every listed camera but `fixed`, in order).
  std::vector<std::string> PolicyCameras() const;
  // The key `camera` travels under (a name from batch::SceneCameraNames(), as rendered under the
  // protocol: "fixed" in place of "head" under the fixed protocol).
  const KeyPath& KeyOf(const std::string& camera) const;
};

// Names of the shipped presets, for --help and errors: "tavis, libero, aloha".
std::string KeyPresetNames();

// The default preset: the observation contract (keys of batch/observation_contract.h, HWC,
// 320x240, no letterbox).
ObservationKeys ContractKeys();

// A preset name (`tavis`, or configs/policy_keys/<name>.yaml in config_dir) or a path to a YAML
// file of that schema. Throws configs::ConfigError naming the file and key for an unknown key or
// camera, a key that is empty, given twice or one of the request fields (env_index, episode_index,
// step, is_first, batch_size), no camera, a bad layout or size; std::invalid_argument for a name
// that is neither a preset nor a file.
ObservationKeys LoadObservationKeys(const std::string& preset_or_path, const std::string& config_dir);

// The same with the file the layout was read from ("" for the built-in preset) and its bytes, read
// once, for a caller that also records the file (a cell's identity).
struct LoadedObservationKeys {
  ObservationKeys keys;
  std::string file;
  std::string text;
};
LoadedObservationKeys LoadObservationKeysWithFile(const std::string& preset_or_path, const std::string& config_dir);

// The layout a policy trained on a LeRobot dataset (v3.0 or v2.1, e.g. written by `tavis demos`)
// reads: its image features observation.images.OBS_* as the cameras, at the features' size, with
// the contract's state, prompt and task keys. Throws std::invalid_argument naming the file and
// what is missing or malformed (no meta/info.json, no image feature of a scene camera, a state
// that is not `state_size` long: a dataset of another robot).
ObservationKeys LoadDatasetKeys(const std::string& dataset_dir, int state_size);

// How `served` differs from `expected` (keys of each camera, state, prompt and task, the image
// layout and size, letterboxing), one line each; empty when they agree.
std::vector<std::string> LayoutDifferences(const ObservationKeys& served, const ObservationKeys& expected);

// The size the cameras are rendered at for these keys: W x H, or with letterbox the largest 4:3
// size (even, for the renderer's tiles) that fits in W x H.
std::pair<int, int> RenderSize(const ObservationKeys& keys);

// The request for `env`: its cameras (the observation's images, in the order of `cameras`, the
// names the env renders under the protocol), letterboxed and laid out as the keys say, its
// observation.state, its prompt (and task), and the request fields env_index, episode_index, step
// (the 20 Hz policy step within the episode) and is_first (step 0). Throws std::logic_error when
// the observation lacks images or proprioception (the episode driver provides both).
Value BuildRequest(const batch::Observation& observation, const ObservationKeys& keys,
                   const std::vector<std::string>& cameras, int env);

// One request for all of `envs` (ascending env slots): the same keys, each value stacked on a
// leading axis of length envs.size() (images N x ..., state N x D, prompt and task lists of N
// strings, env_index, episode_index and step int64 arrays, is_first a bool array), plus
// batch_size = N. `envs` must not be empty.
Value BuildBatchRequest(const batch::Observation& observation, const ObservationKeys& keys,
                        const std::vector<std::string>& cameras, const std::vector<int>& envs);

}  // namespace tavis::batch::remote
