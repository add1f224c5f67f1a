#include "batch/dataset/reader/dataset_galt.h"

#include <utility>

namespace tavis::batch::dataset::reader {

DatasetGalt ComputeDatasetGalt(DatasetActions actions, double fps) {
  DatasetGalt galt;
  galt.actions = std::move(actions);
  galt.fps = fps;
  galt.views.reserve(galt.actions.episodes.size());
  for (const EpisodeActions& episode : galt.actions.episodes) {
    galt.views.push_back({episode.values.data(), episode.num_steps, kDatasetActionWidth});
  }
  galt.results = kinematics::ComputeGaltBatch(galt.views, fps);
  return galt;
}

std::vector<double> DatasetGaltSeconds(const std::filesystem::path& dataset_dir) {
  DatasetActions actions = ReadDatasetActions(dataset_dir);
  const double fps = actions.info.fps;
  const DatasetGalt galt = ComputeDatasetGalt(std::move(actions), fps);
  std::vector<double> seconds;
  for (const kinematics::GaltResult& result : galt.results) {
    if (result.galt_s) seconds.push_back(*result.galt_s);
  }
  return seconds;
}

}  // namespace tavis::batch::dataset::reader
