// "Run a cell into a folder", once for `tavis eval` and `tavis sweep`: the folder is locked, its
// records are streamed as episodes end (CellRecordStream: an interrupted cell keeps them and a
// resumed one continues after them), the cell runs, and summary.json, covering the whole cell
// (the resumed records first), is written last. How a caller chooses the folder's state (eval's
// --resume and --overwrite flags, the sweep's look at the files) stays with the caller; what it
// films or records beside the records is plugged in (CellAttachments).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "batch/cell/cell_plan.h"
#include "batch/cell/episode_recorder.h"
#include "batch/cell/evaluation_cell.h"
#include "batch/episode_driver.h"

namespace tavis::batch::cell {

struct CellFolderOptions {
  std::filesystem::path out;  // the cell's folder
  // Continue the interrupted cell in `out` (the same settings, no summary.json yet).
  bool resume = false;
  // Replace the cell in `out` (only one tavis wrote as a cell): the new one is built beside it and
  // swapped in once it has recorded an episode, so a run that fails before leaves the old one.
  bool overwrite = false;
  std::string command = "eval";  // who holds the folder's lock while the cell runs
  // A folder this run created is removed if the cell fails before its first record.
  bool remove_new_folder_on_failure = true;
  int threads = 0;    // recorded in summary.json
  std::string label;  // the policy label summary.json's provenance names (empty: the policy's name)
  ProgressCallback progress;
  // Run only the episodes before this one (a sweep's sequential test runs a cell in blocks);
  // negative: to the cell's end. A cell stopped short of its end pauses there, as an interrupted
  // one (no summary.json), unless `complete_at_stop` makes it complete with the episodes it has.
  int64_t stop_before = -1;
  bool complete_at_stop = false;
};

// What a caller plugs in beside the cell's records (episode videos, a rollout dataset).
struct CellAttachments {
  CellSinks sinks;  // beside the cell's recorder
  // Each record, just before it is written: what is finished with it (an episode's video) is on
  // disk before the record says the episode is done, so a kill between them costs a rerun, not a
  // video.
  std::function<void(const EpisodeRecord&)> on_record;
  // Once summary.json is written, while the folder is still locked (what is written beside it).
  std::function<void(const CellResult&)> finish;
  // For a resumed cell: how many of its records stand, those before the first whose attachment
  // is missing (a filmed episode without its finished video); the rest run again, giving the same
  // records. Absent: all stand.
  std::function<std::size_t(const std::vector<EpisodeRecord>& resumed)> records_kept;
};
// Makes the attachments once the folder holds the cell's settings and the plan its first episode
// still to run; `folder` says where the cell is at each moment (an --overwrite's new cell lies
// beside the old one until it is swapped in).
using AttachToCell =
    std::function<CellAttachments(const CellPlan& plan, const std::function<std::filesystem::path()>& folder)>;

// Runs the plan into options.out and returns the whole cell's result (the resumed records first).
// Throws std::invalid_argument naming the folder and what is wrong with it (no cell to --resume, a
// folder tavis did not write to --overwrite, results without either), and whatever the cell
// throws (a cell that recorded episodes keeps them for a resume).
CellResult RunCellInFolder(CellPlan plan, const CellFolderOptions& options, const AttachToCell& attach = nullptr);

}  // namespace tavis::batch::cell
