// How many threads a parallel loop of the batch runtime can run on.
#pragma once

#include <algorithm>
#include <cstddef>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

namespace tavis::batch {

// The current arena's concurrency cut to the process-wide limit that `--threads` sets
// (tbb::global_control). this_task_arena::max_concurrency() alone is the arena's size, the
// machine's cores in the default arena, which that limit does not change: a cell run with
// `--threads 2` on 16 cores would be counted as 16 threads.
inline int UsableThreads() {
  const std::size_t limit = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  const std::size_t arena = static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  return static_cast<int>(std::max<std::size_t>(1, std::min(arena, limit)));
}

}  // namespace tavis::batch
