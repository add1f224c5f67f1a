#include "batch/cell/cell_profile.h"

#include <algorithm>
#include <cstdio>
#include <functional>

#include <nlohmann/json.hpp>

namespace tavis::batch::cell {

double CellProfile::work_seconds() const {
  double total = 0.0;
  for (const auto& stage : stages) total += stage.second;
  return total;
}

double CellProfile::critical_path_seconds() const {
  if (!per_slot) return serial_seconds + slowest_env_seconds;
  double longest = 0.0;
  for (const EpisodeCost& cost : episodes) longest = std::max(longest, cost.seconds);
  return serial_seconds + longest;
}

double CellProfile::EstimatedSeconds(int on_threads) const {
  double seconds = serial_seconds + render_seconds / on_threads;
  if (!per_slot) {
    for (const auto& [slowest, work] : sections) seconds += std::max(slowest, work / on_threads);
    return seconds;
  }
  std::vector<EpisodeCost> dealt = episodes;
  std::sort(dealt.begin(), dealt.end(),
            [](const EpisodeCost& a, const EpisodeCost& b) { return a.episode < b.episode; });
  // Each thread's busy-until time, as a min-heap: the next episode goes to the first one free.
  std::vector<double> free_at(static_cast<std::size_t>(std::max(on_threads, 1)), 0.0);
  for (const EpisodeCost& cost : dealt) {
    std::pop_heap(free_at.begin(), free_at.end(), std::greater<>());
    free_at.back() += cost.seconds;
    std::push_heap(free_at.begin(), free_at.end(), std::greater<>());
  }
  return seconds + *std::max_element(free_at.begin(), free_at.end());
}

namespace {

// The share of a 16-thread cell that is serial or waits on its slowest env.
double SerialOrTailShare(const CellProfile& profile, int on_threads) {
  const double estimate = profile.EstimatedSeconds(on_threads);
  return estimate > 0.0 ? 1.0 - profile.work_seconds() / on_threads / estimate : 0.0;
}

}  // namespace

std::string FormatCellProfile(const CellProfile& profile) {
  std::string text;
  char line[256];
  const double work = profile.work_seconds();
  std::snprintf(line, sizeof line, "profile: %.2f s wall on %d thread%s, %.2f s of measured work\n",
                profile.wall_seconds, profile.threads, profile.threads == 1 ? "" : "s", work);
  text += line;
  for (const auto& [name, seconds] : profile.stages) {
    std::snprintf(line, sizeof line, "  %-14s %8.3f s  %5.1f%%\n", name.c_str(), seconds,
                  work > 0.0 ? 100.0 * seconds / work : 0.0);
    text += line;
  }
  if (profile.render_wall_seconds > 0.0) {
    const double held = profile.render_cpu_seconds + profile.render_idle_seconds;
    std::snprintf(
        line, sizeof line,
        "  render calls: %.3f s wall (%s), %.3f s CPU, %.3f s idle inside them (%.1f%% of the thread time they held)\n",
        profile.render_wall_seconds, profile.per_slot ? "summed over the slots' threads" : "x all threads",
        profile.render_cpu_seconds, profile.render_idle_seconds,
        held > 0.0 ? 100.0 * profile.render_idle_seconds / held : 0.0);
    text += line;
  }
  double longest = 0.0, total = 0.0;
  for (const EpisodeCost& cost : profile.episodes) {
    longest = std::max(longest, cost.seconds);
    total += cost.seconds;
  }
  const double mean = profile.episodes.empty() ? 0.0 : total / static_cast<double>(profile.episodes.size());
  std::snprintf(line, sizeof line, "  episodes: %zu, cost mean %.3f s, longest %.3f s\n", profile.episodes.size(), mean,
                longest);
  text += line;
  if (profile.per_slot) {
    std::snprintf(
        line, sizeof line,
        "  critical path (unlimited threads): %.3f s = serial %.3f s + longest episode %.3f s (per-slot schedule)\n",
        profile.critical_path_seconds(), profile.serial_seconds, longest);
  } else {
    std::snprintf(
        line, sizeof line,
        "  critical path (unlimited threads): %.3f s = serial %.3f s + slowest env per section %.3f s (lock-step)\n",
        profile.critical_path_seconds(), profile.serial_seconds, profile.slowest_env_seconds);
  }
  text += line;
  for (int on_threads : {1, 2, 16}) {
    std::snprintf(line, sizeof line, "  estimate on %2d thread%s: %.3f s (%.0f%% serial or tail)\n", on_threads,
                  on_threads == 1 ? "" : "s", profile.EstimatedSeconds(on_threads),
                  100.0 * SerialOrTailShare(profile, on_threads));
    text += line;
  }
  return text;
}

std::string CellProfileJson(const CellProfile& profile) {
  nlohmann::json json;
  json["threads"] = profile.threads;
  json["wall_s"] = profile.wall_seconds;
  json["work_s"] = profile.work_seconds();
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& [name, seconds] : profile.stages) stages[name] = seconds;
  json["stage_s"] = stages;
  json["schedule"] = profile.per_slot ? "per_slot" : "lock_step";
  json["render"] = {{"wall_s", profile.render_wall_seconds},
                    {"cpu_s", profile.render_cpu_seconds},
                    {"idle_s", profile.render_idle_seconds}};
  json["serial_s"] = profile.serial_seconds;
  json["slowest_env_per_section_s"] = profile.slowest_env_seconds;
  json["critical_path_s"] = profile.critical_path_seconds();
  nlohmann::json estimates = nlohmann::json::object();
  for (int on_threads : {1, 2, 4, 8, 16}) {
    estimates[std::to_string(on_threads)] = {{"seconds", profile.EstimatedSeconds(on_threads)},
                                             {"serial_or_tail_share", SerialOrTailShare(profile, on_threads)}};
  }
  json["estimates"] = estimates;
  nlohmann::json episodes = nlohmann::json::array();
  for (const EpisodeCost& cost : profile.episodes) {
    episodes.push_back({{"episode", cost.episode},
                        {"slot", cost.slot},
                        {"control_ticks", cost.control_ticks},
                        {"seconds", cost.seconds}});
  }
  json["episodes"] = episodes;
  return json.dump(2) + "\n";
}

}  // namespace tavis::batch::cell
