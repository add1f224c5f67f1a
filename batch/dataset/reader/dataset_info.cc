#include "batch/dataset/reader/dataset_info.h"

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace tavis::batch::dataset::reader {
namespace fs = std::filesystem;

namespace {

[[noreturn]] void Fail(const fs::path& file, const std::string& what) {
  throw std::runtime_error(file.string() + ": " + what);
}

DatasetVersion VersionOf(const std::string& version, const fs::path& file) {
  if (version == "v3.0") return DatasetVersion::kV30;
  if (version == "v2.1") return DatasetVersion::kV21;
  Fail(file, "unknown codebase_version \"" + version + "\" (supported: v3.0, v2.1)");
}

}  // namespace

std::vector<fs::path> ParquetFilesUnder(const fs::path& root, const std::string& dir_prefix,
                                        const std::string& file_prefix) {
  std::vector<fs::path> files;
  if (!fs::is_directory(root)) return files;
  for (const fs::directory_entry& dir : fs::directory_iterator(root)) {
    if (!dir.is_directory() || dir.path().filename().string().rfind(dir_prefix, 0) != 0) continue;
    for (const fs::directory_entry& file : fs::directory_iterator(dir.path())) {
      const std::string name = file.path().filename().string();
      if (file.is_regular_file() && name.rfind(file_prefix, 0) == 0 && file.path().extension() == ".parquet") {
        files.push_back(file.path());
      }
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

DatasetInfo ReadDatasetInfo(const fs::path& dataset_dir) {
  const fs::path file = dataset_dir / "meta" / "info.json";
  std::ifstream in(file);
  if (!in) Fail(file, "missing (not a LeRobot dataset directory?)");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    Fail(file, std::string("not valid JSON: ") + error.what());
  }
  if (!json.is_object()) Fail(file, "not a JSON object");

  DatasetInfo info;
  const nlohmann::json version = json.value("codebase_version", nlohmann::json());
  if (!version.is_string()) Fail(file, "no codebase_version string, got " + version.dump());
  info.codebase_version = version.get<std::string>();
  info.version = VersionOf(info.codebase_version, file);

  const nlohmann::json fps = json.value("fps", nlohmann::json());
  if (!fps.is_number() || !(fps.get<double>() > 0.0)) Fail(file, "fps must be a positive number, got " + fps.dump());
  info.fps = fps.get<double>();

  const nlohmann::json robot = json.value("robot_type", nlohmann::json());
  if (robot.is_string()) {
    info.robot_type = robot.get<std::string>();
  } else if (!robot.is_null()) {
    Fail(file, "robot_type must be a string or null, got " + robot.dump());
  }

  const nlohmann::json episodes = json.value("total_episodes", nlohmann::json());
  if (!episodes.is_number_integer() || episodes.get<std::int64_t>() < 0) {
    Fail(file, "total_episodes must be a non-negative integer, got " + episodes.dump());
  }
  info.total_episodes = episodes.get<std::int64_t>();
  return info;
}

std::vector<fs::path> DataFiles(const fs::path& dataset_dir, DatasetVersion version) {
  const fs::path data = dataset_dir / "data";
  std::vector<fs::path> files =
      version == DatasetVersion::kV30 ? ParquetFilesUnder(data, "", "") : ParquetFilesUnder(data, "chunk-", "episode_");
  if (files.empty()) {
    Fail(data, version == DatasetVersion::kV30 ? "no data files data/*/*.parquet"
                                               : "no data files data/chunk-*/episode_*.parquet");
  }
  return files;
}

}  // namespace tavis::batch::dataset::reader
