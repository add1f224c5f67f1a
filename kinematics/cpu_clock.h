// CPU-time clocks for the profiles: the calling thread's (an env's cost measured on it does not
// include the time its thread waited for a core, so costs measured on a loaded machine stay
// meaningful) and the whole process's (every thread).
#pragma once

#include <cstdint>
#include <ctime>

namespace tavis::kinematics {

inline int64_t ThreadCpuNanoseconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<int64_t>(now.tv_sec) * 1000000000 + now.tv_nsec;
}

inline int64_t ProcessCpuNanoseconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<int64_t>(now.tv_sec) * 1000000000 + now.tv_nsec;
}

}  // namespace tavis::kinematics
