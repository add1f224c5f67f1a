#include "batch/dataset/episode_rows.h"

#include <string>
#include <vector>

#include "batch/observation_contract.h"

namespace tavis::batch::dataset {

void WriteEpisodeRows(parquet::ParquetWriter& writer, const RecordedEpisode& episode, const DatasetLayout& layout,
                      int64_t episode_index, int64_t first_index) {
  const std::size_t frames = static_cast<std::size_t>(episode.frames);
  parquet::RowGroupBuilder rows = writer.NewRowGroup(frames);
  rows.AddList("action", episode.action);
  rows.AddList(batch::contract::kStateKey, episode.state);
  rows.AddList("observation.left_eef_pos", episode.left_eef_pos);
  rows.AddList("observation.left_eef_quat", episode.left_eef_quat);
  rows.AddList("observation.right_eef_pos", episode.right_eef_pos);
  rows.AddList("observation.right_eef_quat", episode.right_eef_quat);
  rows.Add("language_instruction", std::vector<std::string>(frames, episode.prompt));
  std::vector<float> timestamps(frames);
  std::vector<int64_t> frame_index(frames), index(frames);
  for (std::size_t frame = 0; frame < frames; ++frame) {
    timestamps[frame] = static_cast<float>(static_cast<double>(frame) / layout.fps);
    frame_index[frame] = static_cast<int64_t>(frame);
    index[frame] = first_index + static_cast<int64_t>(frame);
  }
  rows.Add("timestamp", timestamps);
  rows.Add("frame_index", frame_index);
  rows.Add("episode_index", std::vector<int64_t>(frames, episode_index));
  rows.Add("index", index);
  rows.Add("task_index", std::vector<int64_t>(frames, episode.task_index));
  writer.WriteRowGroup(rows);
}

}  // namespace tavis::batch::dataset
