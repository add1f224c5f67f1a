// A cell folder's name, in the two forms results folders already have on disk: `tavis eval`'s
// (the levels after the seed) and a sweep's (the levels in the label), so a resume finds them.
#include "batch/cell/cell_folder_name.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace tavis::batch::cell {
namespace {

EvaluationCellConfig PerturbedCell() {
  EvaluationCellConfig config;
  config.task = "conditional-pick";
  config.robot = "reachy2";
  config.split = scenarios::Split::kOodSpatial;
  config.camera = CameraProtocol::kFixed;
  config.seed = 3;
  config.perturbations = {"camera:fov-wide", "sensor:noise-low"};
  return config;
}

TEST(CellFolderName, BaseCellIsTaskRobotSplitCameraLabelSeed) {
  EvaluationCellConfig config;
  for (const PerturbationsIn where : {PerturbationsIn::kTail, PerturbationsIn::kLabel}) {
    EXPECT_EQ(CellFolderName(config, "expert", where), "clutter-pick-cube_gr1t2_id_head_expert_s0");
  }
}

TEST(CellFolderName, EvalPutsTheLevelsAndTheEpisodeAfterTheSeed) {
  EvaluationCellConfig config = PerturbedCell();
  config.episode_start = 12;
  EXPECT_EQ(
      CellFolderName(config, "expert-head-still", PerturbationsIn::kTail, /*one_episode=*/true),
      "conditional-pick_reachy2_ood-spatial_fixed_expert-head-still_s3_ep12_p-camera-fov-wide_p-sensor-noise-low");
}

TEST(CellFolderName, SweepPutsTheLevelsInTheLabel) {
  EXPECT_EQ(CellFolderName(PerturbedCell(), "pi0", PerturbationsIn::kLabel),
            "conditional-pick_reachy2_ood-spatial_fixed_pi0.camera.fov-wide.sensor.noise-low_s3");
}

TEST(CellFolderName, ALevelThatIsNotAxisColonLevelIsRefused) {
  EvaluationCellConfig config;
  config.perturbations = {"fov-wide"};
  EXPECT_THROW(CellFolderName(config, "expert", PerturbationsIn::kTail), std::invalid_argument);
}

}  // namespace
}  // namespace tavis::batch::cell
