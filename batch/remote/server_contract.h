// The contract a policy server declares in the metadata frame it sends at connect (openpi's
// servers send a metadata map first; RoboArena's PolicyServerConfig does the same), so that the
// client sends what the policy was trained on without being told (docs/serving.md, "The contract a
// server declares"). It lives under one key of that map, `observation_contract`:
//
//   version: 1
//   cameras: {CAMERA: KEY, ...}   the cameras the policy reads (head, fixed, left_wrist, right_wrist)
//                                 and the top-level key each image travels under
//   image_width, image_height     the size of every image (HWC uint8)
//   state: {key: KEY, size: D}    observation.state's key and length (docs/observation.md)
//   n_obs_steps                   the observation history the server keeps (consecutive steps)
//   chunk_length                  rows of actions per reply
//   executed_steps                rows of each reply the client executes before it asks again
//                                 (the client's --replan-steps; 1 when the history needs every step)
//   checkpoint_sha256             optional: the served weights' SHA-256 (64 lower-case hex digits)
//   task, robot                   optional: the tavis task and robot the policy was trained for
//                                 (1 to 64 lower-case letters, digits, '-' or '_'); the client
//                                 refuses a cell of another task or robot, since such a policy
//                                 would run and only score about 0
//
// The frame comes from the network: every field is checked for its type and range, and a map
// with another key, a wrong type or a value out of range is refused naming the server, the field
// and the value. A server that sends no `observation_contract` declares nothing (a plain openpi
// server): the client keeps its own layout.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "batch/remote/msgpack_value.h"
#include "batch/remote/observation_keys.h"

namespace tavis::batch::remote {

inline constexpr const char* kServerContractMetadata = "observation_contract";
inline constexpr int kServerContractVersion = 1;

struct ServerContract {
  std::string server;    // where it was declared (ws://HOST:PORT), for messages
  ObservationKeys keys;  // the cameras, state key and image size; prompt and task as the tavis preset's
  int state_size = 0;
  int n_obs_steps = 1;
  int chunk_length = 1;
  int executed_steps = 1;
  std::string checkpoint_sha256;  // "" when not declared
  std::string task;               // "" when not declared
  std::string robot;              // "" when not declared
};

// The contract in `metadata` (the server's first frame), or nullopt when it declares none. Throws
// std::invalid_argument "policy server SERVER: observation_contract.FIELD ..." for a malformed one.
std::optional<ServerContract> ParseServerContract(const Value& metadata, const std::string& server);

// How a cell's request layout and --replan-steps differ from the contract, one line each naming
// both values ("image size: the cell sends 224x224, policy server ws://... declares 96x96"); empty
// when they agree. `state_size` is the robot's observation.state length.
std::vector<std::string> ContractConflicts(const ServerContract& contract, const ObservationKeys& sent,
                                           int replan_steps, int state_size);

// How a cell's task and robot differ from those the contract says its policy was trained for, one
// line each naming both values ("policy server ws://...'s policy was trained for task
// wait-then-act; this cell is conditional-pick"); empty when they agree or nothing is declared.
std::vector<std::string> TrainedForConflicts(const ServerContract& contract, const std::string& task,
                                             const std::string& robot);

}  // namespace tavis::batch::remote
