#include "batch/cell/cell_record_stream.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "batch/cell/cell_report.h"
#include "batch/cell/episode_times.h"
#include "batch/cell/event_record.h"
#include "batch/cell/stage_record.h"
#include "batch/output/atomic_file.h"
#include "batch/output/json_error_text.h"
#include "batch/output/output_folder.h"
#include "batch/output/setting_error.h"
#include "batch/output/settings_difference.h"
#include "batch/perturb/perturbation_catalog.h"
#include "batch/policy_kinds.h"

namespace tavis::batch::cell {
namespace {

namespace fs = std::filesystem;

// A refusal naming the folder settings resume and overwrite, which tavis eval names by flag.
using Advice = output::SettingsAdvice<std::invalid_argument>;

std::optional<kinematics::GaltResult> ParseGalt(const nlohmann::json& line, const std::string& prefix) {
  if (!line.contains(prefix + "_reason")) return std::nullopt;
  kinematics::GaltResult galt;
  if (!kinematics::ParseGaltReason(line.at(prefix + "_reason").get<std::string>(), &galt.reason)) {
    throw std::invalid_argument(prefix + "_reason " + line.at(prefix + "_reason").dump() + " is not a GALT reason");
  }
  const nlohmann::json& seconds = line.at(prefix + "_s");
  if (!seconds.is_null()) galt.galt_s = seconds.get<double>();
  return galt;
}

double ParseActionValue(const nlohmann::json& value) {
  if (value.is_number()) return value.get<double>();
  const std::string text = value.is_string() ? value.get<std::string>() : "";
  if (text == "nan") return std::numeric_limits<double>::quiet_NaN();
  if (text == "inf") return std::numeric_limits<double>::infinity();
  if (text == "-inf") return -std::numeric_limits<double>::infinity();
  return 0.0;
}

nlohmann::json SettingsJson(const EvaluationCellConfig& config, const std::vector<perturb::PerturbationLevel>& levels,
                            const nlohmann::json& identity) {
  nlohmann::json settings =
      RecordedSettingsJson(config, CellRecord::kCellJson, IsPolicy(config.policy, PolicyKind::kOpenpi));
  // Only a perturbed cell names its perturbations, each level with its settings as read (so an
  // edited level file is a different setting): a base cell's cell.json is as it was.
  if (settings.contains("perturbations")) settings["perturbations"] = perturb::PerturbationsJson(levels);
  settings["identity"] = identity;
  return settings;
}

}  // namespace

nlohmann::json CellSettingsJson(const CellPlan& plan) {
  return SettingsJson(plan.config, plan.perturbations, plan.identity);
}

nlohmann::json CellSettingsJson(const EvaluationCellConfig& config) {
  return SettingsJson(config, perturb::ResolvePerturbations(config.config_dir, config.perturbations),
                      CellIdentityJson(config));
}

EpisodeRecord ParseEpisodeJsonLine(const std::string& text) {
  const nlohmann::json line = nlohmann::json::parse(text);
  EpisodeRecord record;
  record.episode = line.at("episode").get<int64_t>();
  record.success = line.at("success").get<bool>();
  if (!engine::ParseEpisodeEnd(line.at("end").get<std::string>(), &record.end)) {
    throw std::invalid_argument("end " + line.at("end").dump() + " is not an episode end");
  }
  record.length_steps = line.at("length_steps").get<int>();
  record.length_control_ticks = line.at("length_control_ticks").get<int>();
  record.solver_messages = line.at("solver_messages").get<int>();
  if (line.contains("invalid_action")) {
    const nlohmann::json& fault = line.at("invalid_action");
    record.invalid_action.entry = fault.at("entry").is_null() ? -1 : fault.at("entry").get<int>();
    record.invalid_action.value = ParseActionValue(fault.at("value"));
    record.invalid_action.reason = fault.at("reason").get<std::string>();
  }
  record.galt = ParseGalt(line, "galt");
  record.galt_policy_rate = ParseGalt(line, "galt_policy_rate");
  ParseStagesJson(line, record);
  ParseEventsJson(line, record);
  ParseGazeJson(line, record.gaze);
  return record;
}

CellRecordStream::CellRecordStream(std::string dir, const CellPlan& plan, bool resume)
    : dir_(std::move(dir)), seed_(plan.config.seed), episode_start_(plan.config.episode_start) {
  const fs::path cell_json = fs::path(dir_) / "cell.json";
  const nlohmann::json settings = CellSettingsJson(plan);
  const fs::path episodes_path = fs::path(dir_) / "episodes.jsonl";
  std::uintmax_t kept_bytes = 0;
  if (resume) {
    if (!fs::exists(cell_json))
      throw Advice(output::SettingKey("resume") + ": " + dir_ + " holds no cell (no cell.json)");
    if (fs::exists(fs::path(dir_) / "summary.json"))
      throw Advice(output::SettingKey("resume") + ": " + dir_ + " is complete (it has summary.json)");
    // What a resume reads, cuts and appends to is the cell's own: a planted link is refused before
    // anything is read or written (so a file elsewhere is never truncated nor filled).
    for (const char* name : {"cell.json", "episodes.jsonl", "episode_times.jsonl", "actions", "videos"})
      output::RefuseLink(fs::path(dir_) / name);
    nlohmann::json was;
    try {
      std::ifstream(cell_json) >> was;
    } catch (const nlohmann::json::exception& error) {
      throw std::invalid_argument(cell_json.string() +
                                  ": damaged cell file, not valid JSON: " + output::JsonErrorText(error.what()));
    }
    const std::string differences = output::SettingsDifference(was, settings);
    if (!differences.empty())
      throw Advice(output::SettingKey("resume") + " " + dir_ + " with other settings: " + differences);
    // The complete lines, in order; what follows the last one (a line cut by the interruption) goes.
    std::ifstream in(episodes_path, std::ios::binary);
    std::string line;
    while (std::getline(in, line) && !in.eof()) {
      EpisodeRecord record;
      try {
        record = ParseEpisodeJsonLine(line);
      } catch (const std::exception&) {
        break;
      }
      if (record.episode != next_episode()) break;
      resumed_.push_back(std::move(record));
      kept_bytes += line.size() + 1;
      resumed_ends_.push_back(kept_bytes);
    }
  } else {
    if (!output::HoldsNoResults(dir_)) {
      throw Advice(dir_ + " already holds results; give " + output::SettingKey("overwrite") + " to replace them or " +
                   output::SettingKey("resume") + " to finish an interrupted cell");
    }
    fs::create_directories(dir_);
    output::WriteOutputMarker(dir_, output::OutputKind::kEvalCell);
    output::WriteFileAtomically(cell_json, settings.dump(2) + "\n");
  }
  episodes_ = OpenAppending(episodes_path.string(), resume, kept_bytes);
  const std::string times_path = (fs::path(dir_) / "episode_times.jsonl").string();
  if (resume) {
    ResumeTimes(times_path);
  } else {
    times_ = OpenAppending(times_path, false, 0);
  }
}

void CellRecordStream::ResumeTimes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::uintmax_t kept_bytes = 0;
  std::size_t kept = 0;
  while (kept < resumed_.size() && std::getline(in, line) && !in.eof()) {
    EpisodeTimesLine times;
    try {
      times = ParseEpisodeTimesJsonLine(line);
    } catch (const std::exception&) {
      break;
    }
    if (times.episode != resumed_[kept].episode) break;
    resumed_[kept++].times = times.times;
    kept_bytes += line.size() + 1;
    resumed_time_ends_.push_back(kept_bytes);
  }
  in.close();
  times_ = OpenAppending(path, true, kept_bytes);
  for (; kept < resumed_.size(); ++kept) {
    const std::string missing = EpisodeTimesJsonLine(resumed_[kept].episode, std::nullopt);
    Append(times_, "episode_times.jsonl", missing);
    resumed_time_ends_.push_back(resumed_time_ends_.empty() ? 0 : resumed_time_ends_.back());
    resumed_time_ends_.back() += missing.size() + 1;
  }
}

std::FILE* CellRecordStream::OpenAppending(const std::string& path, bool resume, std::uintmax_t kept_bytes) {
  // O_NOFOLLOW: the records go into the cell's own file, never through a link to another.
  const int fd =
      open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_NOFOLLOW | O_CLOEXEC | (resume ? 0 : O_TRUNC), 0644);
  if (fd < 0) {
    const int reason = errno;
    if (reason == ELOOP) output::RefuseLink(path);
    throw std::runtime_error("cannot write " + path + ": " + std::strerror(reason));
  }
  if (resume && ftruncate(fd, static_cast<off_t>(kept_bytes)) != 0) {
    const int reason = errno;
    close(fd);
    throw std::runtime_error("cannot cut the torn last line of " + path + ": " + std::strerror(reason));
  }
  std::FILE* file = fdopen(fd, "ab");
  if (file == nullptr) {
    const int reason = errno;
    close(fd);
    throw std::runtime_error("cannot write " + path + ": " + std::strerror(reason));
  }
  return file;
}

CellRecordStream::~CellRecordStream() {
  if (episodes_ != nullptr) std::fclose(episodes_);
  if (times_ != nullptr) std::fclose(times_);
}

void CellRecordStream::MovedTo(std::string dir) { dir_ = std::move(dir); }

void CellRecordStream::KeepResumed(std::size_t count) {
  if (count >= resumed_.size() || written_ > 0) return;
  const std::pair<std::FILE*, const std::vector<std::uintmax_t>*> files[] = {{episodes_, &resumed_ends_},
                                                                             {times_, &resumed_time_ends_}};
  for (const auto& [file, ends] : files) {
    if (std::fflush(file) != 0 || ftruncate(fileno(file), static_cast<off_t>(count == 0 ? 0 : (*ends)[count - 1])) != 0)
      throw std::runtime_error("cannot cut the files of " + dir_ + " to their first " + std::to_string(count) +
                               " records: " + std::strerror(errno));
  }
  resumed_.resize(count);
  resumed_ends_.resize(count);
  resumed_time_ends_.resize(count);
}

void CellRecordStream::Append(std::FILE* file, const char* name, const std::string& line) {
  if (std::fwrite(line.data(), 1, line.size(), file) != line.size() || std::fputc('\n', file) == EOF ||
      std::fflush(file) != 0) {
    throw std::runtime_error("cannot write " + dir_ + "/" + name + ": " + std::strerror(errno));
  }
}

void CellRecordStream::Write(const EpisodeRecord& record) {
  if (!record.replay_actions.empty()) WriteReplayCsv(record, dir_);
  // The times first: a kill between the two lines leaves a time line without its record, which a
  // resume cuts, rather than a record without its times.
  Append(times_, "episode_times.jsonl", EpisodeTimesJsonLine(record.episode, record.times));
  Append(episodes_, "episodes.jsonl", EpisodeJsonLine(record, seed_));
  ++written_;
}

}  // namespace tavis::batch::cell
