// A sweep's progress for a person at a terminal: one status line rewritten in place (cells
// done/total, episodes done/total, episodes per second, ETA) and a line per finished cell; quiet
// mode (logs) keeps the per-cell lines, each with the counts, and drops the status line.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>

namespace tavis::batch::sweep {

class SweepProgress {
 public:
  // `cells_done` and `episodes_done` were complete before this run started.
  SweepProgress(int cells_total, int cells_done, int64_t episodes_total, int64_t episodes_done, bool quiet);

  // Called from any thread as episodes end.
  void AddEpisodes(int64_t count);
  // A cell finished: its line (stdout), then the status line again.
  void CellFinished(const std::string& line);
  // The status line's text, e.g. "cells 3/12, episodes 300/1152, 41.2 episodes/s, ETA 20s".
  std::string Status() const;

 private:
  void Draw();  // with mutex_ held

  mutable std::mutex mutex_;
  const int cells_total_;
  int cells_done_;
  const int64_t episodes_total_;
  int64_t episodes_done_;
  int64_t episodes_this_run_ = 0;
  const bool quiet_;
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_draw_{};
};

// "1h02m", "3m05s", "42s".
std::string FormatDuration(double seconds);

}  // namespace tavis::batch::sweep
