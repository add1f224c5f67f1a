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
#include "batch/sweep/sequential_group.h"
#include "batch/sweep/sequential_plan.h"
#include "batch/sweep/sequential_stop.h"
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

// What one worker runs at a time: a cell, or a group of paired cells the sequential test runs
// in blocks (sequential_group.h).
struct RunUnit {
  std::vector<const PlannedCell*> cells;
  std::vector<report::SequentialPair> pairs;  // a group's, as positions in `cells`; empty for a lone cell
  report::SequentialTestSettings test;
};

// The shard's cells as units, in the order of their first cell: each sequential group one unit.
std::vector<RunUnit> UnitsOf(const std::vector<PlannedCell>& mine, const std::vector<std::size_t>& positions,
                             const SequentialPlan& sequential, const report::SequentialTestSettings& test) {
  std::vector<RunUnit> units;
  std::vector<std::ptrdiff_t> unit_of_group(sequential.groups.size(), -1);
  for (std::size_t k = 0; k < mine.size(); ++k) {
    const std::ptrdiff_t group = sequential.group_of[positions[k]];
    if (group < 0) {
      units.push_back({{&mine[k]}, {}, test});
      continue;
    }
    if (unit_of_group[group] < 0) {
      unit_of_group[group] = static_cast<std::ptrdiff_t>(units.size());
      units.push_back({{}, GroupPairs(sequential, static_cast<std::size_t>(group)), test});
    }
    units[unit_of_group[group]].cells.push_back(&mine[k]);
  }
  return units;
}

}  // namespace

int DefaultConcurrentCells(bool all_per_slot, int threads) {
  // Lock-step cells run side by side, so that one cell's wait for its slowest env is filled by
  // another's work. Per-slot cells keep their threads busy until their last episodes, whose tail
  // grows with the thread count: one per 4 threads shares it (4 at once on 16 threads took 27%
  // less time than one at a time; on 2 threads one at a time is faster).
  constexpr int kThreadsPerPerSlotCell = 4;
  return all_per_slot ? std::max(1, threads / kThreadsPerPerSlotCell) : std::max(1, threads);
}

// The units of `units` still to run (all but those whose cells are complete in `out`), marking
// the interrupted cells in the manifest; `cells_done` and `episodes_done` count the complete
// cells and the episodes already recorded.
std::vector<RunUnit> UnitsToRun(const std::vector<RunUnit>& units, const fs::path& out, SweepManifest& manifest,
                                int* cells_done, int64_t* episodes_done) {
  std::vector<RunUnit> to_run;
  for (const RunUnit& unit : units) {
    bool complete = true;
    for (const PlannedCell* planned : unit.cells) {
      const SweepCell& cell = *planned->cell;
      const fs::path dir = out / "cells" / cell.id;
      if (ReadCompleteCell(dir, cell::CellSettingsJson(planned->plan), cell.config.episodes)) {
        manifest.SetState(cell.id, "complete");
        ++*cells_done;
        *episodes_done += SequentialEpisodes(dir, cell.config.episodes);
        continue;
      }
      complete = false;
      if (fs::exists(dir / "cell.json")) {
        manifest.SetState(cell.id, "interrupted");
        *episodes_done += std::min<int64_t>(RecordedEpisodes(dir), cell.config.episodes);
      }
    }
    if (!complete) to_run.push_back(unit);
  }
  return to_run;
}

// Runs a sequential group's cells in blocks (the complete ones are read, not run).
void RunGroup(const RunUnit& unit, const fs::path& out, const SweepRunOptions& options,
              const rollout::EpisodeVideoSettings& videos, SweepManifest& manifest, SweepProgress& progress) {
  std::vector<GroupCell> cells;
  for (const PlannedCell* planned : unit.cells) {
    const fs::path dir = out / "cells" / planned->cell->id;
    cells.push_back({planned->cell, dir,
                     ReadCompleteCell(dir, cell::CellSettingsJson(planned->plan), planned->cell->config.episodes)});
    if (!cells.back().complete) manifest.SetState(planned->cell->id, "running");
  }
  manifest.Write(out);
  RunSequentialGroup(cells, unit.pairs, unit.test, [&](std::size_t m, int64_t stop_before, bool complete_at_stop) {
    const SweepCell& cell = *unit.cells[m]->cell;
    int64_t reported = 0;
    cell::CellResult result = RunCellInto(
        unit.cells[m]->plan, cells[m].dir, options.threads,
        [&progress, &reported](int64_t finished, int64_t) {
          progress.AddEpisodes(finished - reported);
          reported = finished;
        },
        cell.label, cell.seed_group, videos, stop_before, complete_at_stop);
    if (complete_at_stop) {
      manifest.SetState(cell.id, "complete");
      manifest.Write(out);
      progress.CellFinished(cell::CellSummaryLine(result));
    }
    return std::move(result.episodes);
  });
}

// Runs `to_run` into out/cells, `jobs` cells at a time, keeping the manifest's states current.
// Returns the first error of a cell, if any (the other running cells finish first).
std::exception_ptr RunCells(const std::vector<RunUnit>& to_run, int jobs, const fs::path& out,
                            const SweepRunOptions& options, const rollout::EpisodeVideoSettings& videos,
                            SweepManifest& manifest, SweepProgress& progress) {
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr first_error;
  std::mutex error_mutex;
  const auto worker = [&] {
    for (std::size_t i = next++; i < to_run.size() && !failed; i = next++) {
      const SweepCell& cell = *to_run[i].cells.front()->cell;
      try {
        if (!to_run[i].pairs.empty()) {
          RunGroup(to_run[i], out, options, videos, manifest, progress);
          continue;
        }
        manifest.SetState(cell.id, "running");
        manifest.Write(out);
        int64_t reported = 0;
        const cell::CellResult result = RunCellInto(
            to_run[i].cells.front()->plan, out / "cells" / cell.id, options.threads,
            [&progress, &reported](int64_t finished, int64_t) {
              progress.AddEpisodes(finished - reported);
              reported = finished;
            },
            cell.label, cell.seed_group, videos);
        manifest.SetState(cell.id, "complete");
        manifest.Write(out);
        progress.CellFinished(cell::CellSummaryLine(result));
      } catch (...) {
        for (const PlannedCell* planned : to_run[i].cells) {
          if (!ReadCompleteCell(out / "cells" / planned->cell->id, cell::CellSettingsJson(planned->plan),
                                planned->cell->config.episodes))
            manifest.SetState(planned->cell->id, "failed");
        }
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
  const SequentialPlan sequential = PlanSequential(all, spec.sequential);
  RequireShardHoldsUnits(options.shard, sequential);
  // Each cell of the shard planned once, here: bad settings fail before any work, and the cell
  // runs that plan (its files read once).
  std::vector<PlannedCell> mine;
  std::vector<std::size_t> positions;  // of mine's cells in `all`
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (!InShard(sequential.shard_position[i], options.shard)) continue;
    mine.push_back({&all[i], cell::PlanCell(all[i].config)});
    positions.push_back(i);
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

  int cells_done = 0;
  int64_t episodes_done = 0;
  const std::vector<RunUnit> to_run = UnitsToRun(UnitsOf(mine, positions, sequential, spec.sequential.test), out,
                                                 manifest, &cells_done, &episodes_done);
  manifest.Write(out);

  const bool all_per_slot = std::all_of(to_run.begin(), to_run.end(), [](const RunUnit& unit) {
    return std::all_of(unit.cells.begin(), unit.cells.end(),
                       [](const PlannedCell* cell) { return cell::RunsPerSlot(cell->cell->config); });
  });
  const int default_jobs = DefaultConcurrentCells(all_per_slot, options.threads);
  const int jobs = std::max(1, std::min<int>(options.concurrent_cells > 0 ? options.concurrent_cells : default_jobs,
                                             static_cast<int>(to_run.size())));
  // Each running cell's own thread works too: TBB gets the cores the cell threads leave.
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                            static_cast<std::size_t>(std::max(1, options.threads - jobs + 1)));
  SweepProgress progress(static_cast<int>(mine.size()), cells_done, static_cast<int64_t>(mine.size()) * spec.episodes,
                         episodes_done, options.quiet);
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
