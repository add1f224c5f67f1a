// Progress of a run of episodes (`tavis eval`, `tavis demos`): done/total, the rate and the ETA.
// On a terminal one status line is rewritten in place; anywhere else (a log file, a pipe, a
// Slurm job's output) plain lines are written instead, at most one per tenth of the run plus the
// last, so that logs stay readable.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <mutex>
#include <string>

namespace tavis::tools {

// "24/96 episodes, 2.0 episodes/s, ETA 36s" ("ETA -" until an episode has ended in this run).
// `done_here`: episodes this run ended in `elapsed_seconds` (a resumed run starts from more).
std::string FormatProgress(int64_t done, int64_t total, int64_t done_here, double elapsed_seconds);

class ProgressReporter {
 public:
  enum class Style { kStatusLine, kPlainLines };
  using Clock = std::function<std::chrono::steady_clock::time_point()>;

  // kStatusLine when `out` is a terminal, else kPlainLines.
  static Style StyleFor(std::FILE* out);

  ProgressReporter(std::FILE* out, Style style, Clock clock = std::chrono::steady_clock::now);

  // `done` of `total` episodes have ended; `label` (e.g. a task) names what is counted, and a new
  // label starts a new count (its own rate and ETA). A count's first call starts its clock, so it
  // comes as the work starts (the episode driver's at the start of its run, demos' at the start
  // of a task), not when the first episode ends: lock-step slots end their first episodes
  // together, and a rate timed from the first of them is the batch over microseconds.
  // Not thread-safe: call from one thread.
  void Update(const std::string& label, int64_t done, int64_t total);

 private:
  std::mutex mutex_;
  std::FILE* out_;
  Style style_;
  Clock clock_;
  std::string label_;
  bool started_ = false;
  int64_t done_at_start_ = 0;
  int last_tenth_ = -1;
  std::chrono::steady_clock::time_point start_{};
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_draw_{};
};

}  // namespace tavis::tools
