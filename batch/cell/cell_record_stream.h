// An evaluation cell's records on disk while the cell runs (`tavis eval`): DIR/cell.json (the
// settings) is written first, so an unwritable DIR fails before any work; each episode's line is
// appended to DIR/episodes.jsonl and flushed as soon as it and every earlier episode have ended
// (with the episode's DIR/actions/episode_<i>.csv when its actions are kept for replay), so an interrupted cell keeps
// its complete episodes; its line of DIR/episode_times.jsonl (episode_times.h) is written just before it.
// summary.json comes last (WriteCellSummary) and marks the cell complete. A resumed cell keeps
// the complete lines and continues after them, and keeps one time line per kept record. No file of the cell is written
// through a symbolic link: a link planted at one is refused, naming it.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/cell_plan.h"
#include "batch/cell/episode_recorder.h"

namespace tavis::batch::cell {

class CellRecordStream {
 public:
  // Fresh: DIR must be absent or hold no results (output::HoldsNoResults); it gets tavis's marker.
  // Resumed: DIR must hold this cell's cell.json (the same
  // settings) and no summary.json; its complete lines are read back and a torn last line is cut.
  // Throws std::invalid_argument naming DIR and what is wrong, std::runtime_error when it cannot
  // be written.
  CellRecordStream(std::string dir, const CellPlan& plan, bool resume);
  ~CellRecordStream();
  CellRecordStream(const CellRecordStream&) = delete;
  CellRecordStream& operator=(const CellRecordStream&) = delete;

  // The records read back when resuming, in episode order (without actions; with their times
  // from episode_times.jsonl, none where the line is missing).
  const std::vector<EpisodeRecord>& resumed() const { return resumed_; }
  // The first episode still to run.
  int64_t next_episode() const { return episode_start_ + static_cast<int64_t>(resumed_.size()); }

  // Keeps only the first `count` resumed records (before anything is written): the others run
  // again, e.g. a filmed episode whose video was never finished.
  void KeepResumed(std::size_t count);
  // Appends the record (the next episode) and flushes it, its times' line first.
  void Write(const EpisodeRecord& record);
  // The folder was renamed to DIR (an --overwrite swapping its new cell in); the open
  // episodes.jsonl goes on, later files are written under DIR.
  void MovedTo(std::string dir);
  // Records written by this stream (not counting the resumed ones).
  int64_t written() const { return written_; }

 private:
  // Opens `path` (DIR/episodes.jsonl, DIR/episode_times.jsonl) to append, a resumed one cut to its
  // first `kept_bytes`.
  static std::FILE* OpenAppending(const std::string& path, bool resume, std::uintmax_t kept_bytes);
  // Resuming: the times of the resumed records, read from DIR/episode_times.jsonl, which is then
  // opened cut to their lines; a record without its line (lost, or a cell begun by an older tavis)
  // gets one without times, so that each record has exactly one.
  void ResumeTimes(const std::string& path);
  // Appends `line` and a newline to `file` (DIR/`name`) and flushes it.
  void Append(std::FILE* file, const char* name, const std::string& line);

  std::string dir_;
  uint64_t seed_;
  int64_t episode_start_;
  std::vector<EpisodeRecord> resumed_;
  std::vector<std::uintmax_t> resumed_ends_;       // [i]: the bytes of episodes.jsonl up to resumed_[i]'s line
  std::vector<std::uintmax_t> resumed_time_ends_;  // [i]: the bytes of episode_times.jsonl up to resumed_[i]'s line
  std::FILE* episodes_ = nullptr;
  std::FILE* times_ = nullptr;
  int64_t written_ = 0;
};

// The settings that decide a cell's records (cell.json), not how it ran (envs, threads): those the
// table records in cell.json (cell_settings.h), each perturbation level with its settings, and
// the identity of the files behind them.
nlohmann::json CellSettingsJson(const CellPlan& plan);
// The same for a cell that is not planned (one read back when finished, whose policy's files, an
// actions CSV or a dataset, need not be here): its perturbation levels and identity read now.
nlohmann::json CellSettingsJson(const EvaluationCellConfig& config);

// An episodes.jsonl line read back; throws std::invalid_argument naming the bad field.
EpisodeRecord ParseEpisodeJsonLine(const std::string& line);

}  // namespace tavis::batch::cell
