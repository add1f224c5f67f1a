// An episode's frames as rows of a dataset's data file (DataColumns), shared by the v3.0 and v2.1
// writers: the vectors, language_instruction, and the bookkeeping columns.
#pragma once

#include <cstdint>

#include "batch/dataset/lerobot_features.h"
#include "batch/dataset/parquet/parquet_writer.h"
#include "batch/dataset/recorded_episode.h"

namespace tavis::batch::dataset {

// Appends `episode` as one row group: dataset episode `episode_index`, global index from
// `first_index`, timestamps frame / fps.
void WriteEpisodeRows(parquet::ParquetWriter& writer, const RecordedEpisode& episode, const DatasetLayout& layout,
                      int64_t episode_index, int64_t first_index);

}  // namespace tavis::batch::dataset
