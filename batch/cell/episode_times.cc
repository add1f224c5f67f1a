#include "batch/cell/episode_times.h"

#include <stdexcept>

#include "batch/cell/statistics.h"

namespace tavis::batch::cell {
namespace {

constexpr const char* kSpanKey = "span_s";

// The file's columns: the span, then each part.
constexpr int kColumns = 1 + EpisodeTimes::kNumParts;

const char* ColumnKey(int column) {
  return column == 0 ? kSpanKey : EpisodeTimePartKey(static_cast<EpisodeTimes::Part>(column - 1));
}

double& Column(EpisodeTimes& times, int column) {
  return column == 0 ? times.span_s : times.parts[static_cast<std::size_t>(column - 1)];
}

double Seconds(const nlohmann::json& line, const char* key) {
  const nlohmann::json& value = line.at(key);
  if (!value.is_number() || value.get<double>() < 0.0)
    throw std::invalid_argument(std::string(key) + " " + value.dump() + " is not a number of seconds");
  return value.get<double>();
}

}  // namespace

const char* EpisodeTimePartKey(EpisodeTimes::Part part) {
  switch (part) {
    case EpisodeTimes::kPolicy: return "policy_s";
    case EpisodeTimes::kPhysics: return "physics_s";
    case EpisodeTimes::kRender: return "render_s";
    case EpisodeTimes::kVideo: return "video_s";
    case EpisodeTimes::kOther:
    case EpisodeTimes::kNumParts: break;
  }
  return "other_s";
}

std::string EpisodeTimesJsonLine(int64_t episode, const std::optional<EpisodeTimes>& times) {
  nlohmann::json line = {{"episode", episode}};
  EpisodeTimes values = times.value_or(EpisodeTimes{});
  for (int column = 0; column < kColumns; ++column) {
    line[ColumnKey(column)] = times ? nlohmann::json(Column(values, column)) : nlohmann::json();
  }
  return line.dump();
}

EpisodeTimesLine ParseEpisodeTimesJsonLine(const std::string& text) {
  const nlohmann::json line = nlohmann::json::parse(text);
  EpisodeTimesLine parsed;
  parsed.episode = line.at("episode").get<int64_t>();
  if (line.at(kSpanKey).is_null()) return parsed;
  EpisodeTimes times;
  for (int column = 0; column < kColumns; ++column) Column(times, column) = Seconds(line, ColumnKey(column));
  parsed.times = times;
  return parsed;
}

nlohmann::json EpisodeTimesSummaryJson(const std::vector<EpisodeTimes>& measured) {
  nlohmann::json summary = {{"file", "episode_times.jsonl"}, {"measured", measured.size()}};
  for (int column = 0; column < kColumns; ++column) {
    if (measured.empty()) {
      summary[ColumnKey(column)] = nullptr;
      continue;
    }
    std::vector<double> values;
    for (EpisodeTimes times : measured) values.push_back(Column(times, column));
    double total = 0.0;
    for (double value : values) total += value;
    summary[ColumnKey(column)] = {
        {"total_s", total}, {"median_s", Median(values)}, {"p90_s", NearestRank(values, 0.9)}};
  }
  return summary;
}

}  // namespace tavis::batch::cell
