// Cells the tests of cell.json and summary.json share: one of a built-in policy with every
// setting of the scene away from its default, and one of a served policy with its options given.
#pragma once

#include "batch/cell/cell_settings.h"

namespace tavis::batch::cell {

inline EvaluationCellConfig HoldCellOnReachy() {
  EvaluationCellConfig config;
  config.task = "wait-then-act";
  config.robot = "reachy2";
  config.split = scenarios::Split::kOodInitPose;
  config.camera = CameraProtocol::kFixed;
  config.policy = "hold";
  config.seed = 18446744073709551615ULL;
  return config;
}

inline EvaluationCellConfig ServedCellWithOptions() {
  EvaluationCellConfig config;
  config.policy = "openpi";
  config.servers = {"ws://a:1", "ws://b:2"};
  config.replan_steps = 5;
  config.observation_keys = "aloha";
  config.observation_dataset = "/data/set";
  config.serving = remote::ServingMode::kBatched;
  return config;
}

}  // namespace tavis::batch::cell
