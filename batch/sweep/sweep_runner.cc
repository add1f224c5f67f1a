#include "batch/sweep/sweep_runner.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>
#include <vector>

#include <tbb/global_control.h>

#include "batch/cell/cell_plan.h"
#include "batch/cell/cell_record_stream.h"
#include "batch/cell/cell_report.h"
#include "batch/dataset/video/video_log.h"
#include "batch/output/output_folder.h"
#include "batch/sweep/galt_reference.h"
#include "batch/sweep/sweep_cell.h"
#include "batch/sweep/sweep_manifest.h"
#include "batch/sweep/sweep_progress.h"
#include "batch/sweep/sweep_results.h"

namespace tavis::batch::sweep {
namespace {

namespace fs = std::filesystem;

// Episodes already recorded in an interrupted cell's folder (for the progress line).
int64_t RecordedEpisodes(const fs::path& dir) {
  std::ifstream in(dir / "episodes.jsonl");
  int64_t lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  return lines;
}

// A cell of this shard with its plan, made once before any work.
struct PlannedCell {
  const SweepCell* cell;
  cell::CellPlan plan;
};

}  // namespace

int DefaultConcurrentCells(bool all_per_slot, int threads) {
  // Lock-step cells run side by side, so that one cell's wait for its slowest env is filled by
  // another's work. Per-slot cells keep their threads busy until their last episodes, whose tail
  // grows with the thread count: one per 4 threads shares it (4 at once on 16 threads took 27%
  // less time than one at a time; on 2 threads one at a time is faster).
  constexpr int kThreadsPerPerSlotCell = 4;
  return all_per_slot ? std::max(1, threads / kThreadsPerPerSlotCell) : std::max(1, threads);
}

// The cells of `mine` still to run (all but the complete ones in `out`), marking the interrupted
// ones in the manifest; `episodes_done` counts the episodes already recorded.
std::vector<const PlannedCell*> CellsToRun(const std::vector<PlannedCell>& mine, const fs::path& out,
                                           SweepManifest& manifest, int64_t* episodes_done) {
  std::vector<const PlannedCell*> to_run;
  for (const PlannedCell& planned : mine) {
    const SweepCell& cell = *planned.cell;
    const fs::path dir = out / "cells" / cell.id;
    if (ReadCompleteCell(dir, cell::CellSettingsJson(planned.plan), cell.config.episodes)) {
      manifest.SetState(cell.id, "complete");
      *episodes_done += cell.config.episodes;
    } else {
      if (fs::exists(dir / "cell.json")) {
        manifest.SetState(cell.id, "interrupted");
        *episodes_done += std::min<int64_t>(RecordedEpisodes(dir), cell.config.episodes);
      }
      to_run.push_back(&planned);
    }
  }
  return to_run;
}

// Runs `to_run` into out/cells, `jobs` cells at a time, keeping the manifest's states current.
// Returns the first error of a cell, if any (the other running cells finish first).
std::exception_ptr RunCells(const std::vector<const PlannedCell*>& to_run, int jobs, const fs::path& out,
                            const SweepRunOptions& options, const rollout::EpisodeVideoSettings& videos,
                            SweepManifest& manifest, SweepProgress& progress) {
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr first_error;
  std::mutex error_mutex;
  const auto worker = [&] {
    for (std::size_t i = next++; i < to_run.size() && !failed; i = next++) {
      const SweepCell& cell = *to_run[i]->cell;
      try {
        manifest.SetState(cell.id, "running");
        manifest.Write(out);
        int64_t reported = 0;
        const cell::CellResult result = RunCellInto(
            to_run[i]->plan, out / "cells" / cell.id, options.threads,
            [&progress, &reported](int64_t finished, int64_t) {
              progress.AddEpisodes(finished - reported);
              reported = finished;
            },
            cell.label, cell.seed_group, videos);
        manifest.SetState(cell.id, "complete");
        manifest.Write(out);
        progress.CellFinished(cell::CellSummaryLine(result));
      } catch (...) {
        manifest.SetState(cell.id, "failed");
        std::lock_guard<std::mutex> error_lock(error_mutex);
        if (!first_error) first_error = std::current_exception();
        failed = true;
      }
    }
  };
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(worker);
  worker();
  for (std::thread& thread : threads) thread.join();
  return first_error;
}

void RunSweep(const SweepSpec& spec, const SweepRunOptions& options) {
  const fs::path out = options.out_dir;
  const std::vector<SweepCell> all = ExpandCells(spec, options.config_dir);
  RequireShardHoldsCells(options.shard, all.size());
  // Each cell of the shard planned once, here: bad settings fail before any work, and the cell
  // runs that plan (its files read once).
  std::vector<PlannedCell> mine;
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (!InShard(i, options.shard)) continue;
    mine.push_back({&all[i], cell::PlanCell(all[i].config)});
    ids.push_back(all[i].id);
  }
  DatasetGaltReference(spec.figures);  // an unreadable reference dataset fails before any work, not after it

  SweepManifest manifest(spec, options.spec_yaml, options.shard, ids);
  // A sweep writes only into a new folder or its own: never beside a user's files or into an
  // eval cell, and never while another process writes the same sweep.
  output::RequireUsableOutputPath(out);
  output::RequireEmptyOrOwn(out, output::OutputKind::kSweep,
                            "give a new --out for the sweep, or this sweep's own folder to finish it");
  const output::OutputLock lock = output::CreateAndLockOutput(out, "sweep");
  if (fs::exists(out / "manifest.json")) manifest.RequireSameSweep(SweepManifest::Read(out), out);
  output::WriteOutputMarker(out, output::OutputKind::kSweep);
  fs::create_directories(out / "cells");

  int64_t episodes_done = 0;
  const std::vector<const PlannedCell*> to_run = CellsToRun(mine, out, manifest, &episodes_done);
  manifest.Write(out);

  const bool all_per_slot = std::all_of(to_run.begin(), to_run.end(),
                                        [](const PlannedCell* cell) { return cell::RunsPerSlot(cell->cell->config); });
  const int default_jobs = DefaultConcurrentCells(all_per_slot, options.threads);
  const int jobs = std::max(1, std::min<int>(options.concurrent_cells > 0 ? options.concurrent_cells : default_jobs,
                                             static_cast<int>(to_run.size())));
  // Each running cell's own thread works too: TBB gets the cores the cell threads leave.
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                            static_cast<std::size_t>(std::max(1, options.threads - jobs + 1)));
  SweepProgress progress(static_cast<int>(mine.size()), static_cast<int>(mine.size() - to_run.size()),
                         static_cast<int64_t>(mine.size()) * spec.episodes, episodes_done, options.quiet);
  rollout::EpisodeVideoSettings videos;
  videos.episodes = options.videos.value_or(spec.videos);
  if (videos.episodes > 0) dataset::video::ShowOnlyVideoErrors();
  const auto start = std::chrono::steady_clock::now();
  const std::exception_ptr first_error = RunCells(to_run, jobs, out, options, videos, manifest, progress);
  manifest.SetTiming(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), options.threads,
                     jobs);
  manifest.Write(out);
  if (first_error) std::rethrow_exception(first_error);
  if (options.shard.count == 1) {  // then the shard's cells are all the cells
    std::vector<nlohmann::json> cell_jsons;
    for (const PlannedCell& planned : mine) cell_jsons.push_back(cell::CellSettingsJson(planned.plan));
    WriteSweepResults(out, SweepSpecJson(spec), all, cell_jsons, manifest.Json());
  }
}

}  // namespace tavis::batch::sweep
