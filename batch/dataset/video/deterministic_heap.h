// libx264 reads heap memory it has not written. Encoding on several threads, whose allocations
// interleave differently from run to run, then gave the same frames different bytes now and then
// (a few GOPs of one episode in about one run in twelve on a loaded two-core machine), though its
// input, every RGB and YUV frame, was identical. With one thread, or with glibc's MALLOC_PERTURB_,
// it never did (0 in 76 runs). So before the first encoder opens, the heap is made to hand out
// memory of fixed content: every malloc'd block starts filled with one byte (glibc's M_PERTURB),
// and memory from the kernel starts zeroed anyway.
#pragma once

namespace tavis::batch::dataset::video::internal {

// Idempotent and thread-safe; a no-op outside glibc.
void MakeHeapContentDeterministic();

}  // namespace tavis::batch::dataset::video::internal
