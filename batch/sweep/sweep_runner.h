// Runs a sweep's cells (or one shard's share) into DIR/cells/<id>, several cells at once, keeping
// DIR/manifest.json up to date, then writes the results (an unsharded sweep only; shards are
// combined by MergeSweeps). A rerun skips the complete cells and continues the interrupted ones.
#pragma once

#include <optional>
#include <string>

#include "batch/sweep/sweep_spec.h"

namespace tavis::batch::sweep {

struct SweepRunOptions {
  std::string out_dir;
  std::string spec_yaml;  // the spec file's text, kept in the manifest
  std::string config_dir;
  Shard shard;
  int threads = 1;  // cores in use at once
  // Cells run at once (each by its own thread, sharing the cores); 0: DefaultConcurrentCells.
  // The results do not depend on it.
  int concurrent_cells = 0;
  bool quiet = false;
  // Film each cell's first N episodes (cells/<id>/videos) in place of the spec's `videos`; unset:
  // the spec's. Not part of the spec, so a sweep may be resumed with or without it.
  std::optional<int> videos;
};

// Cells run at once by default on `threads` cores: one per 4 threads (at least one) when every
// cell runs per slot (cell::RunsPerSlot: built-in policies), else one per thread.
int DefaultConcurrentCells(bool all_per_slot, int threads);

void RunSweep(const SweepSpec& spec, const SweepRunOptions& options);

}  // namespace tavis::batch::sweep
