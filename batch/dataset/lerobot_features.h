// What a TAVIS demonstration dataset holds, in LeRobot's terms (lerobot-v3-format.md 2 and 8,
// tavis-reference-spec.md 9.1): the features and their order in info.json, the camera video keys
// (observation.images.OBS_HEAD, ...), and the columns of the per-frame data files.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/dataset/parquet/parquet_schema.h"
#include "batch/dataset/video/video_settings.h"

namespace tavis::batch::dataset {

enum class DatasetVersion { kV30, kV21 };  // v2.1: one file per episode, for openpi fine-tuning

// "v3.0" / "v2.1"; ParseDatasetVersion throws std::invalid_argument naming other values.
const char* ToString(DatasetVersion version);
DatasetVersion ParseDatasetVersion(const std::string& text);

struct DatasetLayout {
  DatasetVersion version = DatasetVersion::kV30;
  int fps = 60;
  std::string robot_type;                // the robot's name
  std::vector<std::string> cameras;      // scene camera names (head, fixed, left_wrist, right_wrist)
  video::VideoSettings video;            // size, codec; fps equals `fps`
  std::vector<std::string> state_names;  // observation.state entries
  std::vector<std::string> tasks;        // LeRobot tasks (the reference's task class names), by task_index
  // v3.0: a new data file (video file) starts when the current one would reach this size. LeRobot's
  // defaults; tests make them small to see files roll over.
  double data_files_size_mb = 100;
  double video_files_size_mb = 200;
};

// The dataset's key of a scene camera: head -> observation.images.OBS_HEAD, fixed -> OBS_FIXED,
// left_wrist -> OBS_WRIST_LEFT, right_wrist -> OBS_WRIST_RIGHT. Throws std::invalid_argument for
// another name.
std::string CameraVideoKey(const std::string& camera);

// The per-frame float vectors, in info.json order, with their sizes.
struct VectorFeature {
  std::string name;
  int size;
};
std::vector<VectorFeature> VectorFeatures(const DatasetLayout& layout);

// LeRobot's five bookkeeping features.
inline const std::vector<std::string> kIndexFeatures = {"timestamp", "frame_index", "episode_index", "index",
                                                        "task_index"};

// info.json's "features": every feature's dtype, shape and names (video features with their info).
nlohmann::json FeaturesJson(const DatasetLayout& layout);

// The data files' columns (no video: cameras live in the mp4 files).
std::vector<parquet::ColumnSpec> DataColumns(const DatasetLayout& layout);

}  // namespace tavis::batch::dataset
