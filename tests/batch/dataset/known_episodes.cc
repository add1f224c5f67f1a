#include "tests/batch/dataset/known_episodes.h"

#include <cstddef>

#include "batch/dataset/lerobot_writer.h"
#include "batch/dataset/video/episode_encoder.h"
#include "batch/dataset/video/video_log.h"

namespace tavis::batch::dataset::testing {
namespace {

constexpr int kWidth = 64, kHeight = 48;

std::vector<float> KnownRows(int feature, int episode, int frames, int dims) {
  std::vector<float> values;
  for (int frame = 0; frame < frames; ++frame) {
    for (int dim = 0; dim < dims; ++dim) values.push_back(KnownValue(feature, episode, frame, dim));
  }
  return values;
}

}  // namespace

float KnownValue(int feature, int episode, int frame, int dim) {
  return 0.1f * static_cast<float>(feature * 1000 + episode * 100 + frame) - 0.3f * static_cast<float>(dim);
}

KnownDataset MakeKnownDataset(DatasetVersion version) {
  video::ShowOnlyVideoErrors();  // x264's per-stream report would bury the test output
  KnownDataset dataset;
  DatasetLayout& layout = dataset.layout;
  layout.version = version;
  layout.fps = kKnownFps;
  layout.robot_type = "known";
  layout.cameras = {"head", "left_wrist"};
  layout.video.width = kWidth;
  layout.video.height = kHeight;
  layout.video.fps = kKnownFps;
  for (int i = 0; i < kKnownStateSize; ++i) layout.state_names.push_back("s" + std::to_string(i));
  layout.tasks = {"PickTask", "PlaceTask"};
  const std::vector<VectorFeature> features = VectorFeatures(layout);
  for (std::size_t e = 0; e < kKnownLengths.size(); ++e) {
    const int episode = static_cast<int>(e);
    const int frames = kKnownLengths[e];
    RecordedEpisode recorded;
    recorded.source_episode = 10 + episode;
    recorded.task_index = kKnownTaskIndex[e];
    recorded.prompt = "prompt of task " + std::to_string(recorded.task_index);
    recorded.frames = frames;
    std::vector<std::vector<float>*> columns = {&recorded.action,        &recorded.state,
                                                &recorded.left_eef_pos,  &recorded.left_eef_quat,
                                                &recorded.right_eef_pos, &recorded.right_eef_quat};
    for (std::size_t f = 0; f < features.size(); ++f)
      *columns[f] = KnownRows(static_cast<int>(f), episode, frames, features[f].size);
    dataset.frames.emplace_back();
    for (std::size_t camera = 0; camera < layout.cameras.size(); ++camera) {
      video::EpisodeEncoder encoder(layout.video, layout.cameras[camera]);
      ImageStats stats;
      std::vector<RgbFrame>& encoded = dataset.frames.back().emplace_back();
      for (int k = 0; k < frames; ++k) {
        // Each camera's frames differ from the other's, so a swapped stream shows.
        encoded.push_back(SyntheticFrame(kWidth, kHeight, 2 * episode + static_cast<int>(camera), k));
        encoder.WriteFrame(encoded.back().data(), encoded.back().size());
        stats.AddFrame(encoded.back().data(), kWidth, kHeight);
      }
      recorded.videos.push_back(encoder.Finish());
      recorded.image_stats.push_back(stats);
    }
    dataset.episodes.push_back(std::move(recorded));
  }
  return dataset;
}

void WriteKnownDataset(const KnownDataset& dataset, const std::string& root) {
  const std::unique_ptr<DatasetWriter> writer = MakeDatasetWriter(root, dataset.layout);
  for (const RecordedEpisode& episode : dataset.episodes) writer->Add(episode);
  writer->Finish();
}

}  // namespace tavis::batch::dataset::testing
