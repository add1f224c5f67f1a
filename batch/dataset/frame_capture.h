// One recorded frame appended to an episode, shared by the scripted expert's recorder
// (demo_recorder) and a cell's rollout recorder (batch/rollout/rollout_recorder): the frame's
// action with the proprioception after it, and each camera's image into its encoder and stats.
#pragma once

#include "batch/dataset/recorded_episode.h"
#include "batch/dataset/video/episode_encoder.h"
#include "batch/proprioception.h"
#include "kinematics/action.h"
#include "render/image_batch.h"

namespace tavis::batch::dataset {

// Appends `action` and slot's state and end-effector poses as one row of each column.
void AppendFrameState(const batch::ProprioceptionBatch& proprioception, int slot, const kinematics::Action& action,
                      RecordedEpisode* episode);

// Encodes slot's image of `camera` as the episode's next frame and adds it to the camera's stats.
void AppendFrameImage(const render::ImageBatch& images, int slot, int camera, video::EpisodeEncoder* encoder,
                      ImageStats* stats);

}  // namespace tavis::batch::dataset
