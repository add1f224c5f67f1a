#include "batch/sweep/sweep_progress.h"

#include <cmath>

namespace tavis::batch::sweep {

std::string FormatDuration(double seconds) {
  const long total = std::lround(seconds);
  char text[32];
  if (total >= 3600) {
    std::snprintf(text, sizeof(text), "%ldh%02ldm", total / 3600, (total % 3600) / 60);
  } else if (total >= 60) {
    std::snprintf(text, sizeof(text), "%ldm%02lds", total / 60, total % 60);
  } else {
    std::snprintf(text, sizeof(text), "%lds", total);
  }
  return text;
}

SweepProgress::SweepProgress(int cells_total, int cells_done, int64_t episodes_total, int64_t episodes_done, bool quiet)
    : cells_total_(cells_total),
      cells_done_(cells_done),
      episodes_total_(episodes_total),
      episodes_done_(episodes_done),
      quiet_(quiet) {}

std::string SweepProgress::Status() const {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed > 0 ? static_cast<double>(episodes_this_run_) / elapsed : 0.0;
  char text[160];
  std::snprintf(text, sizeof(text), "cells %d/%d, episodes %lld/%lld, %.1f episodes/s, ETA %s", cells_done_,
                cells_total_, static_cast<long long>(episodes_done_), static_cast<long long>(episodes_total_), rate,
                rate > 0 ? FormatDuration(static_cast<double>(episodes_total_ - episodes_done_) / rate).c_str() : "-");
  return text;
}

void SweepProgress::AddEpisodes(int64_t count) {
  std::lock_guard<std::mutex> lock(mutex_);
  episodes_done_ += count;
  episodes_this_run_ += count;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(250)) return;
  last_draw_ = now;
  Draw();
}

void SweepProgress::CellFinished(const std::string& line) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++cells_done_;
  if (quiet_) {
    std::printf("%s [%s]\n", line.c_str(), Status().c_str());
  } else {
    std::fprintf(stderr, "\r\033[K");
    std::printf("%s\n", line.c_str());
  }
  std::fflush(stdout);
  Draw();
}

void SweepProgress::Draw() {
  if (quiet_) return;
  std::fprintf(stderr, "\r\033[K  %s", Status().c_str());
  if (cells_done_ == cells_total_) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

}  // namespace tavis::batch::sweep
