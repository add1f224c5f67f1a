#include "batch/sweep/sweep_runner.h"

#include <gtest/gtest.h>

namespace tavis::batch::sweep {
namespace {

// Cells of built-in policies (per slot) run one per 4 threads by default, at least one; cells
// that include a served policy (lock-step) one per thread.
TEST(SweepRunner, DefaultConcurrentCellsSharesManyCoresBetweenPerSlotCells) {
  EXPECT_EQ(DefaultConcurrentCells(true, 1), 1);
  EXPECT_EQ(DefaultConcurrentCells(true, 2), 1) << "two cores: one cell at a time";
  EXPECT_EQ(DefaultConcurrentCells(true, 7), 1);
  EXPECT_EQ(DefaultConcurrentCells(true, 8), 2);
  EXPECT_EQ(DefaultConcurrentCells(true, 16), 4) << "16 cores: four at once";
  EXPECT_EQ(DefaultConcurrentCells(false, 2), 2);
  EXPECT_EQ(DefaultConcurrentCells(false, 16), 16);
  EXPECT_EQ(DefaultConcurrentCells(false, 0), 1);
}

}  // namespace
}  // namespace tavis::batch::sweep
