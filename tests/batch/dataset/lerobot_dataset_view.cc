#include "tests/batch/dataset/lerobot_dataset_view.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "tests/batch/dataset/node_parquet.h"

namespace tavis::batch::dataset::testing {
namespace {

namespace fs = std::filesystem;

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  return nlohmann::json::parse(in);
}

std::vector<nlohmann::json> ReadJsonLines(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::vector<nlohmann::json> lines;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) lines.push_back(nlohmann::json::parse(line));
  }
  return lines;
}

// Python's str.format for the templates' fields: {name} and {name:0Nd}.
std::string FormatTemplate(const std::string& pattern, const std::map<std::string, int64_t>& numbers,
                           const std::string& video_key) {
  static const std::regex field(R"(\{(\w+)(?::0(\d+)d)?\})");
  std::string out;
  auto begin = std::sregex_iterator(pattern.begin(), pattern.end(), field);
  std::size_t last = 0;
  for (auto it = begin; it != std::sregex_iterator(); ++it) {
    const std::smatch& match = *it;
    out += pattern.substr(last, static_cast<std::size_t>(match.position()) - last);
    const std::string name = match[1];
    if (name == "video_key") {
      out += video_key;
    } else {
      std::string digits = std::to_string(numbers.at(name));
      const std::size_t width = match[2].matched ? std::stoul(match[2]) : 0;
      if (digits.size() < width) digits.insert(0, width - digits.size(), '0');
      out += digits;
    }
    last = static_cast<std::size_t>(match.position() + match.length());
  }
  return out + pattern.substr(last);
}

void LoadV30Episodes(DatasetView& view) {
  const std::vector<std::string> files = SortedFiles(view.root, "meta/episodes", "parquet");
  if (files.size() != 1) throw std::runtime_error("expected one episodes file in " + view.root);
  view.episodes_table = ReadWithIndependentReaders(files.front());
  for (const nlohmann::json& row : view.episodes_table["hyparquet"]["rows"]) {
    EpisodeEntry entry;
    entry.length = Int(row["length"]);
    entry.tasks = row["tasks"].get<std::vector<std::string>>();
    entry.from_index = Int(row["dataset_from_index"]);
    entry.to_index = Int(row["dataset_to_index"]);
    for (const std::string& key : view.video_keys) {
      const std::string prefix = "videos/" + key + "/";
      VideoSpan span;
      span.path = view.root + "/" +
                  FormatTemplate(view.info["video_path"],
                                 {{"chunk_index", Int(row[prefix + "chunk_index"])},
                                  {"file_index", Int(row[prefix + "file_index"])}},
                                 key);
      span.from_timestamp = row[prefix + "from_timestamp"].get<double>();
      span.to_timestamp = row[prefix + "to_timestamp"].get<double>();
      entry.videos[key] = span;
    }
    view.episodes.push_back(entry);
  }
  view.tasks_table = ReadWithIndependentReaders(view.root + "/meta/tasks.parquet");
  for (const nlohmann::json& row : view.tasks_table["hyparquet"]["rows"]) {
    if (Int(row["task_index"]) != static_cast<int64_t>(view.tasks.size()))
      throw std::runtime_error("tasks.parquet out of order");
    view.tasks.push_back(row["task"]);
  }
  view.data_files = SortedFiles(view.root, "data", "parquet");
}

void LoadV21Episodes(DatasetView& view) {
  const int64_t chunks_size = view.info["chunks_size"];
  int64_t from = 0;
  for (const nlohmann::json& line : ReadJsonLines(view.root + "/meta/episodes.jsonl")) {
    const int64_t index = line["episode_index"];
    if (index != static_cast<int64_t>(view.episodes.size())) throw std::runtime_error("episodes.jsonl out of order");
    const std::map<std::string, int64_t> numbers = {{"episode_chunk", index / chunks_size}, {"episode_index", index}};
    EpisodeEntry entry;
    entry.length = line["length"];
    entry.tasks = line["tasks"].get<std::vector<std::string>>();
    entry.from_index = from;
    entry.to_index = from += entry.length;
    for (const std::string& key : view.video_keys) {
      entry.videos[key] = {view.root + "/" + FormatTemplate(view.info["video_path"], numbers, key), 0,
                           static_cast<double>(entry.length) / view.fps};
    }
    view.data_files.push_back(view.root + "/" + FormatTemplate(view.info["data_path"], numbers, ""));
    view.episodes.push_back(entry);
  }
  for (const nlohmann::json& line : ReadJsonLines(view.root + "/meta/tasks.jsonl")) {
    if (line["task_index"].get<int64_t>() != static_cast<int64_t>(view.tasks.size()))
      throw std::runtime_error("tasks.jsonl out of order");
    view.tasks.push_back(line["task"]);
  }
}

}  // namespace

int64_t Int(const nlohmann::json& value) {
  return value.is_string() ? std::stoll(value.get<std::string>()) : value.get<int64_t>();
}

std::vector<std::string> SortedFiles(const std::string& root, const std::string& folder, const std::string& extension) {
  std::vector<std::string> files;
  if (!fs::exists(root + "/" + folder)) return files;
  for (const auto& chunk : fs::directory_iterator(root + "/" + folder)) {
    if (!chunk.is_directory()) continue;
    for (const auto& file : fs::directory_iterator(chunk.path())) {
      if (file.path().extension() == "." + extension) files.push_back(file.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

DatasetView LoadDataset(const std::string& root) {
  DatasetView view;
  view.root = root;
  view.info = ReadJson(root + "/meta/info.json");
  view.stats = ReadJson(root + "/meta/stats.json");
  view.fps = view.info["fps"];
  for (const auto& [name, feature] : view.info["features"].items()) {
    if (feature["dtype"] == "video") view.video_keys.push_back(name);
  }
  if (view.info["codebase_version"] == "v3.0") {
    LoadV30Episodes(view);
  } else {
    LoadV21Episodes(view);
  }
  for (const std::string& file : view.data_files) {
    const nlohmann::json report = ReadWithIndependentReaders(file);
    for (const nlohmann::json& row : report["hyparquet"]["rows"]) view.hyparquet_rows.push_back(row);
    for (const nlohmann::json& row : report["duckdb"]["rows"]) view.duckdb_rows.push_back(row);
  }
  return view;
}

}  // namespace tavis::batch::dataset::testing
