#include "engine/ode_runtime.h"

#include <mutex>

#include <ode/ode.h>

namespace tavis::engine {
namespace {

thread_local uint32_t tls_ode_seed = 0;
thread_local uint64_t tls_ode_draws = 0;

}  // namespace

void EnsureOdeReadyOnThisThread() {
  static std::once_flag init_once;
  std::call_once(init_once, [] { dInitODE2(0); });
  thread_local bool allocated = false;
  if (!allocated) {
    dAllocateODEDataForThread(dAllocateMaskAll);
    allocated = true;
  }
}

uint32_t ExchangeOdeRandomSeed(uint32_t seed) {
  const uint32_t previous = tls_ode_seed;
  tls_ode_seed = seed;
  return previous;
}

uint64_t OdeRandomDrawCount() { return tls_ode_draws; }

}  // namespace tavis::engine

// Overrides libode's exported dRandInt (ELF symbol interposition: ODE calls it through the PLT).
// Same linear congruential generator as ODE's dRand, on the calling thread's seed.
extern "C" int dRandInt(int n) {
  using tavis::engine::tls_ode_draws;
  using tavis::engine::tls_ode_seed;
  tls_ode_seed = 1664525u * tls_ode_seed + 1013904223u;
  ++tls_ode_draws;
  return static_cast<int>((static_cast<uint64_t>(tls_ode_seed) * static_cast<uint64_t>(n)) >> 32);
}
