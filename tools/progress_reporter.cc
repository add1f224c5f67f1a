#include "tools/progress_reporter.h"

#include <unistd.h>

#include "batch/sweep/sweep_progress.h"

namespace tavis::tools {
namespace {

// 0..10: how many tenths of the run have ended (10 only when all of it has).
int Tenth(int64_t done, int64_t total) { return total > 0 && done < total ? static_cast<int>(10 * done / total) : 10; }

}  // namespace

std::string FormatProgress(int64_t done, int64_t total, int64_t done_here, double elapsed_seconds) {
  const double rate = elapsed_seconds > 0 ? static_cast<double>(done_here) / elapsed_seconds : 0.0;
  const std::string eta = done >= total ? "0s"
                          : rate > 0    ? batch::sweep::FormatDuration(static_cast<double>(total - done) / rate)
                                        : "-";
  char text[128];
  std::snprintf(text, sizeof(text), "%lld/%lld episodes, %.1f episodes/s, ETA %s", static_cast<long long>(done),
                static_cast<long long>(total), rate, eta.c_str());
  return text;
}

ProgressReporter::Style ProgressReporter::StyleFor(std::FILE* out) {
  return isatty(fileno(out)) != 0 ? Style::kStatusLine : Style::kPlainLines;
}

ProgressReporter::ProgressReporter(std::FILE* out, Style style, Clock clock)
    : out_(out), style_(style), clock_(std::move(clock)) {}

void ProgressReporter::Update(const std::string& label, int64_t done, int64_t total) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto now = clock_();
  if (!started_ || label != label_) {
    // The first call of a count may already report episodes (a resumed run): they are not this
    // run's, so the rate counts from here.
    started_ = true;
    label_ = label;
    start_ = now;
    done_at_start_ = done;
    // Plain lines start at the next tenth (a rate needs time), or at once if nothing is left.
    last_tenth_ = done < total ? Tenth(done, total) : -1;
    drawn_ = false;
  }
  const bool last = done >= total;
  const std::string text =
      (label_.empty() ? "" : label_ + ": ") +
      FormatProgress(done, total, done - done_at_start_, std::chrono::duration<double>(now - start_).count());
  if (style_ == Style::kStatusLine) {
    if (!last && drawn_ && now - last_draw_ < std::chrono::milliseconds(250)) return;
    drawn_ = true;
    last_draw_ = now;
    std::fprintf(out_, "\r\033[K  %s%s", text.c_str(), last ? "\n" : "");
  } else {
    const int tenth = Tenth(done, total);
    if (tenth == last_tenth_) return;
    last_tenth_ = tenth;
    std::fprintf(out_, "  %s\n", text.c_str());
  }
  std::fflush(out_);
}

}  // namespace tavis::tools
