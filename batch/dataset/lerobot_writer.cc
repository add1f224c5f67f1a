#include "batch/dataset/lerobot_writer.h"

namespace tavis::batch::dataset {

// Defined with their layouts (lerobot_v30_writer.cc, lerobot_v21_writer.cc).
std::unique_ptr<DatasetWriter> MakeV30Writer(const std::string& root, const DatasetLayout& layout);
std::unique_ptr<DatasetWriter> MakeV21Writer(const std::string& root, const DatasetLayout& layout);

std::unique_ptr<DatasetWriter> MakeDatasetWriter(const std::string& root, const DatasetLayout& layout) {
  return layout.version == DatasetVersion::kV30 ? MakeV30Writer(root, layout) : MakeV21Writer(root, layout);
}

}  // namespace tavis::batch::dataset
