// Test support: a dataset written from the known episodes (known_episodes.h), read back by the
// independent readers, holds exactly what was written.
#pragma once

#include "tests/batch/dataset/known_episodes.h"
#include "tests/batch/dataset/lerobot_dataset_checks.h"
#include "tests/batch/dataset/lerobot_dataset_view.h"

namespace tavis::batch::dataset::testing {

// Episode order, lengths, tasks, prompts and every float of every vector column (bit-exact).
void ExpectRowsHoldKnownValues(const DatasetView& view, const KnownDataset& known);

// Each looked-up frame is the one encoded (PSNR >= 30 dB) and not the frame next to it
// (PSNR < 25 dB), so the check discriminates.
void ExpectLookedUpFramesAreKnown(const LookedUpFrames& frames, const KnownDataset& known);

}  // namespace tavis::batch::dataset::testing
