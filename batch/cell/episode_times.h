// An episode's time split, DIR/episode_times.jsonl: per episode (one line each, keyed by its index,
// in the order of episodes.jsonl) how long it took from its reset to its end and where that time
// went: waiting for the policy, physics, rendering the policy's cameras, video, and the rest, as
// cell/episode_timer.h measures them (docs/performance.md, "Where an episode's time goes"). Times
// differ from run to run, so they are kept out of the records: episodes.jsonl stays the same byte
// for byte, and no comparison of records (the tests, resumes, `tavis verify`, `tavis compare`)
// reads this file. summary.json's provenance aggregates it (EpisodeTimesSummaryJson).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tavis::batch::cell {

struct EpisodeTimes {
  // The parts, which add up to at most span_s (their keys: EpisodeTimePartKey).
  enum Part { kPolicy, kPhysics, kRender, kVideo, kOther, kNumParts };

  double span_s = 0.0;                    // wall-clock seconds from the start of its reset to its end
  std::array<double, kNumParts> parts{};  // seconds, each >= 0

  double part(Part which) const { return parts[static_cast<std::size_t>(which)]; }
};

// "policy_s", "physics_s", "render_s", "video_s", "other_s".
const char* EpisodeTimePartKey(EpisodeTimes::Part part);

// An episode's line of episode_times.jsonl (no newline): {"episode", "span_s", and each part's
// key}; with no times (a resumed episode whose line was lost: a cell begun by an older tavis)
// the same keys, null.
std::string EpisodeTimesJsonLine(int64_t episode, const std::optional<EpisodeTimes>& times);

// A line read back: the episode and its times (none when null). Throws std::invalid_argument (or
// nlohmann's parse error) naming what is wrong.
struct EpisodeTimesLine {
  int64_t episode = 0;
  std::optional<EpisodeTimes> times;
};
EpisodeTimesLine ParseEpisodeTimesJsonLine(const std::string& line);

// summary.json's provenance.time.episodes: {"file", "measured" (episodes with times), and for
// span_s and each part "total_s", "median_s" and "p90_s" (nearest rank) over those episodes};
// null parts when none is measured.
nlohmann::json EpisodeTimesSummaryJson(const std::vector<EpisodeTimes>& measured);

}  // namespace tavis::batch::cell
