// Process- and thread-level set-up that ODE needs before a world can be stepped on a thread.
#pragma once

#include <cstdint>

namespace tavis::engine {

// Initialises ODE once per process and allocates ODE's per-thread data on the calling thread
// the first time it is called there. Cheap after the first call; call it before any ODE use.
void EnsureOdeReadyOnThisThread();

// ODE's QuickStep shuffles constraints with a process-global random seed, which makes results
// depend on how threads interleave. The engine replaces ODE's dRandInt with one that draws from
// a thread-local seed; each world installs its own seed around its step.
uint32_t ExchangeOdeRandomSeed(uint32_t seed);
uint64_t OdeRandomDrawCount();  // draws made on this thread through the replacement

}  // namespace tavis::engine
