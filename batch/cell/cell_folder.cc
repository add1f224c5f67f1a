#include "batch/cell/cell_folder.h"

#include <algorithm>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "batch/cell/cell_record_stream.h"
#include "batch/cell/cell_report.h"
#include "batch/output/output_folder.h"
#include "batch/output/setting_error.h"

namespace tavis::batch::cell {
namespace {

namespace fs = std::filesystem;

// A refusal naming the folder settings, which tavis eval names by flag.
using Advice = output::SettingsAdvice<std::invalid_argument>;

// The cell's folder while it runs: locked, and under --overwrite with the new cell built beside
// the old one until its first record swaps it in.
class LockedCellFolder {
 public:
  explicit LockedCellFolder(const CellFolderOptions& options) : options_(options) {
    const fs::path& out = options.out;
    if (options.resume && !fs::is_directory(out))
      throw Advice(output::SettingKey("resume") + ": " + out.string() + " does not exist: there is no cell to finish");
    const bool replace = options.overwrite && !output::HoldsNoResults(out);
    if (replace) {
      output::RequireEmptyOrOwn(out, output::OutputKind::kEvalCell,
                                output::SettingKey("overwrite") +
                                    " replaces only a cell tavis wrote: move those files away or give another " +
                                    output::SettingKey("out"));
    }
    created_ = !fs::exists(out);
    lock_ = output::CreateAndLockOutput(out, options.command);
    if (replace) replacement_ = std::make_unique<output::OutputReplacement>(out, options.command);
  }

  // Where the cell's files are now: beside the old cell until the new one is swapped in.
  fs::path current() const { return replacement_ && !replacement_->swapped() ? replacement_->staging() : options_.out; }
  // Swaps the new cell in where the old one was (if it is not yet); `stream` goes on writing there.
  void SwapIn(CellRecordStream& stream) {
    if (!replacement_ || replacement_->swapped()) return;
    replacement_->SwapIn();
    stream.MovedTo(options_.out.string());
  }
  // A cell that failed before its first record leaves nothing behind (and an --overwrite the old
  // cell) where the caller asks so.
  void ForgetIfNew() {
    if (created_ && options_.remove_new_folder_on_failure) fs::remove_all(options_.out);
  }

 private:
  const CellFolderOptions& options_;
  bool created_ = false;
  output::OutputLock lock_;
  std::unique_ptr<output::OutputReplacement> replacement_;
};

std::unique_ptr<CellRecordStream> OpenStream(LockedCellFolder& folder, const CellPlan& plan, bool resume) {
  try {
    return std::make_unique<CellRecordStream>(folder.current().string(), plan, resume);
  } catch (...) {
    folder.ForgetIfNew();
    throw;
  }
}

// The run's result covering the whole cell: the resumed records first.
void PrependResumed(const CellRecordStream& stream, CellResult& result) {
  std::vector<EpisodeRecord> episodes = stream.resumed();
  for (EpisodeRecord& episode : result.episodes) episodes.push_back(std::move(episode));
  result.episodes = std::move(episodes);
  result.successes = 0;
  for (const EpisodeRecord& episode : result.episodes) result.successes += episode.success ? 1 : 0;
}

}  // namespace

CellResult RunCellInFolder(CellPlan plan, const CellFolderOptions& options, const AttachToCell& attach) {
  LockedCellFolder folder(options);
  const std::unique_ptr<CellRecordStream> stream = OpenStream(folder, plan, options.resume);
  const std::function<fs::path()> where = [&folder] { return folder.current(); };
  plan.ContinueFrom(stream->next_episode());
  CellAttachments attached = attach ? attach(plan, where) : CellAttachments{};
  if (attached.records_kept && !stream->resumed().empty()) {
    const std::size_t kept = attached.records_kept(stream->resumed());
    if (kept < stream->resumed().size()) {
      std::cerr << "note: episode " << stream->resumed()[kept].episode << " of " << options.out.string()
                << " has no finished video: the cell resumes from it\n";
      stream->KeepResumed(kept);
      plan.ContinueFrom(stream->next_episode());
      attached = attach(plan, where);
    }
  }
  const RecordCallback record = [&stream, &folder, &attached](const EpisodeRecord& episode) {
    if (attached.on_record) attached.on_record(episode);
    stream->Write(episode);
    folder.SwapIn(*stream);
  };
  // A cell run in blocks runs up to the block's end (nothing when a resumed one has it already);
  // its records still say how many episodes the whole cell has.
  const int cell_episodes = plan.config.episodes;
  const bool stops_short = options.stop_before >= 0 && options.stop_before < plan.end_episode();
  if (stops_short)
    plan.config.episodes =
        static_cast<int>(std::max(stream->next_episode(), options.stop_before) - plan.config.episode_start);
  CellResult result;
  try {
    result = RunEvaluationCell(plan, options.progress, record, attached.sinks);
    result.config.episodes = cell_episodes;
  } catch (...) {
    // One that recorded episodes keeps them for a resume.
    if (stream->written() == 0) folder.ForgetIfNew();
    throw;
  }
  folder.SwapIn(*stream);  // a cell with nothing left to run
  PrependResumed(*stream, result);
  if (stops_short && !options.complete_at_stop) return result;  // paused: no summary, as if interrupted
  WriteCellSummary(result, {options.threads, static_cast<int64_t>(stream->resumed().size())}, options.out.string(),
                   options.label);
  if (attached.finish) attached.finish(result);
  return result;
}

}  // namespace tavis::batch::cell
