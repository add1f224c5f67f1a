// Flush-to-zero / denormals-are-zero for the scope of a render task, as Embree recommends for
// speed; the previous mode is restored so other work on the same TBB thread is unaffected.
#pragma once

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace tavis::render::internal {

class FlushDenormalsScope {
 public:
#if defined(__SSE2__)
  FlushDenormalsScope() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero); }
  ~FlushDenormalsScope() { _mm_setcsr(saved_); }
#else
  FlushDenormalsScope() = default;
#endif
  FlushDenormalsScope(const FlushDenormalsScope&) = delete;
  FlushDenormalsScope& operator=(const FlushDenormalsScope&) = delete;

 private:
#if defined(__SSE2__)
  static constexpr unsigned int kFlushToZero = 0x8000;
  static constexpr unsigned int kDenormalsAreZero = 0x0040;
  unsigned int saved_;
#endif
};

}  // namespace tavis::render::internal
