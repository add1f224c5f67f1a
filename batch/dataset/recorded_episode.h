// One scripted-expert episode as a dataset stores it: per frame the observation after the
// frame's action and that action (the reference's recording, tavis-reference-spec.md 7.4: frame t
// pairs o_{t+1} with a_t, and the step that ends the episode is not recorded), plus each camera's
// encoded video and image statistics. Filled by DemoRecorder, consumed by LeRobotWriter.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "batch/dataset/feature_stats.h"
#include "batch/dataset/video/episode_encoder.h"

namespace tavis::batch::dataset {

struct RecordedEpisode {
  int64_t source_episode = 0;  // the simulator's episode index (its randomness is (seed, index))
  int task_index = 0;          // row of the dataset's task table
  std::string prompt;          // language_instruction, the same on every frame
  int64_t frames = 0;
  // Row-major (frames x size) float32, in the dataset's feature order.
  std::vector<float> action;                         // 19, the canonical action
  std::vector<float> state;                          // the robot's observation.state
  std::vector<float> left_eef_pos, right_eef_pos;    // 3, canonical frame
  std::vector<float> left_eef_quat, right_eef_quat;  // 4, world frame (w, x, y, z)
  std::vector<video::EncodedEpisode> videos;         // per recorded camera, in the dataset's camera order
  std::vector<ImageStats> image_stats;               // per recorded camera
};

}  // namespace tavis::batch::dataset
