// The Python env's write_results into a folder under the rules every command that writes results
// follows (batch/output/output_folder.h), so that it cannot mix with, or silently replace, what
// `tavis eval` or an earlier write_results wrote: the path must be usable, the folder is locked
// while written (a running `tavis eval` holds it), one that already holds results is refused
// unless overwrite is given, and an overwrite replaces only a cell tavis wrote, building the new
// one beside it and swapping it in. The records are written at once, so there is no resume.
#pragma once

#include <filesystem>

#include "batch/cell/cell_report.h"
#include "batch/cell/evaluation_cell.h"

namespace tavis::batch::gym {

// Who holds the folder's lock while write_results writes it (a refused writer names it).
inline constexpr const char* kWriteResultsCommand = "write_results (Python)";

// Writes `result` into `out` as `tavis eval` writes a cell (episodes.jsonl, summary.json, tavis's
// marker). Throws std::invalid_argument naming `out` and the reason: an unusable path, a folder
// another process is writing, one that holds results (without `overwrite`), or one holding files
// tavis did not write (with it); std::runtime_error when it cannot be written.
void WriteResultsFolder(const cell::CellResult& result, const cell::RunInfo& info, const std::filesystem::path& out,
                        bool overwrite);

}  // namespace tavis::batch::gym
