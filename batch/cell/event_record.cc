#include "batch/cell/event_record.h"

#include <algorithm>
#include <stdexcept>

#include "batch/cell/statistics.h"

namespace tavis::batch::cell {
namespace {

// A number of the record or null; an optional value that is unset writes null.
nlohmann::json OrNull(const std::optional<double>& value) { return value ? nlohmann::json(*value) : nlohmann::json(); }

double Number(const nlohmann::json& motion, const std::string& hand, const char* key) {
  const nlohmann::json& value = motion.at(hand).at(key);
  if (!value.is_number())
    throw std::invalid_argument("motion." + hand + "." + key + " " + value.dump() + " is not a number");
  return value.get<double>();
}

}  // namespace

void AddEventsJson(const EpisodeRecord& record, nlohmann::json& line) {
  if (record.events) {
    nlohmann::json events = nlohmann::json::object();
    for (const EventFired& fired : *record.events) events[ToString(fired.event)] = fired.first_tick;
    line["events"] = events;
  }
  if (record.motion) {
    nlohmann::json motion = nlohmann::json::object();
    for (std::size_t hand = 0; hand < 2; ++hand) {
      const ArmMotion& arm = (*record.motion)[hand];
      motion[kHandKeys[hand]] = {{"path_m", arm.path_m}, {"jerk_rms", arm.jerk_rms}, {"sparc", OrNull(arm.sparc)}};
    }
    line["motion"] = motion;
  }
}

void ParseEventsJson(const nlohmann::json& line, EpisodeRecord& record) {
  if (line.contains("events")) {
    std::vector<EventFired> events;
    for (const auto& [name, tick] : line.at("events").items()) {
      FailureEvent event;
      if (!ParseFailureEvent(name, &event)) throw std::invalid_argument("events." + name + " is not a failure event");
      if (!tick.is_number_integer())
        throw std::invalid_argument("events." + name + " " + tick.dump() + " is not a control tick");
      events.push_back({event, tick.get<int>()});
    }
    // The object's keys come back sorted by name: the record keeps the declared order.
    std::sort(events.begin(), events.end(), [](const EventFired& a, const EventFired& b) { return a.event < b.event; });
    record.events = events;
  }
  if (line.contains("motion")) {
    const nlohmann::json& motion = line.at("motion");
    std::array<ArmMotion, 2> arms;
    for (std::size_t hand = 0; hand < 2; ++hand) {
      const std::string key = kHandKeys[hand];
      arms[hand].path_m = Number(motion, key, "path_m");
      arms[hand].jerk_rms = Number(motion, key, "jerk_rms");
      if (!motion.at(key).at("sparc").is_null()) arms[hand].sparc = Number(motion, key, "sparc");
    }
    record.motion = arms;
  }
}

nlohmann::json EventCountsJson(const std::string& task, bool head_moves, const std::vector<EpisodeRecord>& episodes) {
  const std::vector<FailureEvent> applicable = ApplicableEvents(task, head_moves);
  nlohmann::json counts = nlohmann::json::object();
  for (const FailureEvent event : AllFailureEvents()) {
    if (std::find(applicable.begin(), applicable.end(), event) == applicable.end()) {
      counts[ToString(event)] = nullptr;
      continue;
    }
    int64_t count = 0;
    for (const EpisodeRecord& record : episodes) {
      if (!record.events) continue;
      count += std::any_of(record.events->begin(), record.events->end(),
                           [&](const EventFired& fired) { return fired.event == event; });
    }
    counts[ToString(event)] = count;
  }
  return counts;
}

nlohmann::json MotionMediansJson(const std::vector<EpisodeRecord>& episodes) {
  nlohmann::json medians = nlohmann::json::object();
  for (std::size_t hand = 0; hand < 2; ++hand) {
    std::vector<double> path, jerk, sparc;
    for (const EpisodeRecord& record : episodes) {
      if (!record.motion) continue;
      const ArmMotion& arm = (*record.motion)[hand];
      path.push_back(arm.path_m);
      jerk.push_back(arm.jerk_rms);
      if (arm.sparc) sparc.push_back(*arm.sparc);
    }
    const auto median = [](const std::vector<double>& values) {
      return values.empty() ? nlohmann::json() : nlohmann::json(Median(values));
    };
    medians[kHandKeys[hand]] = {{"path_m", median(path)}, {"jerk_rms", median(jerk)}, {"sparc", median(sparc)}};
  }
  return medians;
}

}  // namespace tavis::batch::cell
