// A small scripted-expert cell whose head and fixed cameras are rendered every policy tick, and
// the check that a perturbed copy of it records exactly its episodes: shared by the perturbation
// axes' tests (a view axis must not reach the expert, which acts on privileged state).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "batch/cell/evaluation_cell.h"

namespace tavis::batch::testing {

inline cell::EvaluationCellConfig RenderedExpertCell(const std::string& robot, int episodes, uint64_t seed) {
  cell::EvaluationCellConfig config;
  config.task = "clutter-pick-cube";
  config.robot = robot;
  config.policy = "expert";
  config.episodes = episodes;
  config.envs = episodes;
  config.seed = seed;
  config.keep_actions = true;
  config.config_dir = TAVIS_CONFIG_DIR;
  config.render_cameras = {"head", "fixed"};  // rendered under the perturbation every policy tick
  config.image_width = 32;
  config.image_height = 24;
  return config;
}

// The same episodes, ends, lengths and commanded actions, bit for bit.
inline void ExpectSameEpisodes(const cell::CellResult& result, const cell::CellResult& reference) {
  ASSERT_EQ(result.episodes.size(), reference.episodes.size());
  for (std::size_t i = 0; i < result.episodes.size(); ++i) {
    EXPECT_EQ(result.episodes[i].success, reference.episodes[i].success);
    EXPECT_EQ(result.episodes[i].end, reference.episodes[i].end);
    EXPECT_EQ(result.episodes[i].length_control_ticks, reference.episodes[i].length_control_ticks);
    EXPECT_EQ(result.episodes[i].actions, reference.episodes[i].actions) << "episode " << i;
  }
}

}  // namespace tavis::batch::testing
