#include "batch/dataset/lerobot_features.h"

#include <stdexcept>

#include "batch/observation_contract.h"
#include "kinematics/action.h"

namespace tavis::batch::dataset {
namespace {

nlohmann::json Scalar(const char* dtype) { return {{"dtype", dtype}, {"shape", {1}}, {"names", nullptr}}; }

}  // namespace

const char* ToString(DatasetVersion version) { return version == DatasetVersion::kV30 ? "v3.0" : "v2.1"; }

DatasetVersion ParseDatasetVersion(const std::string& text) {
  if (text == "v3.0") return DatasetVersion::kV30;
  if (text == "v2.1") return DatasetVersion::kV21;
  throw std::invalid_argument("unknown dataset format '" + text + "' (known: v3.0, v2.1)");
}

std::string CameraVideoKey(const std::string& camera) { return batch::contract::CameraImageKey(camera); }

std::vector<VectorFeature> VectorFeatures(const DatasetLayout& layout) {
  return {{"action", kinematics::action::kSize},
          {std::string(batch::contract::kStateKey), static_cast<int>(layout.state_names.size())},
          {"observation.left_eef_pos", 3},
          {"observation.left_eef_quat", 4},
          {"observation.right_eef_pos", 3},
          {"observation.right_eef_quat", 4}};
}

nlohmann::json FeaturesJson(const DatasetLayout& layout) {
  nlohmann::json features = nlohmann::json::object();
  const nlohmann::json action_names = {"left_eef_x",   "left_eef_y",   "left_eef_z",   "left_eef_qw",  "left_eef_qx",
                                       "left_eef_qy",  "left_eef_qz",  "right_eef_x",  "right_eef_y",  "right_eef_z",
                                       "right_eef_qw", "right_eef_qx", "right_eef_qy", "right_eef_qz", "neck_roll",
                                       "neck_pitch",   "neck_yaw",     "left_gripper", "right_gripper"};
  const nlohmann::json xyz = {"x", "y", "z"}, wxyz = {"w", "x", "y", "z"};
  for (const VectorFeature& feature : VectorFeatures(layout)) {
    nlohmann::json names = feature.name == "action" ? action_names
                           : feature.name == std::string(batch::contract::kStateKey)
                               ? nlohmann::json(layout.state_names)
                           : feature.size == 3 ? xyz
                                               : wxyz;
    features[feature.name] = {{"dtype", "float32"}, {"shape", {feature.size}}, {"names", names}};
    if (feature.name != "action") continue;
    // The cameras follow the action, as in the reference's info.json.
    for (const std::string& camera : layout.cameras) {
      features[CameraVideoKey(camera)] = {{"dtype", "video"},
                                          {"shape", {layout.video.height, layout.video.width, 3}},
                                          {"names", {"height", "width", "channels"}},
                                          {"info",
                                           {{"video.height", layout.video.height},
                                            {"video.width", layout.video.width},
                                            {"video.codec", video::VideoCodecName(layout.video.codec)},
                                            {"video.pix_fmt", "yuv420p"},
                                            {"video.is_depth_map", false},
                                            {"video.fps", layout.fps},
                                            {"video.channels", 3},
                                            {"has_audio", false},
                                            {"is_depth_map", false}}}};
    }
  }
  features["language_instruction"] = {{"dtype", "string"}, {"shape", {1}}, {"names", nullptr}};
  features["timestamp"] = Scalar("float32");
  for (const char* name : {"frame_index", "episode_index", "index", "task_index"}) features[name] = Scalar("int64");
  return features;
}

std::vector<parquet::ColumnSpec> DataColumns(const DatasetLayout& layout) {
  std::vector<parquet::ColumnSpec> columns;
  for (const VectorFeature& feature : VectorFeatures(layout)) {
    columns.push_back(
        parquet::ColumnSpec::List(feature.name, parquet::ValueType::kFloat, {static_cast<std::size_t>(feature.size)}));
  }
  columns.push_back(parquet::ColumnSpec::Scalar("language_instruction", parquet::ValueType::kString));
  columns.push_back(parquet::ColumnSpec::Scalar("timestamp", parquet::ValueType::kFloat));
  for (const char* name : {"frame_index", "episode_index", "index", "task_index"}) {
    columns.push_back(parquet::ColumnSpec::Scalar(name, parquet::ValueType::kInt64));
  }
  return columns;
}

}  // namespace tavis::batch::dataset
