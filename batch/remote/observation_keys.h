// How a served policy's request is laid out. openpi's served policies each read their own keys
// (policy-interfaces.md A1: LIBERO's "observation/image", ALOHA's nested "images"/"cam_high"
// channel-first, the reference's LeRobot "observation.images.head"), so the layout is a YAML
// file: a shipped preset (configs/policy_keys/<name>.yaml: tavis, libero, aloha) or the user's.
//
//   cameras:          camera -> key, for the cameras the policy receives (head, fixed,
//     head: KEY         left_wrist, right_wrist). A KEY is a string (a top-level key) or a list
//     fixed: KEY        of strings (a path into nested maps). `fixed` is the key of the fixed
//     ...               camera under the fixed protocol; without it the fixed camera travels
//                       under head's key.
//   state: KEY        observation.state (float32, docs/observation.md)
//   prompt: KEY       the episode's instruction (str)
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

namespace tavis::remote {

using KeyPath = std::vector<std::string>;  // one entry: a top-level key; more: nested maps

enum class ImageLayout { kHwc, kChw };

struct ObservationKeys {
  std::string source;                                     // the preset's name or the file's path
  std::vector<std::pair<std::string, KeyPath>> cameras;   // in the order of batch::SceneCameraNames()
  KeyPath state;
  KeyPath prompt;
  ImageLayout image_layout = ImageLayout::kHwc;
  int image_width = 224;
  int image_height = 224;
  bool letterbox = false;

  // The policy's cameras under the head protocol (every listed camera but `fixed`, in order).
  std::vector<std::string> PolicyCameras() const;
  // The key `camera` travels under (a name from batch::SceneCameraNames(), as rendered under the
  // protocol: "fixed" in place of "head" under the fixed protocol).
  const KeyPath& KeyOf(const std::string& camera) const;
};

// Names of the shipped presets, for --help and errors: "tavis, libero, aloha".
std::string KeyPresetNames();

// A preset name (configs/policy_keys/<name>.yaml in config_dir) or a path to a YAML file of that
// schema. Throws configs::ConfigError naming the file and key for an unknown key or camera, a key
// that is empty or given twice, no camera, a bad layout or size; std::invalid_argument for a
// name that is neither a preset nor a file.
ObservationKeys LoadObservationKeys(const std::string& preset_or_path, const std::string& config_dir);

// The size the cameras are rendered at for these keys: W x H, or with letterbox the largest 4:3
// size (even, for the renderer's tiles) that fits in W x H.
std::pair<int, int> RenderSize(const ObservationKeys& keys);

// The request for `env`: its cameras (the observation's images, in the order of `cameras`, the
// names the env renders under the protocol), letterboxed and laid out as the keys say, its
// observation.state and its prompt. Throws std::logic_error when the observation lacks images
// or proprioception (the episode driver provides both).
Value BuildRequest(const batch::Observation& observation, const ObservationKeys& keys,
                   const std::vector<std::string>& cameras, int env);

}  // namespace tavis::remote
