#include "batch/dataset/video/deterministic_heap.h"

#include <mutex>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace tavis::batch::dataset::video::internal {

void MakeHeapContentDeterministic() {
#if defined(__GLIBC__)
  static std::once_flag once;
  // Any byte but 0 works; 0xa5 is glibc's documented example (free fills with it, malloc with
  // its complement).
  std::call_once(once, [] { mallopt(M_PERTURB, 0xa5); });
#endif
}

}  // namespace tavis::batch::dataset::video::internal
