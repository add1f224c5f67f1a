#include "batch/cell/episode_timer.h"

#include <algorithm>

#include "batch/vec_env.h"

namespace tavis::batch::cell {
namespace {

EpisodeTimes::Part PartOf(LoopPart part) {
  switch (part) {
    case LoopPart::kPolicyResets:
    case LoopPart::kPolicyActs: return EpisodeTimes::kPolicy;
    case LoopPart::kStep: return EpisodeTimes::kPhysics;
    case LoopPart::kRender: return EpisodeTimes::kRender;
    case LoopPart::kVideo: return EpisodeTimes::kVideo;
    case LoopPart::kParallel:
    case LoopPart::kReset:
    case LoopPart::kSinks: break;
  }
  return EpisodeTimes::kOther;
}

double SecondsBetween(std::chrono::steady_clock::time_point from, std::chrono::steady_clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

// The times of an episode of `span_s` whose parts came to `parts`: "other" trimmed so that they
// add up to at most the span (adding intervals one by one can round a little above it).
EpisodeTimes Finished(double span_s, const std::array<double, EpisodeTimes::kNumParts>& parts) {
  EpisodeTimes times;
  times.span_s = span_s;
  times.parts = parts;
  double measured = 0.0;
  for (int part = 0; part < EpisodeTimes::kOther; ++part) measured += parts[static_cast<std::size_t>(part)];
  double& other = times.parts[EpisodeTimes::kOther];
  other = std::max(0.0, std::min(other, span_s - measured));
  return times;
}

}  // namespace

std::optional<EpisodeTimes> EpisodeTimer::Take(int64_t episode) {
  std::lock_guard<std::mutex> lock(ended_mutex_);
  const auto found = ended_.find(episode);
  if (found == ended_.end()) return std::nullopt;
  const EpisodeTimes times = found->second;
  ended_.erase(found);
  return times;
}

void EpisodeTimer::RunStarting(VecEnv& vec_env, Policy&, bool per_slot) {
  vec_env_ = &vec_env;
  per_slot_ = per_slot;
  lanes_.assign(static_cast<std::size_t>(vec_env.num_envs()), Lane{});
  batch_last_ = Clock::now();
  batch_part_ = EpisodeTimes::kOther;
  live_ = 0;
  shares_ = {};
}

void EpisodeTimer::AdvanceLane(Lane& lane, Clock::time_point now, EpisodeTimes::Part next) {
  lane.seconds[lane.part] += SecondsBetween(lane.last, now);
  lane.last = now;
  lane.part = next;
}

void EpisodeTimer::AdvanceBatch(Clock::time_point now, EpisodeTimes::Part next) {
  if (live_ > 0) shares_[batch_part_] += SecondsBetween(batch_last_, now) / live_;
  batch_last_ = now;
  batch_part_ = next;
}

void EpisodeTimer::PartStarting(LoopPart part, int slot) {
  if (slot == kWholeBatch) {
    // Per slot the batch's one part is the workers' run, which the slots' own parts split.
    if (!per_slot_) AdvanceBatch(Clock::now(), PartOf(part));
    return;
  }
  Lane& lane = lanes_[static_cast<std::size_t>(slot)];
  const Clock::time_point now = Clock::now();
  if (part == LoopPart::kReset) {
    // A slot's reset starts its next episode: the time since its last one ended is no episode's.
    lane.start = lane.last = now;
    lane.seconds = {};
  }
  AdvanceLane(lane, now, PartOf(part));
}

void EpisodeTimer::PartEnded(LoopPart, int slot) {
  if (slot == kWholeBatch) {
    if (!per_slot_) AdvanceBatch(Clock::now(), EpisodeTimes::kOther);
    return;
  }
  AdvanceLane(lanes_[static_cast<std::size_t>(slot)], Clock::now(), EpisodeTimes::kOther);
}

void EpisodeTimer::EpisodesStarting(const std::vector<uint8_t>& starting) {
  const Clock::time_point now = Clock::now();
  AdvanceBatch(now, batch_part_);
  for (std::size_t slot = 0; slot < starting.size(); ++slot) {
    if (!starting[slot]) continue;
    lanes_[slot].start = now;
    lanes_[slot].seconds = shares_;
    ++live_;
  }
}

void EpisodeTimer::EpisodeEnding(int slot) {
  const Clock::time_point now = Clock::now();
  Lane& lane = lanes_[static_cast<std::size_t>(slot)];
  EpisodeTimes times;
  if (per_slot_) {
    AdvanceLane(lane, now, EpisodeTimes::kOther);
    times = Finished(SecondsBetween(lane.start, now), lane.seconds);
  } else {
    AdvanceBatch(now, batch_part_);
    Seconds parts{};
    for (std::size_t part = 0; part < parts.size(); ++part) {
      parts[part] = std::max(0.0, shares_[part] - lane.seconds[part]);
    }
    times = Finished(SecondsBetween(lane.start, now), parts);
    --live_;
  }
  std::lock_guard<std::mutex> lock(ended_mutex_);
  ended_[vec_env_->state().episode[slot]] = times;
}

}  // namespace tavis::batch::cell
