#include "engine/ode_runtime.h"

#include <cstdarg>
#include <mutex>

#include <ode/ode.h>

namespace tavis::engine {
namespace {

thread_local uint64_t tls_ode_messages = 0;

void CountMessage(int, const char*, va_list) { ++tls_ode_messages; }

}  // namespace

void EnsureOdeReadyOnThisThread() {
  static std::once_flag init_once;
  std::call_once(init_once, [] {
    dInitODE2(0);
    dSetMessageHandler(&CountMessage);
  });
  thread_local bool allocated = false;
  if (!allocated) {
    dAllocateODEDataForThread(dAllocateMaskAll);
    allocated = true;
  }
}

uint64_t OdeMessagesOnThisThread() { return tls_ode_messages; }

}  // namespace tavis::engine
