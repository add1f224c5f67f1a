// Process- and thread-level set-up that ODE needs before a world can be stepped on a thread.
#pragma once

#include <cstdint>

namespace tavis::engine {

// Initialises ODE once per process and allocates ODE's per-thread data on the calling thread
// the first time it is called there (cheap afterwards). Called by every PhysicsWorld entry
// point, so TBB workers need no scheduler observer.
void EnsureOdeReadyOnThisThread();

// ODE's solver messages (e.g. "LCP internal error" on a degenerate contact set) are not
// printed but counted, per thread; worlds read the count around their step.
uint64_t OdeMessagesOnThisThread();

}  // namespace tavis::engine
